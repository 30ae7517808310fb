//! The landing gear through the FMI 3.0 C functions: its Boolean parameter, array outputs and
//! Booleans in Co-Simulation, its refusal in Model Exchange.
use crate::fmi3_common;

use fmi3_common::{vr, Plant};
use fmi_testkit::fmi3_ffi::*;

#[test]
fn a_geared_lander_dropped_from_a_metre_settles_on_four_feet_in_co_simulation() {
    let plant = Plant::co_simulation(false);
    assert_eq!(plant.set_booleans(&[vr("gear_enabled")], &[true]), fmi3OK);
    assert_eq!(plant.set("r0_nue", &[0.0, 2.0, 0.0]), fmi3OK);
    plant.init();
    for k in 0..800 {
        let step = plant.do_step(f64::from(k) * 0.01, 0.01);
        assert_eq!(step.status, fmi3OK, "{}", plant.log());
    }
    assert_eq!(plant.get("foot_contact", 4), vec![1.0; 4]);
    let stroke = plant.get("leg_stroke", 4);
    let expected = 900.0 * 1.62 / (4.0 * 40_000.0);
    assert!(
        stroke.iter().all(|s| (s - expected).abs() < 1e-6),
        "{stroke:?}"
    );
    let (status, flags) = plant.get_booleans(&[vr("touchdown"), vr("settled"), vr("tipped_over")]);
    assert_eq!(status, fmi3OK);
    assert_eq!(flags, vec![true, true, false]);
    let a = plant.get("specific_force_body", 3);
    assert!(
        (a[1] - 1.62).abs() < 1e-6 && a[0].abs() < 1e-6 && a[2].abs() < 1e-6,
        "{a:?}"
    );
    let angle = plant.get("gear_static_stability_angle", 1)[0];
    assert!((angle.to_degrees() - 40.31).abs() < 0.01, "{angle}");
    // The touchdown time is the free fall of the footpads through 1 m.
    let t_td = plant.get("touchdown_time", 1)[0];
    assert!((t_td - (2.0 / 1.62f64).sqrt()).abs() < 1e-9, "{t_td}");
}

#[test]
fn model_exchange_refuses_the_gear_naming_gear_enabled() {
    let plant = Plant::model_exchange();
    assert_eq!(plant.set_booleans(&[vr("gear_enabled")], &[true]), fmi3OK);
    plant.init();
    let _ = plant.enter_continuous_time_mode();
    let (status, _) = plant.derivatives(18);
    assert_ne!(status, fmi3OK);
    let log = plant.log();
    assert!(
        log.contains("gear_enabled") && log.contains("Co-Simulation only"),
        "{log}"
    );
}
