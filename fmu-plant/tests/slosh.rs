//! Propellant slosh (docs/plant-slosh.md): the pendulum oscillates at the documented
//! frequency while the lander flies at constant thrust.
use fmu_plant::physics::parameters::PlantParameters;
use fmu_plant::physics::plant::{Advance, Commands, Plant};
use fmu_plant::physics::slosh::pendulum;

const THRUST_N: f64 = 1400.0;

/// Period of tank 1's x displacement from its zero crossings over `seconds`, s, and the
/// largest rate the body picked up.
fn measured_period(delta0: [f64; 4], seconds: f64) -> (f64, f64) {
    let mut p = PlantParameters {
        isp_s: 1e15,
        ..Default::default()
    };
    p.slosh.enabled = true;
    p.slosh.delta0_m = delta0;
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    let c = Commands {
        thrust_cmd_n: THRUST_N,
        ..Default::default()
    };
    let h = 0.01;
    let mut crossings = Vec::new();
    let mut previous = run.slosh.0[0];
    let mut omega_max: f64 = 0.0;
    for k in 0..(seconds / h) as usize {
        assert_eq!(
            plant.advance(&mut run, &c, k as f64 * h, h),
            Advance::Reached
        );
        let now = run.slosh.0[0];
        if previous > 0.0 && now <= 0.0 || previous < 0.0 && now >= 0.0 {
            // Linear interpolation inside the step.
            crossings.push(k as f64 * h + h * previous / (previous - now));
        }
        previous = now;
        omega_max = omega_max.max(run.state.omega_body.norm());
    }
    let n = crossings.len();
    assert!(n >= 8, "{n} crossings");
    let half_periods = (n - 1) as f64;
    (
        2.0 * (crossings[n - 1] - crossings[0]) / half_periods,
        omega_max,
    )
}

fn documented(coupled: bool) -> f64 {
    let p = PlantParameters::default().slosh;
    let (length, m1) = pendulum(p.tank_radius_m[0], p.fill_height_m[0], p.liquid_mass_kg[0]);
    let m = 900.0;
    let g_eff = THRUST_N / m;
    // Tank fixed (SP-106): omega^2 = g_eff / L; the in-phase mode of two equal tanks on a
    // free vehicle: omega^2 = (g_eff / L) m / (m - 2 m_1).
    let omega2 = if coupled {
        g_eff / length * m / (m - 2.0 * m1)
    } else {
        g_eff / length
    };
    let zeta = p.damping_ratio;
    2.0 * std::f64::consts::PI / (omega2.sqrt() * (1.0 - zeta * zeta).sqrt())
}

#[test]
fn tanks_sloshing_in_opposition_oscillate_at_the_pendulum_frequency_sqrt_g_eff_over_l() {
    let (period, omega_max) = measured_period([0.01, 0.0, -0.01, 0.0], 20.0);
    let expected = documented(false);
    println!("opposed: period {period:.6} s, 2 pi / sqrt(g_eff / L) = {expected:.6} s");
    assert!(
        (period / expected - 1.0).abs() < 0.01,
        "{period} vs {expected}"
    );
    assert!(
        omega_max < 1e-12,
        "no torque from x-sloshing at hinges on the x axis"
    );
}

#[test]
fn tanks_sloshing_together_oscillate_at_the_coupled_frequency() {
    let (period, _) = measured_period([0.01, 0.0, 0.01, 0.0], 20.0);
    let expected = documented(true);
    println!("together: period {period:.6} s, coupled 2 pi / omega_c = {expected:.6} s");
    assert!(
        (period / expected - 1.0).abs() < 0.01,
        "{period} vs {expected}"
    );
    assert!(
        (period / documented(false) - 1.0).abs() > 0.05,
        "the coupling is visible"
    );
}

#[test]
fn without_slosh_the_pendulums_stay_at_rest_and_the_run_is_the_old_one() {
    let p = PlantParameters::default();
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    let c = Commands {
        thrust_cmd_n: THRUST_N,
        ..Default::default()
    };
    plant.advance(&mut run, &c, 0.0, 0.01);
    assert_eq!(run.slosh.0, [0.0; 8]);
    assert!(plant.slosh.is_none());
}

#[test]
fn the_accelerometer_of_the_rigid_part_feels_the_sloshing_masses() {
    // GIVEN both tanks displaced 1 cm along body x at rest, under 1400 N
    let mut p = PlantParameters::default();
    p.slosh.enabled = true;
    p.slosh.delta0_m = [0.01, 0.0, 0.01, 0.0];
    let (plant, run, _) = Plant::new(&p).unwrap();
    let c = Commands {
        thrust_cmd_n: THRUST_N,
        ..Default::default()
    };
    let d = plant.delivered_run(&run, &c, &[false; 8], false);
    // THEN the lateral specific force is sum m_1 (g_eff / L) delta / (m - sum m_1)
    let (length, m1) = pendulum(0.4, 0.4, 150.0);
    let g_eff = THRUST_N / 900.0;
    let expected = 2.0 * m1 * g_eff / length * 0.01 / (900.0 - 2.0 * m1);
    let a = d.specific_force_body_mps2;
    assert!((a.x - expected).abs() < 1e-12, "{} vs {expected}", a.x);
    assert_eq!(a.y, g_eff);
}
