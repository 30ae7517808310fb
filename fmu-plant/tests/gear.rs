//! Analytic tests of the landing gear and terrain (docs/plant-gear.md), on the pure Rust API.
use fmu_plant::physics::gear::terrain_normal;
use fmu_plant::physics::parameters::PlantParameters;
use fmu_plant::physics::plant::{Advance, Commands, Plant, PlantRun};
use nalgebra::Vector3;

const G: f64 = 1.62;
const M: f64 = 900.0;
const K: f64 = 40_000.0;

fn geared() -> PlantParameters {
    let mut p = PlantParameters::default();
    p.gear.enabled = true;
    p
}

fn off() -> Commands {
    Commands::default()
}

/// Steps of `h` from `t0` for `n` steps; returns the end time. Calls `each` after every step.
fn fly(
    plant: &Plant,
    run: &mut PlantRun,
    commands: &Commands,
    t0: f64,
    h: f64,
    n: usize,
    mut each: impl FnMut(&PlantRun),
) -> f64 {
    for k in 0..n {
        let adv = plant.advance(run, commands, t0 + k as f64 * h, h);
        assert_eq!(adv, Advance::Reached, "stopped at step {k}: {adv:?}");
        each(run);
    }
    t0 + n as f64 * h
}

fn velocity(plant: &Plant, run: &PlantRun) -> Vector3<f64> {
    plant.translation.to_nue(&run.state.translation).1 .0
}

fn stroke(plant: &Plant, run: &PlantRun) -> [f64; 4] {
    plant.gear_status(run).unwrap().contact.stroke_m
}

#[test]
fn first_footpad_contact_is_the_touchdown_at_the_free_fall_time_and_the_run_goes_on() {
    // GIVEN the gear on, footpads 2 m above flat ground, engines off
    let mut p = geared();
    p.r0_nue_m.y = 3.0;
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    // WHEN falling for 10 s in 0.1 s steps
    fly(&plant, &mut run, &off(), 0.0, 0.1, 100, |_| {});
    // THEN the touchdown is recorded at sqrt(2 h / g) with the free-fall velocity
    let td = run.touchdown.expect("touchdown");
    let t_exact = (2.0 * 2.0 / G).sqrt();
    assert!(
        (td.time_s - t_exact).abs() < 1e-9,
        "{} vs {t_exact}",
        td.time_s
    );
    println!("td {:?}", td);
    assert!(
        (td.v_nue_mps.0.y + G * t_exact).abs() < 1e-8,
        "{:?} {}",
        td.v_nue_mps,
        G * t_exact
    );
    // AND the lander has come to rest on its legs, compressed by m g / (N k)
    let up = run.state.translation[1];
    assert!((up - (1.0 - M * G / (4.0 * K))).abs() < 1e-6, "{up}");
    assert!(plant.gear_status(&run).unwrap().settled);
}

#[test]
fn undamped_drop_compresses_the_legs_to_the_energy_balance() {
    // GIVEN an undamped gear, footpads h = 0.5 m above flat ground, engines off
    let h = 0.5;
    let mut p = geared();
    p.gear.damping_nspm = 0.0;
    p.r0_nue_m.y = 1.0 + h;
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    // WHEN dropping (sampled every 1 ms)
    let mut max_stroke: f64 = 0.0;
    fly(&plant, &mut run, &off(), 0.0, 0.001, 2000, |r| {
        max_stroke = max_stroke.max(stroke(&plant, r)[0]);
    });
    // THEN m g (h + s) = 1/2 N k s^2: s = (m g + sqrt((m g)^2 + 2 N k m g h)) / (N k)
    let (w, nk) = (M * G, 4.0 * K);
    let s = (w + (w * w + 2.0 * nk * w * h).sqrt()) / nk;
    println!("max stroke {max_stroke:.6} m, energy balance {s:.6} m");
    assert!((max_stroke / s - 1.0).abs() < 1e-3, "{max_stroke} vs {s}");
}

#[test]
fn settled_on_flat_ground_each_leg_carries_a_quarter_of_the_weight() {
    // GIVEN the default (damped) gear with its footpads on flat ground
    let mut p = geared();
    p.r0_nue_m.y = 1.0;
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    // WHEN left for 10 s
    fly(&plant, &mut run, &off(), 0.0, 0.01, 1000, |_| {});
    // THEN every stroke is m g / (N k) and the lander is settled
    let expected = M * G / (4.0 * K);
    let status = plant.gear_status(&run).unwrap();
    for s in status.contact.stroke_m {
        assert!((s / expected - 1.0).abs() < 1e-6, "{s} vs {expected}");
    }
    println!(
        "static stroke {:.9} m, m g / (N k) = {expected:.9} m",
        status.contact.stroke_m[0]
    );
    assert!(status.settled && !status.tipped_over);
    assert!(run.touchdown.is_some());
}

/// The lander standing on a plane of slope `slope` (falls towards North) with its body +y
/// along the normal and the footpads just touching, left for `seconds`; returns the downhill
/// velocity at the end and at 2 s before the end.
fn on_slope(slope_deg: f64, mu: f64, seconds: f64) -> (f64, f64, bool) {
    let slope = slope_deg.to_radians();
    let mut p = geared();
    p.gear.terrain_slope_rad = slope;
    p.gear.friction_coefficient = mu;
    let n = terrain_normal(slope, 0.0);
    p.r0_nue_m = n;
    let (s, c) = libm::sincos(-slope / 2.0);
    p.q0_body_to_nue = [c, 0.0, 0.0, s];
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    let downhill = Vector3::new(libm::cos(slope), -libm::sin(slope), 0.0);
    let t = fly(
        &plant,
        &mut run,
        &off(),
        0.0,
        0.01,
        ((seconds - 2.0) * 100.0) as usize,
        |_| {},
    );
    let v_before = velocity(&plant, &run).dot(&downhill);
    fly(&plant, &mut run, &off(), t, 0.01, 200, |_| {});
    let v_end = velocity(&plant, &run).dot(&downhill);
    (
        v_before,
        v_end,
        plant.gear_status(&run).unwrap().tipped_over,
    )
}

#[test]
fn below_the_friction_angle_the_lander_only_creeps_at_the_regularised_rate() {
    // GIVEN a 10 deg slope with mu = 0.5 (tan 10 deg = 0.176 < mu)
    let (mu, slope) = (0.5, 10f64);
    let (_, v, tipped) = on_slope(slope, mu, 8.0);
    // THEN it does not slide: the regularised friction mu N v / sqrt(v^2 + v_reg^2) balances
    // m g sin(slope) at the creep v = v_reg tan / sqrt(mu^2 - tan^2), 0.38 mm/s
    let tan = libm::tan(slope.to_radians());
    let creep = 1e-3 * tan / (mu * mu - tan * tan).sqrt();
    println!("downhill velocity {v:.3e} m/s, creep {creep:.3e} m/s");
    assert!((v / creep - 1.0).abs() < 0.02, "{v} vs {creep}");
    assert!(!tipped);
}

#[test]
fn above_the_friction_angle_the_lander_slides_at_g_sin_minus_mu_g_cos() {
    // GIVEN a 30 deg slope with mu = 0.5 (tan 30 deg = 0.577 > mu)
    let (mu, slope) = (0.5, 30f64.to_radians());
    let (v0, v1, tipped) = on_slope(30.0, mu, 6.0);
    // THEN it accelerates downhill at g (sin - mu cos)
    let a = (v1 - v0) / 2.0;
    let expected = G * (libm::sin(slope) - mu * libm::cos(slope));
    println!("sliding acceleration {a:.5} m/s2, g (sin - mu cos) = {expected:.5} m/s2");
    assert!((a / expected - 1.0).abs() < 0.01, "{a} vs {expected}");
    assert!(!tipped);
}

/// The lander tilted by `tilt_deg` about body z (the +x side down) on flat ground with its two
/// lower footpads just touching, left for 10 s; whether it tipped over, and its state.
fn tilted(tilt_deg: f64) -> (bool, bool) {
    let tilt = tilt_deg.to_radians();
    let mut p = geared();
    let (s, c) = libm::sincos(-tilt / 2.0);
    p.q0_body_to_nue = [c, 0.0, 0.0, s];
    let d = 1.2 * std::f64::consts::FRAC_1_SQRT_2;
    p.r0_nue_m.y = d * libm::sin(tilt) + libm::cos(tilt);
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    for k in 0..1000 {
        match plant.advance(&mut run, &off(), k as f64 * 0.01, 0.01) {
            Advance::Reached => {}
            Advance::Touchdown(_) => break,
        }
    }
    let status = plant.gear_status(&run).unwrap();
    (status.tipped_over, status.settled)
}

#[test]
fn tilted_beyond_the_static_stability_angle_it_tips_over_and_below_it_rights_itself() {
    // The default footprint: atan(0.8485 / 1.0) = 40.3 deg
    let (plant, _, _) = Plant::new(&geared()).unwrap();
    let limit = plant.gear.unwrap().static_stability_angle_rad.to_degrees();
    assert!((limit - 40.31).abs() < 0.01, "{limit}");
    let (tipped, _) = tilted(limit + 2.0);
    assert!(tipped, "tilted {} deg", limit + 2.0);
    let (tipped, settled) = tilted(limit - 2.0);
    assert!(!tipped && settled, "tilted {} deg", limit - 2.0);
}

#[test]
fn the_engine_cut_off_fires_at_first_contact_or_at_the_set_height() {
    // GIVEN a descent at 1 m/s under exactly m g with no mass flow, footpads 2 m up
    for (mode, height) in [(1, 0.0), (2, 0.5)] {
        let mut p = geared();
        p.isp_s = 1e15;
        p.v0_nue_mps.y = -1.0;
        p.r0_nue_m.y = 3.0;
        p.gear.engine_cutoff_mode = mode;
        p.gear.engine_cutoff_height_m = height;
        let (plant, mut run, _) = Plant::new(&p).unwrap();
        let hover = Commands {
            thrust_cmd_n: M * G,
            ..Default::default()
        };
        // WHEN flying 1.2 s past the cut-off's time (2 - height) s
        let t_cut = 2.0 - height;
        let t_end = t_cut + 0.2;
        fly(
            &plant,
            &mut run,
            &hover,
            0.0,
            0.01,
            (t_end * 100.0).round() as usize,
            |_| {},
        );
        // THEN the engines were cut at it: v = -1 - g (t - t_cut) (mode 2 still in flight)
        assert!(run.gear.engine_cut, "mode {mode}");
        let d = plant.delivered(&run.state, &hover, plant.engines_cut(&run));
        assert_eq!(d.thrust_n, 0.0);
        if mode == 2 {
            let v = velocity(&plant, &run).y;
            let expected = -1.0 - G * (t_end - t_cut);
            assert!((v - expected).abs() < 1e-9, "{v} vs {expected}");
        }
    }
}

#[test]
fn the_accelerometer_reads_the_gear_force_at_rest() {
    // GIVEN the lander settled on flat ground
    let mut p = geared();
    p.r0_nue_m.y = 1.0;
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    fly(&plant, &mut run, &off(), 0.0, 0.01, 1000, |_| {});
    // THEN the specific force is g along body +y (the ground holds the weight)
    let d = plant.delivered(&run.state, &off(), false);
    assert!((d.specific_force_body_mps2 - Vector3::new(0.0, G, 0.0)).norm() < 1e-6);
}

/// The lander settled on flat ground given a lateral velocity `v` along North with footpad
/// friction `mu`, left for 6 s; whether it tipped over.
fn pushed(v: f64, mu: f64) -> bool {
    let mut p = geared();
    p.gear.friction_coefficient = mu;
    p.r0_nue_m.y = 1.0 - M * G / (4.0 * K);
    p.v0_nue_mps.x = v;
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    for k in 0..600 {
        if plant.advance(&mut run, &off(), k as f64 * 0.01, 0.01) != Advance::Reached {
            break;
        }
    }
    plant.gear_status(&run).unwrap().tipped_over
}

#[test]
fn a_lateral_velocity_above_the_pivot_threshold_tips_the_lander_and_below_it_does_not() {
    // The footpads grip (mu = 3) and the lander pivots about its leading edge (d = 0.8485 m
    // ahead of the centre of mass, h = 1 m below it): angular momentum about the edge
    // m v h = I_e w with I_e = I_zz + m (d^2 + h^2), and it goes over iff 1/2 I_e w^2 exceeds
    // m g (sqrt(d^2 + h^2) - h): v_crit = sqrt(2 m g (L - h) I_e) / (m h) = 1.497 m/s.
    let (d, h) = (1.2 * std::f64::consts::FRAC_1_SQRT_2, 1.0);
    let l = (d * d + h * h).sqrt();
    let i_edge = 450.0 + M * l * l;
    let v_crit = (2.0 * M * G * (l - h) * i_edge).sqrt() / (M * h);
    assert!((v_crit - 1.4968).abs() < 1e-3, "{v_crit}");
    // The compliant legs put the model's threshold between 1.0 and 1.1 v_crit.
    assert!(!pushed(0.9 * v_crit, 3.0), "0.9 v_crit");
    assert!(pushed(1.1 * v_crit, 3.0), "1.1 v_crit");
}
