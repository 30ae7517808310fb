//! The specific force (what an accelerometer at the centre of mass measures), on the pure
//! Rust API and through the FMI variable table.
use fmu_plant::physics::parameters::{PlantParameters, RcsModelKind};
use fmu_plant::physics::plant::{Advance, Commands, Plant};
use fmu_plant::physics::thrusters::NONE_FIRING;
use nalgebra::Vector3;

fn thrust(n: f64) -> Commands {
    Commands {
        thrust_cmd_n: n,
        torque_cmd_body_nm: Vector3::zeros(),
    }
}

#[test]
fn hovering_at_constant_thrust_the_accelerometer_reads_t_over_m_along_plus_y() {
    // GIVEN the default lander at a constant 1400 N, tilted 20 deg about body z
    let (s, c) = libm::sincos(10f64.to_radians());
    let p = PlantParameters {
        q0_body_to_nue: [c, 0.0, 0.0, s],
        ..Default::default()
    };
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    let commands = thrust(1400.0);
    for k in 0..500 {
        assert_eq!(
            plant.advance(&mut run, &commands, k as f64 * 0.01, 0.01),
            Advance::Reached
        );
        // THEN at every step the specific force is T / m along body +y, whatever the attitude
        let d = plant.delivered(&run.state, &commands, false);
        let expected = Vector3::new(0.0, 1400.0 / run.state.mass_kg, 0.0);
        assert!(
            (d.specific_force_body_mps2 - expected).norm() <= 1e-15 * expected.norm(),
            "{} vs {expected}",
            d.specific_force_body_mps2
        );
    }
}

#[test]
fn in_free_fall_the_accelerometer_reads_zero() {
    let (plant, mut run, _) = Plant::new(&PlantParameters::default()).unwrap();
    for k in 0..300 {
        plant.advance(&mut run, &thrust(0.0), k as f64 * 0.01, 0.01);
        let d = plant.delivered(&run.state, &thrust(0.0), false);
        assert_eq!(d.specific_force_body_mps2, Vector3::zeros());
    }
}

#[test]
fn the_thruster_models_force_is_part_of_the_specific_force() {
    // GIVEN the thruster model with thruster 5 (+z force, 58 N) firing and the engines off
    let p = PlantParameters {
        rcs_model: RcsModelKind::Thrusters as i32,
        ..Default::default()
    };
    let (plant, run, _) = Plant::new(&p).unwrap();
    let mut firing = NONE_FIRING;
    firing[4] = true;
    let d = plant.delivered_firing(&run.state, &thrust(0.0), &firing, false);
    // THEN the accelerometer reads 58 N / 900 kg along body +z
    assert_eq!(
        d.specific_force_body_mps2,
        Vector3::new(0.0, 0.0, 58.0 / 900.0)
    );
}
