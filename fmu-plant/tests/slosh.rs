//! Propellant slosh (docs/plant-slosh.md): rigid body and pendulums as one mechanical
//! system, flown at constant thrust with no control. Periods against the linearised modes
//! and the exact nonlinear pendulum; energy and angular momentum without damping.
use fmu_plant::physics::frames::{body_to_nue, Body};
use fmu_plant::physics::parameters::PlantParameters;
use fmu_plant::physics::plant::{Advance, Commands, Plant, PlantRun};
use fmu_plant::physics::slosh::pendulum;
use fmu_plant::physics::slosh_dynamics::bob;
use nalgebra::Vector3;

const THRUST_N: f64 = 1400.0;
const STEP_S: f64 = 0.01;

/// The defaults with slosh on, no damping, no mass flow, tank k's initial displacement
/// `delta0` and hinges `hinges` (None: the defaults).
fn parameters(delta0: [f64; 4], hinges: Option<[f64; 6]>) -> PlantParameters {
    let mut p = PlantParameters {
        isp_s: 1e15,
        ..Default::default()
    };
    p.slosh.enabled = true;
    p.slosh.damping_ratio = 0.0;
    p.slosh.delta0_m = delta0;
    if let Some(h) = hinges {
        p.slosh.hinge_body_m = h;
    }
    p
}

fn thrust() -> Commands {
    Commands {
        thrust_cmd_n: THRUST_N,
        ..Default::default()
    }
}

/// Flies `seconds` and hands each state to `each`.
fn fly(p: &PlantParameters, seconds: f64, mut each: impl FnMut(f64, &Plant, &PlantRun)) {
    let (plant, mut run, _) = Plant::new(p).unwrap();
    each(0.0, &plant, &run);
    for k in 0..(seconds / STEP_S).round() as usize {
        let t = k as f64 * STEP_S;
        assert_eq!(
            plant.advance(&mut run, &thrust(), t, STEP_S),
            Advance::Reached
        );
        each(t + STEP_S, &plant, &run);
    }
}

/// Period of element `i` of the pendulum state (tank k's direction at 6k..6k + 3) from its zero crossings (linear
/// interpolation within the step; the signal's curvature vanishes at a crossing).
fn period(p: &PlantParameters, i: usize, seconds: f64) -> f64 {
    let mut crossings = Vec::new();
    let mut previous: Option<(f64, f64)> = None;
    fly(p, seconds, |t, _, run| {
        let now = run.slosh.0[i];
        if let Some((t0, v0)) = previous {
            if v0 > 0.0 && now <= 0.0 || v0 < 0.0 && now >= 0.0 {
                crossings.push(t0 + (t - t0) * v0 / (v0 - now));
            }
        }
        previous = Some((t, now));
    });
    let n = crossings.len();
    assert!(n >= 8, "{n} crossings");
    2.0 * (crossings[n - 1] - crossings[0]) / (n - 1) as f64
}

fn g_eff() -> f64 {
    THRUST_N / 900.0
}

fn default_pendulum() -> (f64, f64) {
    pendulum(0.4, 0.4, 150.0)
}

/// The energy in the frame of the centre of mass (kinetic relative to it, plus the thrust's
/// potential `F . (r_cm - r_O)`, valid while the thrust keeps its direction) and the
/// angular momentum about the centre of mass along the thrust axis.
fn energy_and_momentum(plant: &Plant, run: &PlantRun) -> (f64, f64) {
    let slosh = plant.slosh.as_ref().unwrap();
    let x = &run.state;
    let pendulums = slosh.pendulums_at(x.mass_kg);
    let (r_o, v_o) = plant.translation.to_nue(&x.translation);
    let (r_o, v_o) = (r_o.0, v_o.0);
    let w = x.omega_body.0;
    let to_nue = |v: Vector3<f64>| body_to_nue(&x.q_body_to_nue, &Body(v)).0;
    let mut points = vec![(x.mass_kg - slosh.total_mass_kg, r_o, v_o)];
    for (k, p) in pendulums.iter().enumerate() {
        let b = bob(p, &run.slosh, k);
        points.push((
            p.mass_kg,
            r_o + to_nue(b.position_body_m),
            v_o + to_nue(w.cross(&b.position_body_m) + b.velocity_body_mps),
        ));
    }
    let m: f64 = points.iter().map(|(m, _, _)| m).sum();
    let r_cm = points.iter().map(|(m, r, _)| r * *m).sum::<Vector3<f64>>() / m;
    let v_cm = points.iter().map(|(m, _, v)| v * *m).sum::<Vector3<f64>>() / m;
    let inertia = plant.inertia_body_kgm2;
    let kinetic = 0.5 * w.dot(&inertia.component_mul(&w))
        + points
            .iter()
            .map(|(m, _, v)| 0.5 * m * (v - v_cm).norm_squared())
            .sum::<f64>();
    let force = to_nue(Vector3::new(0.0, THRUST_N, 0.0));
    let axis = force.normalize();
    let momentum = to_nue(inertia.component_mul(&w))
        + points
            .iter()
            .map(|(m, r, v)| (r - r_cm).cross(&(v - v_cm)) * *m)
            .sum::<Vector3<f64>>();
    (kinetic + force.dot(&(r_cm - r_o)), momentum.dot(&axis))
}

#[test]
fn tanks_sloshing_in_opposition_about_the_thrust_axis_turn_the_body_at_the_coupled_frequency() {
    // GIVEN the default tanks (hinges 0.6 m either side on body x, rigid I_yy = 300 kg m^2)
    // displaced 2 mm in opposite directions along body z
    let p = parameters([0.0, 0.002, 0.0, -0.002], None);
    let period = period(&p, 2, 20.0);
    // THEN the body turns against the propellant: omega^2 (1 + 2 m_1 x^2 / I_yy)
    let (length, m1) = default_pendulum();
    let omega2 = g_eff() / length * (1.0 + 2.0 * m1 * 0.36 / 300.0);
    let expected = 2.0 * std::f64::consts::PI / omega2.sqrt();
    let tank_fixed = 2.0 * std::f64::consts::PI / (g_eff() / length).sqrt();
    println!("opposed about y: period {period:.6} s, coupled {expected:.6} s, tank fixed {tank_fixed:.6} s");
    assert!((expected - 2.2400).abs() < 5e-5, "{expected}");
    assert!(
        (period / expected - 1.0).abs() < 2e-5,
        "{period} vs {expected}"
    );
}

#[test]
fn tanks_sloshing_together_oscillate_at_the_free_vehicle_frequency() {
    // GIVEN hinges at the centre of mass's height (no pitch at first order), both masses
    // displaced 2 mm along body x
    let hinges = [0.6, 0.0, 0.0, -0.6, 0.0, 0.0];
    let p = parameters([0.002, 0.0, 0.002, 0.0], Some(hinges));
    let period = period(&p, 0, 20.0);
    // THEN the rigid part moves against them: omega^2 m / (m - 2 m_1)
    let (length, m1) = default_pendulum();
    let expected =
        2.0 * std::f64::consts::PI / (g_eff() / length * 900.0 / (900.0 - 2.0 * m1)).sqrt();
    println!("together: period {period:.6} s, coupled {expected:.6} s");
    assert!(
        (period / expected - 1.0).abs() < 2e-5,
        "{period} vs {expected}"
    );
}

/// The exact period of two equal pendulums hung from one hinge on a free body, swinging
/// mirror-symmetrically from `theta0`: with `eps = 2 m_1 / m` the Lagrangian in the centre of
/// mass's frame is `m_1 L^2 theta'^2 (1 - eps sin^2 theta) + 2 m_1 g_eff L cos theta`, so
/// `T = 4 sqrt(L / g_eff) int_0^(pi/2) sqrt(1 - eps sin^2 theta) / sqrt(1 - k^2 sin^2 phi)
/// d phi` with `sin(theta / 2) = k sin phi`, `k = sin(theta0 / 2)` (eps = 0: 4 K(k)).
fn nonlinear_period(length: f64, theta0: f64, eps: f64) -> f64 {
    let k = libm::sin(theta0 / 2.0);
    let n = 20_000;
    let h = std::f64::consts::FRAC_PI_2 / n as f64;
    let f = |phi: f64| {
        let (s, ks) = (
            libm::sin(2.0 * libm::asin(k * libm::sin(phi))),
            k * libm::sin(phi),
        );
        (1.0 - eps * s * s).sqrt() / (1.0 - ks * ks).sqrt()
    };
    // Simpson's rule.
    let mut sum = f(0.0) + f(std::f64::consts::FRAC_PI_2);
    for i in 1..n {
        sum += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    4.0 * (length / g_eff()).sqrt() * sum * h / 3.0
}

#[test]
fn a_large_swing_has_the_nonlinear_pendulums_period() {
    // GIVEN both pendulums hung from one point and swung 0.8 L apart along body x
    // (53 deg): no turn, no lateral motion, only the axial exchange with the body
    let (length, m1) = default_pendulum();
    let a = 0.8 * length;
    let p = parameters([a, 0.0, -a, 0.0], Some([0.0; 6]));
    let period = period(&p, 0, 30.0);
    let theta0 = libm::asin(0.8);
    let expected = nonlinear_period(length, theta0, 2.0 * m1 / 900.0);
    let linear = 2.0 * std::f64::consts::PI * (length / g_eff()).sqrt();
    println!("0.8 L: period {period:.6} s, exact {expected:.6} s, small-angle {linear:.6} s");
    assert!(
        (period / expected - 1.0).abs() < 2e-5,
        "{period} vs {expected}"
    );
    assert!(period / linear > 1.025, "the swing is visibly nonlinear");
}

#[test]
fn without_damping_energy_and_angular_momentum_about_the_thrust_axis_are_conserved() {
    // GIVEN the default tanks swung 15 cm (0.66 L) in opposition about the thrust axis
    let p = parameters([0.0, 0.15, 0.0, -0.15], None);
    let mut first = None;
    let (mut de, mut dh, mut swing_e, mut w_max, mut e_max) = (0.0f64, 0.0f64, 0.0, 0.0f64, 0.0f64);
    let mut e_min = f64::INFINITY;
    fly(&p, 20.0, |_, plant, run| {
        let (e, h) = energy_and_momentum(plant, run);
        let (e0, h0) = *first.get_or_insert((e, h));
        de = de.max((e - e0).abs());
        dh = dh.max((h - h0).abs());
        w_max = w_max.max(run.state.omega_body.0.y.abs());
        e_max = e_max.max(e);
        e_min = e_min.min(e);
        swing_e = e0;
    });
    let scale_h = 300.0 * w_max;
    println!(
        "energy {swing_e:.6} J, largest drift {de:.3e} J; momentum largest drift {dh:.3e} kg m^2/s \
         against I w_max = {scale_h:.4}"
    );
    // THEN both stay at their start to RK4's accuracy: on an oscillation at w its
    // amplification factor loses (w h)^6 / 72 of the energy per step; at the coupled mode's
    // w = 2.805 rad/s (the slowest swing only loses less) over 2000 steps of 10 ms, 1.35e-8
    let w = 2.0 * std::f64::consts::PI / 2.24;
    let wh2 = (w * STEP_S) * (w * STEP_S);
    let bound = 2000.0 * wh2 * wh2 * wh2 / 72.0;
    println!("RK4 bound {bound:.3e} of each");
    assert!(w_max > 0.05, "the body turns: {w_max}");
    assert!(de < 2.0 * bound * swing_e.abs(), "{de} of {swing_e}");
    assert!(dh < 2.0 * bound * scale_h, "{dh} against {scale_h}");
    assert!(e_max - e_min < 2.0 * bound * swing_e.abs());
}

#[test]
fn without_slosh_the_pendulums_stay_at_rest_and_the_run_is_the_old_one() {
    let p = PlantParameters::default();
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    plant.advance(&mut run, &thrust(), 0.0, 0.01);
    assert_eq!(run.slosh.0, [0.0; 12]);
    assert!(plant.slosh.is_none());
}

#[test]
fn the_accelerometer_of_the_rigid_part_feels_the_sloshing_masses() {
    // GIVEN both tanks displaced 1 cm along body x at rest, under 1400 N, hinges at the
    // centre of mass's height
    let mut p = parameters(
        [0.01, 0.0, 0.01, 0.0],
        Some([0.6, 0.0, 0.0, -0.6, 0.0, 0.0]),
    );
    p.slosh.damping_ratio = 0.005;
    let (plant, run, _) = Plant::new(&p).unwrap();
    let d = plant.delivered_run(&run, &thrust(), &[false; 8], false);
    // THEN the lateral specific force is sum m_1 (g_eff / L) delta / (m - sum m_1) to first
    // order in delta / L = 0.044 (the rod's tilt and the masses' axial give-way second)
    let (length, m1) = default_pendulum();
    let expected = 2.0 * m1 * g_eff() / length * 0.01 / (900.0 - 2.0 * m1);
    let a = d.specific_force_body_mps2;
    assert!((a.x / expected - 1.0).abs() < 3e-3, "{} vs {expected}", a.x);
    assert!((a.y / g_eff() - 1.0).abs() < 3e-3, "{} vs {}", a.y, g_eff());
}

#[test]
fn tanks_sloshing_together_below_raised_hinges_pitch_the_body_at_the_coupled_frequency() {
    // GIVEN the default tanks, hinges y_h above the centre of mass, the masses y_b = y_h - L
    // The linearised in-phase motion along body x: q = (X lateral position, theta pitch about
    // z, delta both masses), thrust F following the body (a lateral -F theta), s = F / m:
    //   m X'' - 2 m_1 y_b theta'' + 2 m_1 delta'' + F theta = 0
    //   X'' - y_b theta'' + delta'' + s theta + (s / L) delta = 0    (each pendulum)
    //   -2 m_1 y_b X'' + (I_zz + 2 m_1 (a^2 + y_b^2)) theta'' - 2 m_1 y_b delta''
    //       - 2 m_1 s y_b theta + 2 m_1 s delta = 0                  (moment about O)
    let (length, m1) = default_pendulum();
    let y_h = PlantParameters::default().slosh.hinge_body_m[1];
    let (m, f, a, izz) = (900.0, THRUST_N, 0.6, 450.0);
    let (s, y_b) = (f / m, y_h - length);
    let mass = nalgebra::Matrix3::new(
        m,
        -2.0 * m1 * y_b,
        2.0 * m1,
        1.0,
        -y_b,
        1.0,
        -2.0 * m1 * y_b,
        izz + 2.0 * m1 * (a * a + y_b * y_b),
        -2.0 * m1 * y_b,
    );
    let stiffness = nalgebra::Matrix3::new(
        0.0,
        f,
        0.0,
        0.0,
        s,
        s / length,
        0.0,
        -2.0 * m1 * s * y_b,
        2.0 * m1 * s,
    );
    // One root is the pendulum's; the other two are zero: with the thrust through O nothing
    // restores pitch or translation (no control flies here)
    let lambdas = (mass.try_inverse().unwrap() * stiffness).complex_eigenvalues();
    let lambda = lambdas.iter().map(|l| l.re).fold(0.0, f64::max);
    assert!(lambdas.iter().all(|l| l.im.abs() < 1e-12));
    assert_eq!(
        lambdas.iter().filter(|l| l.re.abs() < 1e-9).count(),
        2,
        "{lambdas:?}"
    );
    // WHEN both masses start 2 mm along body x
    let p = parameters([0.002, 0.0, 0.002, 0.0], None);
    let period = period(&p, 0, 20.0);
    let mut pitch: f64 = 0.0;
    fly(&p, 2.0, |_, _, run| {
        pitch = pitch.max(run.state.omega_body.0.z.abs())
    });
    // THEN the masses swing at the coupled root, and the body pitches with them
    let expected = 2.0 * std::f64::consts::PI / lambda.sqrt();
    let tank_fixed = 2.0 * std::f64::consts::PI / (g_eff() / length).sqrt();
    println!(
        "together, raised hinges: period {period:.6} s, coupled {expected:.6} s, tank fixed \
         {tank_fixed:.6} s; pitch rate up to {pitch:.2e} rad/s in 2 s"
    );
    assert!(
        (period / expected - 1.0).abs() < 2e-5,
        "{period} vs {expected}"
    );
    assert!(pitch > 1e-5, "{pitch}");
}

#[test]
fn a_tumbling_lander_swings_the_propellant_over_its_hinges_and_stays_finite() {
    // GIVEN a lander tumbling at 3 rad/s about body z under thrust: omega^2 r across the
    // 0.6 m arm is 3.5 times g_eff, more than enough to lift the masses over their hinges
    let mut p = parameters([0.0; 4], None);
    p.omega0_body_radps = Vector3::new(0.0, 0.0, 3.0);
    let mut largest: f64 = 0.0;
    fly(&p, 20.0, |_, plant, run| {
        let slosh = plant.slosh.as_ref().unwrap();
        largest = largest.max(slosh.largest_swing(&run.slosh, run.state.mass_kg));
        // THEN every state is finite and each direction a unit vector
        assert!(run.state.is_finite() && run.slosh.0.iter().all(|v| v.is_finite()));
        for k in 0..2 {
            assert!((run.slosh.direction(k).norm() - 1.0).abs() < 1e-12);
        }
    });
    println!("largest swing {:.1} deg", largest.to_degrees());
    assert!(largest > std::f64::consts::FRAC_PI_2, "{largest}");
}

#[test]
fn with_damping_the_energy_only_falls() {
    // GIVEN the opposed swing of the conservation test with the default damping ratio 0.005
    let mut p = parameters([0.0, 0.15, 0.0, -0.15], None);
    p.slosh.damping_ratio = 0.005;
    let (mut first, mut last, mut rise) = (None, f64::INFINITY, 0.0f64);
    fly(&p, 20.0, |_, plant, run| {
        let (e, _) = energy_and_momentum(plant, run);
        first.get_or_insert(e);
        rise = rise.max(e - last);
        last = e;
    });
    let e0 = first.unwrap();
    println!("energy {e0:.4} J -> {last:.4} J, largest step-to-step rise {rise:.2e} J");
    // THEN the damping pair between mass and tank dissipates: the energy falls step by step
    // (less than exp(-2 zeta w t) would: part of the swing's energy is the body's turn, which
    // the damper between mass and tank does not see) and never rises by more than RK4's
    // error
    assert!(last < 0.9 * e0 && last > 0.5 * e0, "{last} of {e0}");
    assert!(rise < 1e-7 * e0, "{rise}");
}
