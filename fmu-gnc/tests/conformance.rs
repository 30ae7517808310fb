//! The workspace's conformance suite (fmi-testkit), derived from the declaration table and
//! [package.metadata.fmu]; what only LanderGnc knows is in the other tests.
fmi_testkit::conformance!(fmu_gnc, LanderGnc);
