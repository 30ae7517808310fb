//! The workspace's conformance suite (fmi-testkit), derived from the declaration table and
//! [package.metadata.fmu]; what only LanderPlant knows is in the other tests.
fmi_testkit::conformance!(fmu_plant, LanderPlant, model_exchange);
