//! A campaign over a scenario that commands a retarget measures each flight's divert:
//! overshoot past the new site, cross-track drift, settling time and peak tilt, as
//! `harness retarget` measures the nominal flight.
use crate::common;

use campaign::dispersion::DispersionRanges;
use campaign::flight::{campaign_system, Flyer};
use campaign::summary;
use campaign::Flight;
use lander::laws::Law;

fn flight(run: u64, law: Law) -> Flight {
    Flight {
        index: run,
        run,
        run_seed: 0xd1e7_0000 + run,
        law,
        phi_cmd_deg: 150.0,
    }
}

fn flyer(scenario: &str, sets: &[String]) -> Flyer {
    let (system, spec) = campaign_system(scenario, sets, false).unwrap();
    Flyer::new(system, spec, &common::fmu_dir()).unwrap()
}

#[test]
fn an_undispersed_flight_measures_the_divert_that_harness_retarget_measures() {
    // GIVEN the retarget scenario as a campaign records it (only the metrics' columns), with
    // no dispersion
    let mut lean = flyer("retarget", &[]);
    for law in [Law::COUPLED, Law::DECOUPLED] {
        let row = lean.fly(&flight(0, law), &DispersionRanges::none());
        // WHEN the same flight is measured from every output, as `harness retarget` does
        let (mut system, _) = campaign_system("retarget", &[], true).unwrap();
        system.record = None;
        let mut full = Flyer::new(
            system,
            lander::scenarios::spec::load("retarget").unwrap().1,
            &common::fmu_dir(),
        )
        .unwrap();
        full.fly(&flight(0, law), &DispersionRanges::none());
        let command = lander::retarget::RetargetCommand::of(full.simulation().system()).unwrap();
        let reference = lander::retarget::divert_metrics(full.trajectory(), &command).unwrap();
        // THEN the campaign's divert metrics are those, bit for bit
        let m = row.metrics;
        assert_eq!(m.divert_overshoot_m, reference.overshoot_m, "{law:?}");
        assert_eq!(m.divert_cross_track_m, reference.cross_track_m, "{law:?}");
        assert_eq!(m.divert_settle_time_s, reference.settle_time_s, "{law:?}");
        assert_eq!(m.divert_peak_tilt_rad, reference.peak_tilt_deg.to_radians());
        // AND they are docs/retarget.md's: millimetres past the site, under the 15 deg limit,
        // settled within 1 m before the 22.4 s divert ends
        assert!(m.divert_overshoot_m < 0.01, "{m:?}");
        assert!(m.divert_peak_tilt_rad.to_degrees() < 15.0, "{m:?}");
        assert!(
            m.divert_settle_time_s > 10.0 && m.divert_settle_time_s < 22.4,
            "{m:?}"
        );
    }
}

#[test]
fn dispersed_diverts_stay_near_the_site_when_re_planned_and_overshoot_when_only_moved() {
    // GIVEN three dispersed runs of each law, re-planned and with the target only moved
    let ranges = DispersionRanges::default();
    let mut replanned = flyer("retarget", &[]);
    let mut moved = flyer("retarget", &["gnc.retarget_replan=false".to_owned()]);
    let mut rows = Vec::new();
    for run in 0..3 {
        for law in [Law::COUPLED, Law::DECOUPLED] {
            // WHEN each is flown
            let re = replanned.fly(&flight(run, law), &ranges);
            let mo = moved.fly(&flight(run, law), &ranges);
            // THEN the re-planned divert ends on the site without passing it by more than
            // 0.1 m and within the tilt limit; moving the target alone passes it by metres
            let (r, m) = (re.metrics, mo.metrics);
            assert!(r.divert_overshoot_m < 0.1, "{law:?} run {run}: {r:?}");
            assert!(r.divert_settle_time_s < 30.0, "{law:?} run {run}: {r:?}");
            assert!(r.divert_peak_tilt_rad.to_degrees() < 16.0, "{r:?}");
            assert!(m.divert_overshoot_m > 10.0, "{law:?} run {run}: {m:?}");
            assert!(m.divert_peak_tilt_rad.to_degrees() > 30.0, "{m:?}");
            rows.push(re);
        }
    }
    // AND the campaign's table carries the divert block per point
    let text = summary::table(&summary::summarise(&rows));
    assert!(text.contains("overshoot (m)"), "{text}");
    assert!(text.contains("within 1 m for good after (s)"), "{text}");
}

#[test]
fn a_scenario_without_a_retarget_has_no_divert_metrics() {
    // GIVEN the paper scenario's first 20 s as a campaign
    let (mut system, spec) = campaign_system("paper", &[], false).unwrap();
    system.stop_time = 20.0;
    let mut flyer = Flyer::new(system, spec, &common::fmu_dir()).unwrap();
    let row = flyer.fly(&flight(0, Law::DECOUPLED), &DispersionRanges::default());
    // THEN its divert metrics are NaN (not applicable), and the table has no divert block
    let m = row.metrics;
    assert!(
        m.divert_overshoot_m.is_nan() && m.divert_settle_time_s.is_nan(),
        "{m:?}"
    );
    let text = summary::table(&summary::summarise(&[row]));
    assert!(!text.contains("divert"), "{text}");
}
