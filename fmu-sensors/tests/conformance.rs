//! The workspace's conformance suite (fmi-testkit), derived from the declaration table and
//! [package.metadata.fmu]; what only LanderSensors knows is in the other tests.
fmi_testkit::conformance!(fmu_sensors, LanderSensors, inputs = hovering);

/// At 800 m, sinking at 1 m/s, upright, hovering (specific force = g up): every sensor in
/// range, so every measurement is made.
fn hovering(k: usize) -> Vec<(&'static str, f64)> {
    vec![
        ("r_nue[2]", 800.0 - k as f64 * 0.01),
        ("v_nue[2]", -1.0),
        ("q_body_to_nue[1]", 1.0),
        ("specific_force_body[2]", 1.62),
    ]
}
