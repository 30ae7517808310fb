use super::*;

/// A one-row trajectory holding the touchdown outputs, as the plant reports them.
fn touchdown_row(v_nue: [f64; 3], tilt_rad: f64, omega: [f64; 3], touched: bool) -> Trajectory {
    let names = [
        "plant.touchdown",
        "plant.touchdown_time",
        "plant.touchdown_v_nue[1]",
        "plant.touchdown_v_nue[2]",
        "plant.touchdown_v_nue[3]",
        "plant.touchdown_omega_body[1]",
        "plant.touchdown_omega_body[2]",
        "plant.touchdown_omega_body[3]",
        "plant.touchdown_tilt",
        "plant.propellant_exhausted",
        "plant.r_nue[1]",
        "plant.r_nue[3]",
    ];
    Trajectory {
        names: names.iter().map(|s| s.to_string()).collect(),
        times: vec![141.73],
        values: vec![
            f64::from(u8::from(touched)),
            141.73,
            v_nue[0],
            v_nue[1],
            v_nue[2],
            omega[0],
            omega[1],
            omega[2],
            tilt_rad,
            0.0,
            3.0,
            4.0,
        ],
    }
}

fn terminated() -> RunEnd {
    RunEnd::Terminated {
        instance: "plant".into(),
        time: 141.73,
    }
}

#[test]
fn a_soft_touchdown_is_landed_and_passes_a_landing_scenario_only() {
    let t = touchdown_row([0.3, -1.0, 0.0], 2f64.to_radians(), [0.0; 3], true);
    let verdict = judge(&t, &terminated(), &Envelope::default());
    let Verdict::Landed(td) = &verdict else {
        panic!("{verdict:?}")
    };
    assert_eq!(td.vertical_speed_mps, 1.0);
    assert_eq!(td.horizontal_position_m, 5.0);
    assert_eq!(verdict.exit_code(Expect::Landed), EXIT_OK);
    assert_eq!(verdict.exit_code(Expect::Completed), EXIT_FAILED_VERDICT);
    assert!(verdict
        .describe(Expect::Completed)
        .contains("expects: completed"));
}

#[test]
fn a_hard_landing_names_each_broken_limit_and_by_how_much() {
    // the paper scenario at m0 = 1000 kg: 4.9 m/s down, 56 deg of tilt
    let t = touchdown_row([0.1, -4.9, 0.0], 56f64.to_radians(), [0.0, 0.0, 0.1], true);
    let verdict = judge(&t, &terminated(), &Envelope::default());
    let Verdict::HardLanding { broken, .. } = &verdict else {
        panic!("{verdict:?}")
    };
    let names: Vec<_> = broken.iter().map(|b| b.quantity).collect();
    assert_eq!(names, ["vertical speed", "tilt", "body rate"]);
    let text = verdict.describe(Expect::Landed);
    assert!(
        text.contains("vertical speed 4.90 m/s > 2.00 m/s (by 2.90 m/s)"),
        "{text}"
    );
    assert!(
        text.contains("tilt 56.00 deg > 12.00 deg (by 44.00 deg)"),
        "{text}"
    );
    assert_eq!(verdict.exit_code(Expect::Landed), EXIT_FAILED_VERDICT);
}

#[test]
fn limits_are_inclusive_and_unknown_values_fail() {
    let e = Envelope::default();
    let at_limit = touchdown_row([0.5, -2.0, 0.0], 12f64.to_radians(), [0.0; 3], true);
    let verdict = judge(&at_limit, &terminated(), &e);
    // 12 deg through radians and back may round a hair above 12
    assert!(
        matches!(&verdict, Verdict::Landed(_))
            || matches!(&verdict, Verdict::HardLanding { broken, .. }
                if broken.len() == 1 && broken[0].value - 12.0 < 1e-12),
        "{verdict:?}"
    );
    let nan = touchdown_row([0.0, f64::NAN, 0.0], 0.0, [0.0; 3], true);
    assert!(matches!(
        judge(&nan, &terminated(), &e),
        Verdict::HardLanding { .. }
    ));
}

#[test]
fn a_run_to_the_stop_time_completes_and_a_stop_without_touchdown_fails() {
    let hover = touchdown_row([0.0; 3], 0.0, [0.0; 3], false);
    let verdict = judge(&hover, &RunEnd::Completed, &Envelope::default());
    assert_eq!(
        verdict,
        Verdict::Completed {
            end_time_s: 141.73,
            touchdown_recorded: true
        }
    );
    assert_eq!(verdict.exit_code(Expect::Completed), EXIT_OK);
    assert_eq!(verdict.exit_code(Expect::Landed), EXIT_FAILED_VERDICT);
    let stopped = judge(&hover, &terminated(), &Envelope::default());
    assert_eq!(stopped.word(), "stopped");
    assert_eq!(stopped.exit_code(Expect::Completed), EXIT_FAILED_VERDICT);
    assert_eq!(
        Verdict::Error("x".into()).exit_code(Expect::Completed),
        EXIT_ERROR
    );
}

#[test]
fn a_model_that_is_not_a_lander_is_judged_only_by_how_its_run_ended() {
    // GIVEN the trajectory of an oscillator: no plant columns at all
    let run = Trajectory {
        names: vec!["osc.x".into(), "osc.v".into()],
        times: vec![10.0],
        values: vec![0.5, -0.1],
    };
    // WHEN it reaches the stop time THEN it completed, with no word about the ground
    let completed = judge(&run, &RunEnd::Completed, &Envelope::default());
    assert_eq!(completed.exit_code(Expect::Completed), EXIT_OK);
    let text = completed.describe(Expect::Completed);
    assert!(!text.contains("ground"), "{text}");
    // WHEN it ends the run itself THEN it stopped, which a scenario may expect
    let end = RunEnd::Terminated {
        instance: "osc".into(),
        time: 4.0,
    };
    let stopped = judge(&run, &end, &Envelope::default());
    assert_eq!(stopped.exit_code(Expect::Stopped), EXIT_OK);
    assert_eq!(stopped.exit_code(Expect::Completed), EXIT_FAILED_VERDICT);
    let text = stopped.describe(Expect::Stopped);
    assert!(
        text.contains("the FMU ended the run") && !text.contains("touchdown"),
        "{text}"
    );
}

#[test]
fn a_lander_that_tips_over_after_a_soft_touchdown_fails_saying_so() {
    // GIVEN a touchdown inside the envelope, then the plant's tip-over flag
    let mut run = touchdown_row([0.1, -1.0, 0.0], 0.02, [0.0; 3], true);
    let soft = judge(&run, &terminated(), &Envelope::default());
    assert!(matches!(soft, Verdict::Landed(_)), "{soft:?}");
    run.names.push("plant.tipped_over".into());
    run.values.push(1.0);
    // WHEN it is judged
    let verdict = judge(&run, &terminated(), &Envelope::default());
    // THEN it is a hard landing whose broken limit is the tip-over, stated as a fact
    let Verdict::HardLanding { broken, .. } = &verdict else {
        panic!("{verdict:?}")
    };
    assert_eq!(broken.len(), 1);
    assert_eq!(broken[0].to_string(), "tipped over after touchdown");
}
