//! `harness linearize` on the paper's hover at 150 m: the attitude margins of the linearized
//! system against the margins the paper's design values give the rigid body analytically
//! (written out here, independent of the command's own design loop), with the Jacobians from
//! the FMUs and from finite differences; a vehicle of another inertia; bad input.
use crate::common;

/// Inside the paper's hover at 150 m (142 s to 172 s, the sequencer's phase 3), between two
/// guidance cycles (0.1 s), so the guidance command is held over the sample.
const HOVER_AT: &str = "160.05";
const STEP_S: f64 = 0.01;

/// The analytic margins of one axis: `L(s) = (Kd s + Kp) / (I s^2)` held over the step `h`
/// and sampled, `L(z) = Kp h^2 (z + 1) / (2 I (z - 1)^2) + Kd h / (I (z - 1))`, with
/// `Kp = I_g w_c^2`, `Kd = 2 zeta w_c I_g` for the gains' inertia `I_g` (paper Table I:
/// 0.5 Hz, damping 0.8). Returns (phase margin deg, crossover rad/s, gain margin dB).
fn analytic(inertia_gains: f64, inertia_plant: f64) -> (f64, f64, f64) {
    let wc = std::f64::consts::TAU * 0.5;
    let (kp, kd) = (inertia_gains * wc * wc, 2.0 * 0.8 * wc * inertia_gains);
    let h = STEP_S;
    // complex numbers as (re, im)
    let mul = |a: (f64, f64), b: (f64, f64)| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
    let div = |a: (f64, f64), b: (f64, f64)| {
        let n = b.0 * b.0 + b.1 * b.1;
        ((a.0 * b.0 + a.1 * b.1) / n, (a.1 * b.0 - a.0 * b.1) / n)
    };
    let loop_at = |w: f64| {
        let z = ((w * h).cos(), (w * h).sin());
        let zm1 = (z.0 - 1.0, z.1);
        let angle = div(
            (
                (z.0 + 1.0) * kp * h * h / (2.0 * inertia_plant),
                z.1 * kp * h * h / (2.0 * inertia_plant),
            ),
            mul(zm1, zm1),
        );
        let rate = div((kd * h / inertia_plant, 0.0), zm1);
        (angle.0 + rate.0, angle.1 + rate.1)
    };
    let magnitude = |w: f64| {
        let l = loop_at(w);
        (l.0 * l.0 + l.1 * l.1).sqrt()
    };
    let (mut lo, mut hi) = (0.1, 100.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if magnitude(mid) > 1.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let l = loop_at(lo);
    let phase_margin = 180.0 + l.1.atan2(l.0).to_degrees();
    // At z = -1 only the rate term is left: L = -Kd h / (2 I).
    let gain_margin = 20.0 * (2.0 * inertia_plant / (kd * h)).log10();
    (phase_margin, lo, gain_margin)
}

fn linearize(extra: &[&str]) -> serde_json::Value {
    let out = tempfile::tempdir().unwrap();
    let file = out.path().join("linear.json");
    let mut args = vec![
        "linearize",
        "paper",
        "--at",
        HOVER_AT,
        "-o",
        file.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let output = common::harness(&args);
    let text = String::from_utf8_lossy(&output.stdout).into_owned()
        + &String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{text}");
    assert!(text.contains("phase margin"), "{text}");
    serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap()
}

fn number(value: &serde_json::Value, key: &str) -> f64 {
    value[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {value}"))
}

/// Each axis's (phase margin, crossover, gain margin).
fn axes(document: &serde_json::Value) -> Vec<(f64, f64, f64)> {
    document["attitude_axes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|axis| {
            let m = &axis["margins"];
            (
                number(m, "phase_margin_deg"),
                number(m, "gain_crossover_radps"),
                number(m, "gain_margin_db"),
            )
        })
        .collect()
}

#[test]
fn the_paper_hover_has_the_margins_of_its_design_from_the_fmus_and_from_differences() {
    // GIVEN the paper scenario at its hover at 150 m, the design inertia (400, 300, 450)
    let from_fmus = linearize(&[]);
    let from_differences = linearize(&["--jacobian", "fd"]);
    let inertia = [400.0, 300.0, 450.0];
    for (document, what) in [(&from_fmus, "fmu"), (&from_differences, "fd")] {
        assert_eq!(number(document, "time_s"), 160.05);
        let axes = axes(document);
        assert_eq!(axes.len(), 3, "{what}: three attitude axes");
        for (i, (pm, wc, gm)) in axes.into_iter().enumerate() {
            // THEN every axis has the margins of L(s) = (Kd s + Kp) / (I s^2), sampled and held
            let (pm_analytic, wc_analytic, gm_analytic) = analytic(inertia[i], inertia[i]);
            assert!(
                (pm - pm_analytic).abs() < 0.05,
                "{what} axis {i}: PM {pm} vs {pm_analytic}"
            );
            assert!(
                (wc - wc_analytic).abs() < 2e-3 * wc_analytic,
                "{what} axis {i}: {wc} vs {wc_analytic}"
            );
            assert!(
                (gm - gm_analytic).abs() < 0.05,
                "{what} axis {i}: GM {gm} vs {gm_analytic}"
            );
        }
        // AND the closed loop is stable but for the held modes (position, mass, the
        // quaternion's norm): no eigenvalue outside the unit circle
        for e in document["closed_loop"]["eigenvalues"].as_array().unwrap() {
            let z = number(e, "z_re").hypot(number(e, "z_im"));
            assert!(z < 1.0 + 1e-9, "{what}: |z| = {z}");
        }
    }
    // AND the sanity of the numbers: 0.5 Hz, zeta 0.8 is 68.3 deg at 5.35 rad/s, 32.0 dB
    let (pm, wc, gm) = analytic(300.0, 300.0);
    assert!((pm - 68.33).abs() < 0.01 && (wc - 5.354).abs() < 1e-3 && (gm - 32.0).abs() < 0.01);
    // AND the two linearizations agree with each other closer than with the analytic loop
    for (a, b) in axes(&from_fmus).into_iter().zip(axes(&from_differences)) {
        assert!((a.0 - b.0).abs() < 1e-3, "{a:?} vs {b:?}");
    }
    // AND each instance says where its Jacobians came from: LanderGnc and LanderPlant from
    // their directional derivatives, every one from differences when asked
    for (document, forced) in [(&from_fmus, false), (&from_differences, true)] {
        for instance in document["instances"].as_array().unwrap() {
            let source = &instance["source"];
            if forced {
                assert_eq!(source["kind"], "finite-differences");
                assert_eq!(source["reason"], "differences asked for");
            } else {
                assert_eq!(source["kind"], "directional-derivatives", "{instance}");
            }
        }
    }
    // AND the FMUs' Jacobians are the differences' to the differences' own error
    let entries = |instance: &serde_json::Value, matrix: &str| -> Vec<f64> {
        instance[matrix]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|row| row.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()))
            .collect()
    };
    for (exact, differenced) in from_fmus["instances"]
        .as_array()
        .unwrap()
        .iter()
        .zip(from_differences["instances"].as_array().unwrap())
    {
        for matrix in ["A", "B", "C", "D"] {
            for (a, b) in entries(exact, matrix)
                .into_iter()
                .zip(entries(differenced, matrix))
            {
                assert!(
                    (a - b).abs() < 1e-6 * (1.0 + b.abs()),
                    "{} {matrix}: {a} vs {b}",
                    exact["instance"]
                );
            }
        }
    }
}

#[test]
fn at_a_guidance_cycle_the_controller_is_differenced_naming_its_refusal() {
    // GIVEN the hover at a sample that opens a guidance cycle (every 0.1 s)
    let out = tempfile::tempdir().unwrap();
    let file = out.path().join("linear.json");
    let output = common::harness(&[
        "linearize",
        "paper",
        "--at",
        "160",
        "-o",
        file.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let document: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    // THEN LanderGnc, which gives no partials of its guidance solve, is differenced, the
    // refusal naming the input; the plant keeps its own Jacobians
    let gnc = &document["instances"][0];
    assert_eq!(gnc["instance"], "gnc");
    assert_eq!(gnc["source"]["kind"], "finite-differences");
    let reason = gnc["source"]["reason"].as_str().unwrap();
    assert!(
        reason.contains("refused")
            && reason.contains("opens a guidance cycle")
            && reason.contains("r_nue[1]"),
        "{reason}"
    );
    assert_eq!(
        document["instances"][1]["source"]["kind"],
        "directional-derivatives"
    );
}

#[test]
fn a_vehicle_of_its_own_inertia_gets_the_margins_of_its_own_loop() {
    // GIVEN the paper's controller (gains for 300 kg m^2 about the thrust axis) on a plant
    // with twice that inertia
    let document = linearize(&["--set", "plant.inertia_body[2]=600"]);
    let (pm, wc, gm) = axes(&document)[1];
    // THEN the roll axis has the margins of the gains for 300 on a body of 600: half the
    // loop gain, a lower crossover, 6 dB more gain margin
    let (pm_analytic, wc_analytic, gm_analytic) = analytic(300.0, 600.0);
    assert!((pm - pm_analytic).abs() < 0.05, "{pm} vs {pm_analytic}");
    assert!(
        (wc - wc_analytic).abs() < 2e-3 * wc_analytic,
        "{wc} vs {wc_analytic}"
    );
    assert!((gm - gm_analytic).abs() < 0.05, "{gm} vs {gm_analytic}");
    let (_, wc_design, gm_design) = analytic(300.0, 300.0);
    assert!(wc < 0.8 * wc_design && (gm - gm_design - 6.02).abs() < 0.05);
}

#[test]
fn a_time_beyond_the_run_or_an_unknown_scenario_is_one_clear_error() {
    for (args, expected) in [
        (
            vec!["linearize", "paper", "--at", "500"],
            "--at 500: outside the run of scenario 'paper' (0 s to 172 s)",
        ),
        (
            vec!["linearize", "no-such-scenario", "--at", "1"],
            "no-such-scenario",
        ),
    ] {
        let output = common::harness(&args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(
            !stderr.contains("panicked") && !stderr.contains("backtrace"),
            "{stderr}"
        );
        assert!(output.stdout.is_empty());
    }
}

/// `fault-engine` (engine health 0.93 from an event at 60 s) linearized at `at`: the JSON,
/// and the summary printed.
fn fault_engine_at(at: &str) -> (serde_json::Value, String) {
    let out = tempfile::tempdir().unwrap();
    let file = out.path().join("linear.json");
    let output = common::harness(&[
        "linearize",
        "fault-engine",
        "--at",
        at,
        "-o",
        file.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let document = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    (document, stdout)
}

/// The plant's partial of its vertical acceleration with respect to the thrust command:
/// `health u_up / m`.
fn thrust_partial(document: &serde_json::Value) -> f64 {
    let plant = document["instances"]
        .as_array()
        .unwrap()
        .iter()
        .find(|i| i["instance"] == "plant")
        .unwrap();
    let position = |list: &str, name: &str| {
        plant[list]
            .as_array()
            .unwrap()
            .iter()
            .position(|v| v == name)
            .unwrap_or_else(|| panic!("{name} not among {}", plant[list]))
    };
    let (row, column) = (
        // Flat model: r_nue, then v_nue; its element 5 is v_nue[2], the up velocity.
        position("states", "plant.translation_state[5]"),
        position("inputs", "plant.thrust_cmd"),
    );
    plant["B"][row][column].as_f64().unwrap()
}

#[test]
fn an_engine_fault_due_at_the_point_is_in_the_linear_model_and_one_due_after_it_is_not() {
    // GIVEN fault-engine, whose engines lose 7 % of their thrust by an event at 60 s
    // WHEN linearized at 60 s and a step before
    let (at_fault, summary) = fault_engine_at("60");
    let (before, summary_before) = fault_engine_at("59.99");
    // THEN at 60 s the plant's thrust partial is 0.93 of the one a step before (mass and
    // attitude move by less than 1e-5 over the step): the fault is in the model of the step
    // from its point, and not in the model before it
    let ratio = thrust_partial(&at_fault) / thrust_partial(&before);
    assert!((ratio - 0.93).abs() < 1e-4, "{ratio}");
    // AND each says so, in the JSON and in the summary
    let event = |document: &serde_json::Value| document["events"][0].clone();
    assert_eq!(event(&at_fault)["name"], "engine-degraded");
    assert_eq!(event(&at_fault)["applied_at_s"], 60.0);
    assert!(event(&before)["applied_at_s"].is_null());
    assert!(
        summary.contains(
            "event 'engine-degraded' (plant.engine_health = 0.93) due at 60 s: applied at 60 s"
        ),
        "{summary}"
    );
    assert!(
        summary_before.contains("due after this point, not applied"),
        "{summary_before}"
    );
}
