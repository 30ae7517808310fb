//! The workspace's conformance suite (fmi-testkit), derived from the declaration table and
//! [package.metadata.fmu]; what only LanderGnc knows is in the other tests.
fmi_testkit::conformance!(fmu_gnc, LanderGnc, inputs = sinking);

/// A lander at 800 m, slowly sinking, upright, at rest otherwise: navigation a guidance and
/// control step works on.
fn sinking(k: usize) -> Vec<(&'static str, f64)> {
    vec![
        ("r_nue[2]", 800.0 - k as f64 * 0.01),
        ("v_nue[2]", -1.0),
        ("q_body_to_nue[1]", 1.0),
        ("mass", 900.0),
    ]
}
