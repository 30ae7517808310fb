//! Every loop of a plant step ends: sub-stepping and event location at any time magnitude
//! (far beyond 2^16 s, where doubles are coarser than the crossing tolerance, up to 1e300)
//! and any integration step, run under a watchdog because a hang never reports by itself.
// std's transcendental functions here are a reference independent of the libm the model uses.
#![allow(clippy::disallowed_methods)]
use fmu_plant::physics::parameters::PlantParameters;
use fmu_plant::physics::plant::{Advance, Commands, Plant};
use proptest::prelude::*;
use std::sync::mpsc;
use std::time::Duration;

/// Runs `f` on a thread; fails if it has not finished within `limit_s`.
fn within<T: Send + 'static>(limit_s: u64, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(Duration::from_secs(limit_s))
        .expect("the plant step did not end (watchdog)")
}

/// One communication step of `h` from time `t` with sub-steps of at most `h_sub`, thrown up
/// at `climb_mps` from `altitude_m` with the engines at `thrust_cmd_n` (0 = ballistic, so
/// the touchdown is found inside the step when the step is long enough; a fast climb puts it
/// far into a long window, where doubles are coarser than the absolute tolerance).
fn step(
    climb_mps: f64,
    altitude_m: f64,
    thrust_cmd_n: f64,
    t: f64,
    h: f64,
    h_sub: f64,
) -> (Advance, f64) {
    let parameters = PlantParameters {
        integration_step_s: h_sub,
        r0_nue_m: [0.0, altitude_m, 0.0].into(),
        v0_nue_mps: [0.0, climb_mps, 0.0].into(),
        ..PlantParameters::default()
    };
    let (plant, mut run, _) = Plant::new(&parameters).expect("valid parameters");
    let commands = Commands {
        thrust_cmd_n,
        ..Commands::default()
    };
    let advance = plant.advance(&mut run, &commands, t, h);
    (advance, run.state.mass_kg)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn a_step_ends_at_every_time_magnitude_and_integration_step(
        log_t in -2.0f64..300.0,
        log_h_sub in -3.0f64..12.0,
        sub_steps in 1u32..64,
        altitude_m in 0.001f64..5000.0,
        log_climb in -3.0f64..7.0,
        burning in any::<bool>(),
    ) {
        let (t, h_sub) = (10f64.powf(log_t), 10f64.powf(log_h_sub));
        let h = h_sub * f64::from(sub_steps);
        // A full burn exhausts the propellant in a long step: a second event in the window.
        let thrust = if burning { 1600.0 } else { 0.0 };
        let (advance, mass_kg) = within(20, move || step(10f64.powf(log_climb), altitude_m, thrust, t, h, h_sub));
        prop_assert!(mass_kg.is_finite());
        if let Advance::Touchdown(time) = advance {
            // At huge t the step is lost in the rounding of t + h; the time stays in range.
            prop_assert!(time >= t && time <= t + h, "touchdown at {time}, step [{t}, {}]", t + h);
        }
    }
}

#[test]
fn a_ballistic_flight_of_twenty_minutes_in_one_sub_step_finds_its_touchdown() {
    // GIVEN a throw up at 1 km/s: back on the ground after 2 v / g = 1235 s, in one sub-step
    let (advance, _) = within(20, move || step(1e3, 0.0 + 1e-3, 0.0, 0.0, 1e4, 1e4));
    let Advance::Touchdown(time) = advance else {
        panic!("no touchdown: {advance:?}")
    };
    assert!((time - 2e3 / 1.62).abs() < 1e-3, "{time}");
}

#[test]
fn a_long_free_fall_step_at_a_huge_time_finds_the_touchdown_within_the_relative_tolerance() {
    // GIVEN a drop from 800 m at t = 2^40 s, one step of 100 s in one 100 s sub-step
    let t = 2f64.powi(40);
    let (advance, _) = within(20, move || step(0.0, 800.0, 0.0, t, 100.0, 100.0));
    // THEN the touchdown lies at sqrt(2 h / g) after t, as finely as the doubles near t allow
    let Advance::Touchdown(time) = advance else {
        panic!("no touchdown: {advance:?}")
    };
    let exact = t + (2.0 * 800.0 / 1.62f64).sqrt();
    let resolution = fmu_plant::physics::events::crossing_tolerance_s(t);
    // RK4 in one 100 s sub-step of a parabola is exact; the rest is the search resolution.
    assert!(
        (time - exact).abs() <= resolution + 1e-9 * (exact - t),
        "{time} vs {exact}"
    );
}
