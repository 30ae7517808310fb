//! Every optional effect at once through the Co-Simulation step, as a full-fidelity scenario
//! sets them: a descent at constant thrust onto a 5 deg slope, engines cut 0.3 m above it.
use fmi_model::{Log, Model, StepEnd};
use fmu_plant::LanderPlant;

#[test]
fn a_descent_with_every_effect_on_lands_cuts_the_engines_and_settles() {
    let mut m = LanderPlant::default();
    // Every parameter set through the declarations, by its declared name.
    let set = |m: &mut LanderPlant, name: &str, values: &[f64]| {
        let d = LanderPlant::declarations()
            .iter()
            .find(|d| d.name == name)
            .unwrap_or_else(|| panic!("{name}"));
        let fmi_model::Kind::Real { set: Some(set), .. } = d.kind else {
            panic!("{name} is not a settable Real")
        };
        for (i, v) in values.iter().enumerate() {
            set(m, i, *v);
        }
    };
    let set_bool = |m: &mut LanderPlant, name: &str| {
        let d = LanderPlant::declarations()
            .iter()
            .find(|d| d.name == name)
            .unwrap();
        let fmi_model::Kind::Boolean { set: Some(set), .. } = d.kind else {
            panic!("{name}")
        };
        set(m, true);
    };
    set_bool(&mut m, "gear_enabled");
    set_bool(&mut m, "slosh_enabled");
    set(&mut m, "r0_nue", &[0.0, 12.0, 0.0]);
    set(&mut m, "v0_nue", &[0.3, -1.5, 0.0]);
    set(&mut m, "terrain_slope", &[5f64.to_radians()]);
    set(&mut m, "engine_cutoff_height", &[0.3]);
    set(&mut m, "throttle_rate_limit", &[2000.0]);
    set(&mut m, "engine_time_constant", &[0.1]);
    set(&mut m, "rcs_valve_delay", &[0.025]);
    set(&mut m, "rcs_isp", &[220.0]);
    set(&mut m, "slosh_delta0", &[0.005, 0.0, 0.0, 0.002]);
    set(&mut m, "inertia_dry_body", &[300.0, 200.0, 350.0]);
    set(&mut m, "com_offset_dry_body", &[0.01, 0.0, 0.0]);
    let d = LanderPlant::declarations()
        .iter()
        .find(|d| d.name == "engine_cutoff_mode")
        .unwrap();
    let fmi_model::Kind::Integer {
        set: Some(set_int), ..
    } = d.kind
    else {
        panic!()
    };
    set_int(&mut m, 2);
    let mut log = Log::default();
    m.exit_initialization(0.0, &mut log).unwrap();
    let get = |m: &LanderPlant, name: &str, i: usize| {
        let d = LanderPlant::declarations()
            .iter()
            .find(|d| d.name == name)
            .unwrap();
        let fmi_model::Kind::Real { get, .. } = d.kind else {
            panic!()
        };
        get(m, i)
    };
    let get_bool = |m: &LanderPlant, name: &str| {
        let d = LanderPlant::declarations()
            .iter()
            .find(|d| d.name == name)
            .unwrap();
        let fmi_model::Kind::Boolean { get, .. } = d.kind else {
            panic!()
        };
        get(m)
    };
    // A descent at just under hover thrust, with a small RCS command.
    let thrust = 900.0 * 1.62 * 0.97;
    for k in 0..2000 {
        set(&mut m, "thrust_cmd", &[thrust]);
        set(&mut m, "torque_cmd_body", &[0.0, 2.0, 0.0]);
        let end = m.do_step(f64::from(k) * 0.01, 0.01, &mut log).unwrap();
        assert_eq!(end, StepEnd::Complete, "step {k}");
        m.calculate_values(&mut log);
        for name in [
            "r_nue",
            "v_nue",
            "specific_force_body",
            "slosh_displacement",
        ] {
            assert!(get(&m, name, 0).is_finite(), "{name} at step {k}");
        }
    }
    println!(
        "touchdown at {:.4} s, v = [{:.3}, {:.3}, {:.3}] m/s, strokes {:?} m, propellant {:.4} kg",
        get(&m, "touchdown_time", 0),
        get(&m, "touchdown_v_nue", 0),
        get(&m, "touchdown_v_nue", 1),
        get(&m, "touchdown_v_nue", 2),
        (0..4).map(|i| get(&m, "leg_stroke", i)).collect::<Vec<_>>(),
        get(&m, "propellant_used", 0)
    );
    assert!(get_bool(&m, "touchdown"));
    assert!(
        get_bool(&m, "settled"),
        "{:?}",
        (0..4).map(|i| get(&m, "leg_stroke", i)).collect::<Vec<_>>()
    );
    assert!(!get_bool(&m, "tipped_over"));
    assert_eq!(get(&m, "thrust_actual", 0), 0.0, "engines cut");
    assert!(get(&m, "propellant_used", 0) > 0.0);
}
