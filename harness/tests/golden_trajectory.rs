//! Golden trajectory: the nominal decoupled flight of the paper scenario, sampled once per
//! second, compared with the checked-in CSV. Regenerate (after a reviewed, intended change of
//! behaviour) with `UPDATE_GOLDEN=1 cargo test -p harness --test main golden_trajectory::`.
//!
//! Tolerance: |fresh - golden| <= 1e-6 (1 + |golden|). The FMUs compute their transcendental
//! functions with the libm crate, so the run is meant to be bit-exact on every platform
//! (docs/floating-point.md); the tolerance admits last-bit differences, such as the 1e-15
//! relative between glibc's functions and libm's, which the well-damped decoupled loop
//! (closed-loop poles at 0.5 Hz / 0.06 Hz, zeta 0.8) keeps far below 1e-6 relative.
//! Anything larger is a change of behaviour.
use crate::common;

use cosim::master::Trajectory;
use cosim::results::{read_csv, write_csv};
use cosim::supervise::Runner;
use lander::laws::Law;
use lander::paper::fly;
use lander::scenarios;
use std::path::PathBuf;

const COLUMNS: &[&str] = &[
    "plant.r_nue[1]",
    "plant.r_nue[2]",
    "plant.r_nue[3]",
    "plant.v_nue[1]",
    "plant.v_nue[2]",
    "plant.v_nue[3]",
    "plant.q_body_to_nue[1]",
    "plant.q_body_to_nue[2]",
    "plant.q_body_to_nue[3]",
    "plant.q_body_to_nue[4]",
    "plant.omega_body[1]",
    "plant.omega_body[2]",
    "plant.omega_body[3]",
    "plant.mass",
    "gnc.thrust_cmd",
    "gnc.torque_cmd_body[1]",
    "gnc.torque_cmd_body[2]",
    "gnc.torque_cmd_body[3]",
    "gnc.phi_b",
    "gnc.guidance_phase",
];

/// Every 100th row (1 s at the 0.01 s step) of the selected columns.
fn sample(full: &Trajectory) -> Trajectory {
    let indices: Vec<usize> = COLUMNS
        .iter()
        .map(|c| {
            full.column_index(c)
                .unwrap_or_else(|| panic!("no column {c}"))
        })
        .collect();
    let mut out = Trajectory {
        names: COLUMNS.iter().map(|s| s.to_string()).collect(),
        ..Default::default()
    };
    for k in (0..full.len()).step_by(100) {
        out.times.push(full.times[k]);
        let row = full.row(k);
        out.values.extend(indices.iter().map(|&j| row[j]));
    }
    out
}

#[test]
fn nominal_decoupled_run_matches_the_golden_csv() {
    let system = scenarios::load("paper").unwrap();
    let mut simulation = Runner::new(system, &common::fmu_dir()).unwrap();
    let fresh = sample(&fly(&mut simulation, Law::DECOUPLED).unwrap().trajectory);
    let golden_path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden/paper-decoupled.csv");
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        write_csv(&golden_path, &fresh).unwrap();
    }
    let golden = read_csv(&golden_path).unwrap_or_else(|e| {
        panic!("{e:#}: regenerate with UPDATE_GOLDEN=1 (after reviewing the change)")
    });
    assert_eq!(golden.names, fresh.names, "column set changed");
    assert_eq!(golden.times, fresh.times, "sample times changed");
    let mut worst = (0.0, String::new());
    for k in 0..golden.len() {
        for (j, name) in golden.names.iter().enumerate() {
            let (g, f) = (golden.row(k)[j], fresh.row(k)[j]);
            let excess = (f - g).abs() / (1e-6 * (1.0 + g.abs()));
            if excess > worst.0 {
                worst = (
                    excess,
                    format!("{name} at t = {}: golden {g}, fresh {f}", golden.times[k]),
                );
            }
        }
    }
    assert!(worst.0 <= 1.0, "beyond tolerance: {}", worst.1);
}
