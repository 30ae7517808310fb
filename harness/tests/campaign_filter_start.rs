//! A campaign over a scenario with an on-board navigation filter starts the filter where
//! each run's dispersed plant starts, off by an error drawn from the covariance the filter
//! claims, instead of at the scenario's nominal start it would otherwise keep.
use crate::common;

use campaign::dispersion::DispersionRanges;
use campaign::estimator_start::{self, ClaimedStartError, Start};
use campaign::flight::{campaign_system, Flyer};
use campaign::Flight;
use lander::laws::Law;

#[test]
fn each_run_starts_the_filter_at_its_dispersed_truth_with_the_claimed_error() {
    // GIVEN the full-fidelity scenario's first 50 ms as a campaign recording every output
    let (mut system, spec) = campaign_system("full-fidelity", &[], true).unwrap();
    system.stop_time = 0.05;
    let mut flyer = Flyer::new(system, spec, &common::fmu_dir()).unwrap();
    let ranges = DispersionRanges::default();
    for run in 0..3 {
        // WHEN a run is flown
        let flight = Flight {
            index: run,
            run,
            run_seed: 0x5eed_0000 + run,
            law: Law::DECOUPLED,
            phi_cmd_deg: 150.0,
        };
        let row = flyer.fly(&flight, &ranges);
        let t = flyer.trajectory();
        let at0 = |name: &str| t.row(0)[t.column_index(name).unwrap()];
        let vector = |instance: &str, name: &str| -> [f64; 3] {
            std::array::from_fn(|i| at0(&format!("{instance}.{name}[{}]", i + 1)))
        };
        // THEN the filter's first estimate is the plant's start (the dispersed truth) plus
        // the error drawn for the run from the filter's claimed 10 m, 1 m/s, 0.01 rad
        let truth = Start {
            r0_nue_m: vector("plant", "r_nue"),
            v0_nue_mps: vector("plant", "v_nue"),
            q0_body_to_nue: std::array::from_fn(|k| {
                at0(&format!("plant.q_body_to_nue[{}]", k + 1))
            }),
        };
        let claimed = ClaimedStartError {
            r0_sigma_m: 10.0,
            v0_sigma_mps: 1.0,
            attitude0_sigma_rad: 0.01,
        };
        let expected = estimator_start::estimate(flight.run_seed, &truth, &claimed);
        let estimate = vector("filter", "r_nue");
        for (i, (got, want)) in estimate.iter().zip(&expected.r0_nue_m).enumerate() {
            assert!(
                (got - want).abs() < 1e-9,
                "run {run} r_nue[{}]: {got} vs {want}",
                i + 1
            );
        }
        // AND the truth itself was dispersed away from the scenario's nominal 800 m up (so
        // a filter left at its nominal start would fail the check above)
        let offset = row.dispersion.delta_r0_nue_m;
        assert!(offset.iter().any(|d| d.abs() > 0.1), "{offset:?}");
    }
}
