//! A container FMU made by fmpy's own tool (`fmpy.container_fmu`: fmpy's C binary steps the
//! FMUs inside it and passes their values) around the FMI 3.0 LanderGnc and LanderPlant,
//! wired as the paper wires them, with the paper's 150 deg roll demand as the container's
//! parameter: one FMU of a tool we did not write, flown alone over its DefaultExperiment (40
//! s at 0.01 s) by fmpy's `simulate_fmu` (tests/interop/python/container_fmu.py) and by the
//! harness (`harness run Container.fmu`). The same binary under the same calls at the same
//! communication points: every recorded value must be equal, bit for bit.
use cosim::master::Conventions;
use interop_tests::{python, read_trajectory, run_harness, scenario, scratch};
use system_tests::fmi3_fmu_path;

const PHI_CMD_RAD: f64 = 2.6179938779914944;

#[test]
fn fmpys_container_fmu_flies_the_same_in_the_harness_and_in_fmpy() {
    // GIVEN the container, made and flown by fmpy
    let dir = scratch("interop-container-");
    let container = dir.path().join("Container.fmu");
    let fmpy_csv = dir.path().join("fmpy.csv");
    python::run(
        "container_fmu.py",
        [
            fmi3_fmu_path("LanderGnc").as_os_str(),
            fmi3_fmu_path("LanderPlant").as_os_str(),
            container.as_os_str(),
            fmpy_csv.as_os_str(),
            "40".as_ref(),
            "0.01".as_ref(),
        ],
    );
    let fmpy = read_trajectory(&fmpy_csv);
    // WHEN the harness flies it alone
    let harness = run_harness(
        scenario(container.to_str().unwrap()),
        Conventions::default(),
    );
    // THEN the same columns (the harness prefixes its one instance's name) ...
    let unprefixed: Vec<&str> = harness
        .names
        .iter()
        .map(|n| n.split_once('.').map_or(n.as_str(), |(_, v)| v))
        .collect();
    assert_eq!(unprefixed, fmpy.names, "columns");
    // ... over the same 4,001 communication points, every value bit for bit
    assert_eq!(harness.len(), 4001);
    assert_eq!(harness.times, fmpy.times, "times");
    for k in 0..harness.len() {
        let (h, f) = (harness.row(k), fmpy.row(k));
        let same = h.iter().zip(f).all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "t = {}: harness {h:?}, fmpy {f:?}", harness.times[k]);
    }
    // AND the flight is the loop's, not a container passing nothing: the roll demand reached,
    // the descent under way (800 m, hover until 12 s, then down)
    let column = |name: &str| unprefixed.iter().position(|n| *n == name).unwrap();
    let last = harness.row(harness.len() - 1);
    assert!(
        (last[column("phi_b")] - PHI_CMD_RAD).abs() < 1e-3,
        "{last:?}"
    );
    assert!(last[column("altitude")] < 790.0, "{last:?}");
    assert!(harness.row(0)[column("thrust_cmd")] > 1000.0);
}
