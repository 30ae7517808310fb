//! The workspace's conformance suite (fmi-testkit), derived from the declaration table and
//! [package.metadata.fmu]; what only LanderFilter knows is in the other tests.
fmi_testkit::conformance!(fmu_filter, LanderFilter, inputs = hovering);

/// Hovering upright at 800 m, every measurement valid: g on the accelerometer, the
/// altimeter's range, no line-of-sight velocity, so each step runs both updates.
fn hovering(_k: usize) -> Vec<(&'static str, f64)> {
    vec![
        ("accel_body_meas[2]", 1.62),
        ("altimeter_range", 800.0),
        ("altimeter_valid", 1.0),
        ("velocimeter_valid_1", 1.0),
        ("velocimeter_valid_2", 1.0),
        ("velocimeter_valid_3", 1.0),
    ]
}
