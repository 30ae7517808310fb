//! Analytic, invariant and convergence tests of the plant physics, on the pure
//! Rust API: no FMI involved.
// std's transcendental functions here are a reference independent of the libm the model uses.
#![allow(clippy::disallowed_methods)]
use fmu_plant::physics::frames::Body;
use fmu_plant::physics::parameters::PlantParameters;
use fmu_plant::physics::plant::{Advance, Commands, Plant, PlantRun};
use fmu_plant::physics::rigid_body::{angular_momentum_nue, rotational_energy};
use nalgebra::{Quaternion, Vector3};
use proptest::prelude::*;

const G: f64 = 1.62;
const ISP_G0: f64 = 300.0 * 9.81;

fn start(p: &PlantParameters) -> (Plant, PlantRun) {
    let (plant, run, _) = Plant::new(p).expect("valid parameters");
    (plant, run)
}

/// Runs `n` communication steps of `h` with constant commands; panics on touchdown.
fn run_for(plant: &Plant, run: &mut PlantRun, commands: &Commands, h: f64, n: usize) {
    for k in 0..n {
        let adv = plant.advance(run, commands, k as f64 * h, h);
        assert_eq!(adv, Advance::Reached, "unexpected touchdown at step {k}");
    }
}

fn position_velocity(plant: &Plant, run: &PlantRun) -> (Vector3<f64>, Vector3<f64>) {
    let (r_nue, v_nue) = plant.translation.to_nue(&run.state.translation);
    (r_nue.0, v_nue.0)
}

fn thrust(n: f64) -> Commands {
    Commands {
        thrust_cmd_n: n,
        torque_cmd_body_nm: Vector3::zeros(),
    }
}

#[test]
fn free_fall_follows_the_parabola() {
    // GIVEN engines off at 800 m with a lateral velocity
    let p = PlantParameters {
        v0_nue_mps: Vector3::new(3.0, 0.0, -2.0),
        ..Default::default()
    };
    let (plant, mut run) = start(&p);
    // WHEN falling for 20 s
    run_for(&plant, &mut run, &thrust(0.0), 0.01, 2000);
    // THEN r = r0 + v0 t - g t^2 / 2; RK4 is exact for a quadratic, so only round-off remains
    let t: f64 = 20.0;
    let (r, v) = position_velocity(&plant, &run);
    let r_exact = Vector3::new(3.0 * t, 800.0 - 0.5 * G * t * t, -2.0 * t);
    assert!((r - r_exact).norm() < 1e-9, "{r} vs {r_exact}");
    assert!((v - Vector3::new(3.0, -G * t, -2.0)).norm() < 1e-11);
    assert_eq!(run.state.mass_kg, 900.0, "no thrust, no mass flow");
}

#[test]
fn hover_at_exactly_m_g_stays_put_without_mass_flow() {
    // GIVEN a thrust of exactly m g and no mass flow (Isp -> infinity isolates the dynamics)
    let p = PlantParameters {
        isp_s: 1e15,
        ..Default::default()
    };
    let (plant, mut run) = start(&p);
    // WHEN hovering for 100 s
    run_for(&plant, &mut run, &thrust(900.0 * G), 0.01, 10_000);
    // THEN the lander has not moved beyond round-off
    let (r, v) = position_velocity(&plant, &run);
    assert!((r - Vector3::new(0.0, 800.0, 0.0)).norm() < 1e-9, "{r}");
    assert!(v.norm() < 1e-11, "{v}");
}

#[test]
fn hover_with_m_g_updated_every_step_drifts_only_by_the_zero_order_hold() {
    // GIVEN thrust = m g re-commanded at every 0.01 s step while the mass falls
    let p = PlantParameters::default();
    let (plant, mut run) = start(&p);
    let (h, n) = (0.01, 10_000);
    for k in 0..n {
        let cmd = thrust(run.state.mass_kg * G);
        assert_eq!(
            plant.advance(&mut run, &cmd, k as f64 * h, h),
            Advance::Reached
        );
    }
    // THEN the only acceleration is the hold error: within a step T/m(t) - g ~ g (mdot/m) s,
    // s in [0, h], i.e. a mean upward acceleration g (mdot/m) h / 2 over the run.
    let (r, v) = position_velocity(&plant, &run);
    let t_total = h * n as f64;
    let mdot_over_m_max = G / ISP_G0; // (m g / (Isp g0)) / m
    let a_hold = G * mdot_over_m_max * h / 2.0;
    assert!(
        v.y > 0.0 && v.y < 1.1 * a_hold * t_total,
        "v_up {} vs bound {}",
        v.y,
        a_hold * t_total
    );
    assert!(r.y - 800.0 < 1.1 * 0.5 * a_hold * t_total * t_total);
    assert!(
        r.x.abs() < 1e-12 && r.z.abs() < 1e-12,
        "no lateral motion when upright"
    );
}

#[test]
fn constant_thrust_matches_the_rocket_equation() {
    // GIVEN full thrust (1600 N) straight up
    let p = PlantParameters::default();
    let (plant, mut run) = start(&p);
    // WHEN burning for 60 s
    let t = 60.0;
    run_for(&plant, &mut run, &thrust(1600.0), 0.01, 6000);
    // THEN the mass falls linearly and the velocity is Tsiolkovsky's minus gravity loss
    let m_exact = 900.0 - 1600.0 / ISP_G0 * t;
    // Linear in time, so RK4 is exact; 6000 additions on ~ 900 kg round off to ~ 1e-9 kg.
    assert!(
        (run.state.mass_kg - m_exact).abs() < 1e-8,
        "{} vs {m_exact}",
        run.state.mass_kg
    );
    let v_exact = ISP_G0 * (900.0 / m_exact).ln() - G * t;
    let (_, v) = position_velocity(&plant, &run);
    // The RK4 error of the log term, ~ (mdot/m)^5 h^5 v_e per step, is below round-off;
    // what remains is the round-off of 6000 steps on v ~ 900 m/s (~ 1e-12 relative).
    assert!((v.y - v_exact).abs() < 1e-8, "{} vs {v_exact}", v.y);
}

#[test]
fn pure_torque_about_a_principal_axis_gives_the_analytic_rate_and_angle() {
    for (axis, inertia) in [(0, 400.0), (1, 300.0), (2, 450.0)] {
        // GIVEN a constant 50 N m about one principal axis, engines off, high up
        let p = PlantParameters {
            r0_nue_m: Vector3::new(0.0, 10_000.0, 0.0),
            ..Default::default()
        };
        let (plant, mut run) = start(&p);
        let mut torque = Vector3::zeros();
        torque[axis] = 50.0;
        let cmd = Commands {
            thrust_cmd_n: 0.0,
            torque_cmd_body_nm: torque,
        };
        // WHEN applied for 10 s
        let t = 10.0;
        run_for(&plant, &mut run, &cmd, 0.01, 1000);
        // THEN w = tau t / I and the attitude is a rotation by tau t^2 / (2 I) about the axis
        let alpha = 50.0 / inertia;
        let angle = 0.5 * alpha * t * t;
        let mut expected_w = Vector3::zeros();
        expected_w[axis] = alpha * t;
        assert!(
            (run.state.omega_body.0 - expected_w).norm() < 1e-12,
            "axis {axis}"
        );
        let (s, c) = (0.5 * angle).sin_cos();
        let mut v = Vector3::zeros();
        v[axis] = s;
        let q_exact = Quaternion::from_parts(c, v);
        let q = run.state.q_body_to_nue;
        assert!((q - q_exact).norm() < 1e-9, "axis {axis}: {q} vs {q_exact}");
    }
}

fn tumbling_parameters(omega0: Vector3<f64>, integration_step_s: f64) -> PlantParameters {
    PlantParameters {
        r0_nue_m: Vector3::new(0.0, 1e6, 0.0),
        omega0_body_radps: omega0,
        integration_step_s,
        ..Default::default()
    }
}

#[test]
fn torque_free_tumbling_conserves_inertial_momentum_and_energy() {
    // GIVEN a spin near the intermediate axis (x, Ixx = 400 between 300 and 450), which
    // tumbles (Dzhanibekov), so all three rates vary strongly
    let omega0 = Vector3::new(0.8, 0.02, 0.03);
    let p = tumbling_parameters(omega0, 0.01);
    let (plant, mut run) = start(&p);
    let inertia = p.inertia_body_kgm2;
    let h0 = angular_momentum_nue(&inertia, &run.state.q_body_to_nue, &run.state.omega_body);
    let e0 = rotational_energy(&inertia, &Body(omega0));
    // WHEN coasting for 100 s (several flips)
    let mut min_wx = f64::INFINITY;
    for k in 0..10_000 {
        plant.advance(&mut run, &thrust(0.0), k as f64 * 0.01, 0.01);
        min_wx = min_wx.min(run.state.omega_body.0.x);
        // |q| = 1 after every step (renormalised; the error is pure round-off)
        assert!((run.state.q_body_to_nue.norm() - 1.0).abs() < 4.0 * f64::EPSILON);
    }
    assert!(
        min_wx < -0.5,
        "the body must actually tumble: min wx = {min_wx}"
    );
    // THEN H_nue and E are conserved to the RK4 error: per step ~ (|w| h)^5 relative,
    // (0.8 x 0.01)^5 = 3e-11, times 1e4 steps = 3e-7; the tolerance is 1e-6 relative.
    let h1 = angular_momentum_nue(&inertia, &run.state.q_body_to_nue, &run.state.omega_body);
    let e1 = rotational_energy(&inertia, &run.state.omega_body);
    assert!((h1 - h0).norm() / h0.norm() < 1e-6, "H {h0:?} -> {h1:?}");
    assert!((e1 - e0).abs() / e0 < 1e-6, "E {e0} -> {e1}");
}

#[test]
fn rk4_error_falls_sixteenfold_when_the_sub_step_halves() {
    // GIVEN a tumbling body under thrust (rotation and translation coupled), integrated to
    // t = 8 s with sub-steps h, h/2 and a reference at h/64
    let omega0 = Vector3::new(1.5, 0.3, -0.8);
    let final_state = |h_sub: f64| {
        let p = tumbling_parameters(omega0, h_sub);
        let (plant, mut run) = start(&p);
        let cmd = Commands {
            thrust_cmd_n: 1200.0,
            torque_cmd_body_nm: Vector3::new(20.0, -10.0, 5.0),
        };
        // One communication step of 0.08 s: the sub-step parameter sets the resolution.
        run_for(&plant, &mut run, &cmd, 0.08, 100);
        let (r, v) = position_velocity(&plant, &run);
        (r, v, run.state.omega_body)
    };
    let reference = final_state(0.04 / 64.0);
    let error = |h_sub: f64| {
        let (r, v, w) = final_state(h_sub);
        (
            (r - reference.0).norm(),
            (v - reference.1).norm(),
            (w - reference.2).norm(),
        )
    };
    let coarse = error(0.04);
    let fine = error(0.02);
    // WHEN comparing the errors THEN each ratio is ~2^4 (12..20 allows the O(h^5) term)
    for (name, c, f) in [
        ("r", coarse.0, fine.0),
        ("v", coarse.1, fine.1),
        ("w", coarse.2, fine.2),
    ] {
        let ratio = c / f;
        assert!(
            (12.0..20.0).contains(&ratio),
            "{name}: {c:e} / {f:e} = {ratio}"
        );
    }
}

#[test]
fn throttle_and_rcs_saturate() {
    let p = PlantParameters {
        r0_nue_m: Vector3::new(0.0, 10_000.0, 0.0),
        ..Default::default()
    };
    let (plant, run) = start(&p);
    for (cmd, delivered) in [
        (0.5, 0.0),
        (1.0, 0.0),
        (100.0, 720.0),
        (1000.0, 1000.0),
        (1e9, 1600.0),
    ] {
        let d = plant.delivered(&run.state, &thrust(cmd), false);
        assert_eq!(d.thrust_n, delivered, "command {cmd}");
    }
    let cmd = Commands {
        thrust_cmd_n: 1e9,
        torque_cmd_body_nm: Vector3::new(1e6, -1e6, 30.0),
    };
    let d = plant.delivered(&run.state, &cmd, false);
    assert_eq!(d.rcs_torque_body_nm, Vector3::new(116.0, -116.0, 30.0));
    // The saturated values are what acts: after 1 s about one axis w = -116 / I and the
    // mass flow is 1600 N's.
    let cmd = Commands {
        thrust_cmd_n: 1e9,
        torque_cmd_body_nm: Vector3::new(-1e6, 0.0, 0.0),
    };
    let mut run = run;
    run_for(&plant, &mut run, &cmd, 0.01, 100);
    assert!((run.state.omega_body.0.x + 116.0 / 400.0).abs() < 1e-12);
    assert!((run.state.mass_kg - (900.0 - 1600.0 / ISP_G0)).abs() < 1e-10);
}

#[test]
fn touchdown_time_matches_the_analytic_crossing_for_any_step() {
    // GIVEN a descent at 10 m/s from 800 m under 720 N (less than the weight: accelerating)
    let p = PlantParameters {
        v0_nue_mps: Vector3::new(0.0, -10.0, 0.0),
        isp_s: 1e15,
        ..Default::default()
    };
    let a = 720.0 / 900.0 - G;
    // 800 - 10 t + a t^2 / 2 = 0 with a < 0
    let t_exact = (-10.0 + (100.0 + 2.0 * -a * 800.0f64).sqrt()) / -a;
    for h in [0.01, 0.1, 0.37, 2.0] {
        let (plant, mut run) = start(&p);
        let mut t = 0.0;
        let t_td = loop {
            match plant.advance(&mut run, &thrust(720.0), t, h) {
                Advance::Reached => t += h,
                Advance::Touchdown(time) => break time,
            }
        };
        // WHEN the step contains the crossing THEN the reported time is the crossing
        assert!(t_td > t && t_td <= t + h);
        assert!(
            (t_td - t_exact).abs() < 1e-9,
            "h = {h}: {t_td} vs {t_exact}"
        );
        let td = run.touchdown.expect("recorded");
        assert!((td.v_nue_mps.0.y - (-10.0 + a * t_exact)).abs() < 1e-8);
        assert!(plant.altitude(&run.state).abs() < 1e-8);
        // and the plant no longer moves
        let frozen = run;
        assert_eq!(
            plant.advance(&mut run, &thrust(1600.0), t_td, h),
            Advance::Touchdown(t_td)
        );
        assert_eq!(run, frozen);
    }
}

#[test]
fn propellant_exhaustion_cuts_thrust_at_the_dry_mass() {
    // GIVEN 1 kg of propellant and full thrust upwards
    let p = PlantParameters {
        m0_kg: 601.0,
        ..Default::default()
    };
    let (plant, mut run) = start(&p);
    // WHEN burning for 4 s in 0.1 s steps (the burn-out at 1.839 s lies inside a step)
    run_for(&plant, &mut run, &thrust(1600.0), 0.1, 40);
    // THEN the flag is up, the mass is the dry mass, no thrust is delivered, and the
    // velocity is the rocket equation up to burn-out followed by a coast: this checks
    // the burn-out time to the event tolerance.
    assert!(run.propellant_exhausted);
    assert_eq!(run.state.mass_kg, 600.0);
    assert_eq!(
        plant.delivered(&run.state, &thrust(1600.0), true).thrust_n,
        0.0
    );
    let v_exact = ISP_G0 * (601.0f64 / 600.0).ln() - G * 4.0;
    let (_, v) = position_velocity(&plant, &run);
    assert!((v.y - v_exact).abs() < 1e-9, "{} vs {v_exact}", v.y);
}

#[test]
fn first_order_thrust_lag_follows_the_exponential() {
    let mut p = PlantParameters {
        isp_s: 1e15,
        ..Default::default()
    };
    p.engines.time_constant_s = 0.5;
    let (plant, mut run) = start(&p);
    run_for(&plant, &mut run, &thrust(1000.0), 0.01, 50);
    let d = plant.delivered(&run.state, &thrust(1000.0), false);
    let expected = 1000.0 * (1.0 - (-1.0f64).exp());
    // RK4 on x' = -x / tau: relative global error ~ (t / tau) (h / tau)^4 / 120 = 2.7e-9.
    let tolerance = 2.0 * 1000.0 * 2.0 * (0.01f64 / 0.5).powi(4) / 120.0;
    assert!(
        (d.thrust_n - expected).abs() < tolerance,
        "{} vs {expected}",
        d.thrust_n
    );
    assert!(
        (d.thrust_n - expected).abs() > 1e-12,
        "a lag must not be exact: is it active?"
    );
}

#[test]
fn thrust_misalignment_produces_the_lever_arm_torque_and_rate() {
    // GIVEN 0.5 deg misalignment towards +x, nozzle 1 m below the centre of mass
    let mut p = PlantParameters {
        isp_s: 1e15,
        ..Default::default()
    };
    p.thrust_line.misalignment_rad = 0.5f64.to_radians();
    let (plant, mut run) = start(&p);
    // WHEN firing 1000 N for 1 s
    run_for(&plant, &mut run, &thrust(1000.0), 0.01, 100);
    // THEN about z: tau = 1 m x 1000 N x sin(0.5 deg), w_z = tau / Izz after 1 s
    let tau = 1000.0 * 0.5f64.to_radians().sin();
    assert!(
        (run.state.omega_body.0.z - tau / 450.0).abs() < 1e-9,
        "{}",
        run.state.omega_body.0.z
    );
    assert!(run.state.omega_body.0.x.abs() < 1e-12 && run.state.omega_body.0.y.abs() < 1e-12);
}

fn spherical(p: PlantParameters) -> PlantParameters {
    PlantParameters {
        translation_model: 2,
        ..p
    }
}

/// Runs the same ballistic flight in both models; returns (flat, spherical) position and
/// the spherical altitude above the sphere.
fn flat_and_spherical(v0_nue: Vector3<f64>, seconds: f64) -> (Vector3<f64>, Vector3<f64>, f64) {
    let p = PlantParameters {
        r0_nue_m: Vector3::new(0.0, 800.0, 0.0),
        v0_nue_mps: v0_nue,
        ..Default::default()
    };
    let n = (seconds / 0.1).round() as usize;
    let (flat, mut run_flat) = start(&p);
    run_for(&flat, &mut run_flat, &thrust(0.0), 0.1, n);
    let (sph, mut run_sph) = start(&spherical(p));
    run_for(&sph, &mut run_sph, &thrust(0.0), 0.1, n);
    (
        position_velocity(&flat, &run_flat).0,
        position_velocity(&sph, &run_sph).0,
        sph.altitude(&run_sph.state),
    )
}

#[test]
fn flat_and_spherical_agree_near_the_site_over_a_short_arc() {
    // GIVEN 10 s of coasting at 10 m/s North from 800 m (a 100 m arc)
    let (r_flat, r_sph, _) = flat_and_spherical(Vector3::new(10.0, 0.0, 0.0), 10.0);
    // THEN they differ by centimetres: the neglected accelerations are gravity fall-off
    // 2 g h / R = 1.5e-3, transport V^2 / R = 6e-5, Coriolis 2 w V = 5e-5 m/s^2,
    // i.e. < 0.1 m after 10 s.
    assert!((r_flat - r_sph).norm() < 0.1, "{r_flat} vs {r_sph}");
}

#[test]
fn flat_and_spherical_differ_as_the_neglected_terms_predict_over_a_long_arc() {
    // GIVEN 20 s of coasting at 300 m/s North (a 6 km arc) at the default site (69.4 S)
    let (v, t) = (300.0, 20.0);
    let (r_flat, r_sph, altitude_sph) = flat_and_spherical(Vector3::new(v, 0.0, 0.0), t);
    let radius = 1_737_400.0;
    // THEN the spherical lander stays higher above its sphere: the surface curves away
    // (centripetal V^2 / R) and gravity is weaker with height (2 g h / R, h ~ 800 -> 476 m)
    let h_mean = 800.0 - 0.5 * G * t * t / 2.0;
    let predicted_lift = 0.5 * (v * v / radius + 2.0 * G * h_mean / radius) * t * t;
    let lift = altitude_sph - r_flat.y;
    assert!(
        (lift / predicted_lift - 1.0).abs() < 0.05,
        "lift {lift} vs {predicted_lift}"
    );
    // and Coriolis deflects it East-West: u' = 2 w_m v sin(lat) (towards West in the south)
    let lat = fmu_plant::physics::parameters::SITE_LATITUDE_RAD;
    let w_m = fmu_plant::physics::parameters::MOON_ROTATION_RATE_RADPS;
    let predicted_east = 0.5 * 2.0 * w_m * v * lat.sin() * t * t;
    assert!(predicted_east < 0.0);
    assert!(
        (r_sph.z / predicted_east - 1.0).abs() < 0.05,
        "east {} vs {predicted_east}",
        r_sph.z
    );
    // (the site-frame Up coordinate additionally drops by the curvature d^2 / (2R))
    let d = r_sph.x;
    assert!((altitude_sph - r_sph.y - d * d / (2.0 * radius)).abs() < 0.05);
}

#[test]
fn spherical_hover_needs_the_same_thrust_at_the_site_up_to_centrifugal_and_height() {
    // GIVEN the spherical model and m g thrust with the mass flow switched off
    let p = spherical(PlantParameters {
        isp_s: 1e15,
        ..Default::default()
    });
    let (plant, mut run) = start(&p);
    run_for(&plant, &mut run, &thrust(900.0 * G), 0.1, 100);
    // THEN after 10 s the residual vertical acceleration is 2 g h / R + R w^2 cos^2(lat)
    let radius: f64 = 1_737_400.0;
    let lat = fmu_plant::physics::parameters::SITE_LATITUDE_RAD;
    let w_m = fmu_plant::physics::parameters::MOON_ROTATION_RATE_RADPS;
    let a = 2.0 * G * 800.0 / radius + radius * w_m * w_m * lat.cos().powi(2);
    let (_, v) = position_velocity(&plant, &run);
    assert!(
        (v.y / (a * 10.0) - 1.0).abs() < 0.02,
        "{} vs {}",
        v.y,
        a * 10.0
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn no_nan_and_unit_quaternion_for_any_commands(
        thrust_cmd in -1e12f64..1e12,
        tx in -1e9f64..1e9, ty in -1e9f64..1e9, tz in -1e9f64..1e9,
        w in prop::array::uniform3(-5.0f64..5.0),
        q in prop::array::uniform4(-1.0f64..1.0),
        model in 1i32..=2,
        h in 0.001f64..0.5,
    ) {
        let qn = Quaternion::new(q[0], q[1], q[2], q[3]);
        prop_assume!(qn.norm() > 0.1);
        let qn = qn.normalize();
        let p = PlantParameters {
            q0_body_to_nue: [qn.w, qn.i, qn.j, qn.k],
            omega0_body_radps: Vector3::from(w),
            m0_kg: 600.5,
            translation_model: model,
            ..Default::default()
        };
        let (plant, mut run) = start(&p);
        let cmd = Commands { thrust_cmd_n: thrust_cmd, torque_cmd_body_nm: Vector3::new(tx, ty, tz) };
        let mut t = 0.0;
        for _ in 0..20 {
            let adv = plant.advance(&mut run, &cmd, t, h);
            prop_assert!(run.state.is_finite());
            prop_assert!((run.state.q_body_to_nue.norm() - 1.0).abs() < 1e-12);
            prop_assert!(run.state.mass_kg >= 600.0);
            if let Advance::Touchdown(_) = adv { break; }
            t += h;
        }
    }
}

/// A Co-Simulation step that fails is undone from the checkpoint taken before it: the run
/// as it was, down to the means of the step before, the touchdown the failed step recorded
/// and the pendulums it swung.
#[test]
fn a_step_undone_from_its_checkpoint_leaves_the_run_as_it_was() {
    let mut p = PlantParameters {
        r0_nue_m: Vector3::new(0.0, 1.0, 0.0),
        v0_nue_mps: Vector3::new(0.5, -2.0, 0.0),
        ..Default::default()
    };
    p.slosh.enabled = true;
    p.slosh.delta0_m = [0.05, 0.0, 0.0, 0.05];
    let (plant, mut run) = start(&p);
    run.start_means();
    assert_eq!(
        plant.advance(&mut run, &thrust(1000.0), 0.0, 0.01),
        Advance::Reached
    );
    let before = run;
    let checkpoint = run.checkpoint(&plant);
    run.start_means();
    let end = plant.advance(&mut run, &thrust(1000.0), 0.01, 1.0);
    assert!(matches!(end, Advance::Touchdown(_)), "{end:?}");
    assert!(run.touchdown.is_some());
    assert_ne!(run.slosh, before.slosh);
    assert_ne!(run.state, before.state);
    run.restore(&checkpoint);
    assert_eq!(run, before);
}
