//! The thruster model of the RCS against analytic results and against the torque model.
use fmu_plant::physics::parameters::{PlantParameters, RcsModelKind};
use fmu_plant::physics::plant::{Advance, Commands, Plant, PlantRun};
use fmu_plant::physics::rigid_body::{angular_momentum_nue, rotational_energy};
use nalgebra::Vector3;

const G: f64 = 1.62;

fn thruster_model() -> PlantParameters {
    PlantParameters {
        rcs_model: RcsModelKind::Thrusters as i32,
        ..Default::default()
    }
}

fn start(p: &PlantParameters) -> (Plant, PlantRun) {
    let (plant, run, _) = Plant::new(p).expect("valid parameters");
    (plant, run)
}

fn step(plant: &Plant, run: &mut PlantRun, cmd: &Commands, duty: &[f64; 8], t: f64, h: f64) {
    assert_eq!(
        plant.advance_with_duty(run, cmd, duty, t, h),
        Advance::Reached
    );
}

fn only(k: usize, duty: f64) -> [f64; 8] {
    std::array::from_fn(|i| if i == k { duty } else { 0.0 })
}

#[test]
fn torque_free_tumbling_is_unchanged_with_zero_duty() {
    // GIVEN a lander tumbling about all three axes, engines off, in both RCS models
    let tumbling = |p: PlantParameters| PlantParameters {
        omega0_body_radps: Vector3::new(0.3, -0.7, 0.5),
        r0_nue_m: Vector3::new(0.0, 5000.0, 0.0),
        ..p
    };
    let (torque_plant, mut torque_run) = start(&tumbling(PlantParameters::default()));
    let (thruster_plant, mut thruster_run) = start(&tumbling(thruster_model()));
    let off = Commands::default();
    let inertia = thruster_plant.inertia_body_kgm2;
    let h0 = angular_momentum_nue(
        &inertia,
        &thruster_run.state.q_body_to_nue,
        &thruster_run.state.omega_body,
    );
    let e0 = rotational_energy(&inertia, &thruster_run.state.omega_body);
    // WHEN both fly 20 s, the thruster model with every duty 0
    for k in 0..2000 {
        let t = k as f64 * 0.01;
        torque_plant.advance(&mut torque_run, &off, t, 0.01);
        step(&thruster_plant, &mut thruster_run, &off, &[0.0; 8], t, 0.01);
    }
    // THEN the trajectories are bit-identical and the torque-free invariants hold
    assert_eq!(thruster_run.state, torque_run.state);
    let x = &thruster_run.state;
    let h1 = angular_momentum_nue(&inertia, &x.q_body_to_nue, &x.omega_body);
    assert!((h1 - h0).norm() < 1e-9 * h0.norm(), "{h0:?} -> {h1:?}");
    let e1 = rotational_energy(&inertia, &x.omega_body);
    assert!((e1 - e0).abs() < 1e-9 * e0, "{e0} -> {e1}");
}

#[test]
fn a_single_pulse_gives_the_analytic_changes_of_angular_and_linear_velocity() {
    // GIVEN the lander at rest, upright, engines off; thruster 1 sits at (1, 0, 0) m and
    // pushes along body +y: torque (0, 0, F) about the pitch axis alone (no gyroscopic term)
    let p = thruster_model();
    let (plant, mut run) = start(&p);
    let (f, m, izz) = (58.0, p.m0_kg, p.inertia_body_kgm2.z);
    // WHEN it fires for 37.3 % of a 0.1 s step (the pulse ends inside an RK4 sub-step)
    let h = 0.1;
    let t_on = 0.373 * h;
    step(
        &plant,
        &mut run,
        &Commands::default(),
        &only(0, 0.373),
        0.0,
        h,
    );
    // THEN delta omega = I^-1 (r x F) t_on, exactly up to round-off
    let omega = run.state.omega_body.0;
    let expected = f * t_on / izz;
    assert!(
        (omega.z - expected).abs() < 1e-14,
        "{} vs {expected}",
        omega.z
    );
    assert_eq!((omega.x, omega.y), (0.0, 0.0));
    // AND delta v = F t_on / m along the thrust direction plus the free fall over h. The body
    // turns by alpha t_on^2 / 2 = 9e-5 rad meanwhile, which tilts the impulse by that much.
    let v = plant.translation.to_nue(&run.state.translation).1 .0;
    let impulse = f * t_on / m;
    let turned = 0.5 * f / izz * t_on * t_on;
    assert!((v.y - (impulse - G * h)).abs() < 1e-8 * impulse, "{v}");
    assert!(v.x.abs() < impulse * turned && v.x < 0.0, "{v}");
    assert_eq!(run.state.mass_kg, m, "the RCS propellant is not booked");
}

#[test]
fn the_pulse_end_is_integrated_exactly_whatever_the_sub_step() {
    // GIVEN the same pulse integrated with 10 ms and with 1 ms sub-steps
    let run_with = |integration_step_s| {
        let p = PlantParameters {
            integration_step_s,
            ..thruster_model()
        };
        let (plant, mut run) = start(&p);
        step(
            &plant,
            &mut run,
            &Commands::default(),
            &only(4, 0.373),
            0.0,
            0.1,
        );
        run.state.omega_body.0
    };
    // THEN the rates agree to round-off (a pulse smeared over a sub-step would differ by
    // up to a tenth of the impulse)
    let (coarse, fine) = (run_with(0.01), run_with(0.001));
    assert!(
        (coarse - fine).norm() < 1e-12 * fine.norm(),
        "{coarse} vs {fine}"
    );
}

#[test]
fn pulses_below_the_minimum_impulse_bit_are_not_fired_unless_they_continue_one() {
    // GIVEN the default bit, 0.29 N s = 5 ms at 58 N
    let p = thruster_model();
    let (plant, mut run) = start(&p);
    let h = 0.01;
    let cmd = Commands::default();
    // WHEN a 4 ms pulse is asked for
    step(&plant, &mut run, &cmd, &only(0, 0.4), 0.0, h);
    // THEN nothing fires
    assert_eq!(run.state.omega_body.0, Vector3::zeros());
    // WHEN it fires a full step and then 4 ms more
    step(&plant, &mut run, &cmd, &only(0, 1.0), h, h);
    step(&plant, &mut run, &cmd, &only(0, 0.4), 2.0 * h, h);
    // THEN the 4 ms continue the pulse: 14 ms in all
    let expected = 58.0 * 0.014 / p.inertia_body_kgm2.z;
    assert!((run.state.omega_body.0.z - expected).abs() < 1e-14);
}

#[test]
fn a_full_step_couple_matches_the_torque_model_at_its_limit() {
    // GIVEN both models, engines at hover thrust, a 116 N m pitch couple for 2 s
    let (torque_plant, mut torque_run) = start(&PlantParameters::default());
    let (thruster_plant, mut thruster_run) = start(&thruster_model());
    let torque_cmd = Commands {
        thrust_cmd_n: 1458.0,
        torque_cmd_body_nm: Vector3::new(0.0, 0.0, 500.0),
    };
    let thrust_cmd = Commands {
        thrust_cmd_n: 1458.0,
        torque_cmd_body_nm: Vector3::zeros(),
    };
    let couple = [1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    for k in 0..200 {
        let t = k as f64 * 0.01;
        torque_plant.advance(&mut torque_run, &torque_cmd, t, 0.01);
        step(
            &thruster_plant,
            &mut thruster_run,
            &thrust_cmd,
            &couple,
            t,
            0.01,
        );
    }
    // THEN they agree to round-off: a couple has no net force
    let (a, b) = (&torque_run.state, &thruster_run.state);
    assert!(
        (a.omega_body - b.omega_body).norm() < 1e-12,
        "{} vs {}",
        a.omega_body.0,
        b.omega_body.0
    );
    assert!((a.translation - b.translation).norm() < 1e-9);
    assert!(b.omega_body.0.z > 0.5, "{}", b.omega_body.0);
}

#[test]
fn a_thruster_direction_that_is_not_a_unit_vector_is_refused_by_name() {
    let mut p = thruster_model();
    p.thrusters.direction_body[3 * 5 + 2] = -0.5;
    let e = p.check().unwrap_err();
    assert_eq!((e.field, e.index), ("thrusters.direction_body", Some(15)));
    // Elements 16..18 (1-based) are the sixth thruster's.
    assert!(e.reason.contains("thruster 6"), "{e}");
    let mut p = thruster_model();
    p.rcs_model = 3;
    assert_eq!(p.check().unwrap_err().field, "rcs_model");
}
