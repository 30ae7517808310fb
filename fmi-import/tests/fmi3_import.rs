//! FMI 3.0 Co-Simulation FMUs (`cargo xtask fmus` writes them to target/fmu/fmi3/) through
//! the importer: Step Mode and Event Mode around a get after a set, and every exchanged type
//! through the FMI 3.0 Oscillator as through its FMI 2.0 twin.
use fmi_import::{CallError, Fmu, InstanceOptions, StepStatus, VariableKind};
use std::path::PathBuf;

/// target/fmu (checked to hold the FMI 2.0 FMUs) with every FMI 3.0 FMU the crates'
/// metadata ships under fmi3/.
fn fmu_dir() -> PathBuf {
    let dir = crate::common::fmu_dir();
    let fmus = fmu_metadata::fmus_around(env!("CARGO_MANIFEST_DIR")).unwrap();
    let shipped = fmus.iter().filter(|f| f.ships(fmu_metadata::Fmi::V3));
    for fmu in shipped.map(|f| &f.model_identifier) {
        let path = dir.join("fmi3").join(format!("{fmu}.fmu"));
        assert!(
            path.is_file(),
            "{} is missing: run `cargo xtask fmus` first",
            path.display()
        );
    }
    dir
}

#[test]
fn step_mode_refuses_a_get_after_a_set_and_event_mode_allows_it() {
    let fmu = Fmu::load(fmu_dir().join("fmi3/LanderGnc.fmu")).unwrap();
    assert!(fmu.supports_same_instant_feedthrough(), "hasEventMode");
    let up = fmu.value_reference("r_nue[2]", VariableKind::Real).unwrap();
    let thrust = fmu
        .value_reference("thrust_cmd", VariableKind::Real)
        .unwrap();
    for same_instant in [false, true] {
        let options = InstanceOptions {
            same_instant_feedthrough: same_instant,
            ..Default::default()
        };
        let mut gnc = fmu.instantiate_with("gnc", options).unwrap();
        assert_eq!(gnc.can_get_after_set(), same_instant);
        gnc.setup_experiment(None, 0.0, Some(10.0)).unwrap();
        gnc.enter_initialization_mode().unwrap();
        gnc.exit_initialization_mode().unwrap();
        let mut value = [f64::NAN];
        gnc.get_real(&[thrust], &mut value).unwrap();
        let hover = value[0];
        gnc.set_real(&[up], &[790.0]).unwrap();
        let after_set = gnc.get_real(&[thrust], &mut value);
        if same_instant {
            // Event Mode: the command answers the position just set (10 m low: more thrust).
            after_set.unwrap();
            assert!(value[0] > hover, "{} > {hover}", value[0]);
        } else {
            let Err(CallError::InvalidArgument {
                function, reason, ..
            }) = after_set
            else {
                panic!("a get after a set in Step Mode was not refused: {after_set:?}");
            };
            assert_eq!(function, "fmi3GetFloat64");
            assert!(reason.contains("Step Mode"), "{reason}");
        }
        assert!(matches!(
            gnc.do_step(0.0, 0.01).unwrap(),
            StepStatus::Complete(_)
        ));
        // After the step a get is allowed in either mode.
        gnc.get_real(&[thrust], &mut value).unwrap();
        gnc.terminate().unwrap();
    }
}

#[test]
fn every_exchanged_type_round_trips_through_the_fmi3_oscillator_as_through_fmi2() {
    // Int32 and Enumeration (Int64 in FMI 3.0) in one integer call, Boolean, String, Float64.
    let dir = fmu_dir();
    let mut seen = Vec::new();
    for path in [dir.join("Oscillator.fmu"), dir.join("fmi3/Oscillator.fmu")] {
        let fmu = Fmu::load(&path).unwrap();
        let vr = |name: &str, kind| fmu.value_reference(name, kind).unwrap();
        let ints = [
            vr("substeps", VariableKind::Integer),
            vr("crossing_direction", VariableKind::Integer),
        ];
        let mut osc = fmu.instantiate("osc", false).unwrap();
        osc.set_integer(&ints, &[4, 3]).unwrap();
        osc.set_boolean_by_name("stop_at_threshold", true).unwrap();
        osc.set_string_by_name("label", "round trip").unwrap();
        osc.set_real_by_name("threshold", -2.0).unwrap();
        osc.setup_experiment(None, 0.0, Some(1.0)).unwrap();
        osc.enter_initialization_mode().unwrap();
        let mut values = [0; 2];
        osc.get_integer(&ints, &mut values).unwrap();
        let label = osc.get_string_by_name("label").unwrap();
        let stop = osc.get_boolean_by_name("stop_at_threshold").unwrap();
        osc.exit_initialization_mode().unwrap();
        for k in 0..10 {
            assert!(matches!(
                osc.do_step(f64::from(k) * 0.1, 0.1).unwrap(),
                StepStatus::Complete(_)
            ));
        }
        let x = osc.get_real_by_name("x").unwrap();
        let steps = osc.get_integer_by_name("step_count").unwrap();
        osc.terminate().unwrap();
        seen.push((values, label, stop, x.to_bits(), steps));
    }
    assert_eq!(seen[0].0, [4, 3]);
    assert_eq!(seen[0].1, "round trip");
    assert_eq!(seen[0].4, 10);
    assert_eq!(seen[1], seen[0]);
}
