//! The workspace's conformance suite (fmi-testkit), derived from the declaration table and
//! [package.metadata.fmu]; what only LanderPlant knows is in the other tests.
fmi_testkit::conformance!(fmu_plant, LanderPlant, model_exchange, inputs = manoeuvring);

/// The engine and torque commands of a manoeuvre (the RCS duties, ignored by the default
/// torque model, stay off), so that the state moves and every part of a step runs.
fn manoeuvring(_k: usize) -> Vec<(&'static str, f64)> {
    vec![
        ("thrust_cmd", 1300.0),
        ("torque_cmd_body[1]", 1.0),
        ("torque_cmd_body[2]", -2.0),
        ("torque_cmd_body[3]", 0.5),
    ]
}
