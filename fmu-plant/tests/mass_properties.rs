//! Inertia and centre of mass moving with the propellant (docs/plant-actuators.md, *Mass
//! properties*).
use fmu_plant::physics::parameters::PlantParameters;
use fmu_plant::physics::plant::{Advance, Commands, Plant};
use nalgebra::Vector3;

fn wet_to_dry() -> PlantParameters {
    PlantParameters {
        inertia_dry_body_kgm2: Vector3::new(300.0, 200.0, 350.0),
        ..Default::default()
    }
}

#[test]
fn a_constant_torque_spins_up_as_tau_over_i_dot_ln_i_over_i0_while_the_inertia_drains() {
    // GIVEN 1600 N (a linear mass loss) and 50 N m about the thrust axis y
    let p = wet_to_dry();
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    let c = Commands {
        thrust_cmd_n: 1600.0,
        torque_cmd_body_nm: Vector3::new(0.0, 50.0, 0.0),
    };
    for k in 0..2000 {
        assert_eq!(
            plant.advance(&mut run, &c, k as f64 * 0.01, 0.01),
            Advance::Reached
        );
    }
    // THEN I_yy(t) = 300 + I' t with I' = (300 - 200) / 300 kg x m', and
    // w_y = (tau / I') ln(I(t) / I0)
    let m_dot = -1600.0 / (300.0 * 9.81);
    let i_dot = (300.0 - 200.0) / 300.0 * m_dot;
    let i_t = 300.0 + i_dot * 20.0;
    let expected = 50.0 / i_dot * libm::log(i_t / 300.0);
    let w = run.state.omega_body.0.y;
    println!(
        "omega_y {w:.12} rad/s, (tau / I') ln(I / I0) = {expected:.12} rad/s, fixed inertia {:.12}",
        50.0 * 20.0 / 300.0
    );
    assert!((w - expected).abs() < 1e-9, "{w} vs {expected}");
}

#[test]
fn the_moving_centre_of_mass_turns_the_thrust_into_a_torque_in_proportion_to_the_propellant_burnt()
{
    // GIVEN the dry centre of mass 2 cm along body x from the wet one
    let mut p = wet_to_dry();
    p.com_offset_dry_body_m = Vector3::new(0.02, 0.0, 0.0);
    let (plant, mut run, _) = Plant::new(&p).unwrap();
    let c = Commands {
        thrust_cmd_n: 1600.0,
        ..Default::default()
    };
    // At m0 the thrust line passes through the centre of mass
    let d = plant.delivered(&run.state, &c, false);
    assert_eq!(d.engine_torque_body_nm, Vector3::zeros());
    for k in 0..1000 {
        plant.advance(&mut run, &c, k as f64 * 0.01, 0.01);
    }
    // THEN after 10 s the torque is -(1 - f) c_dry x F about z
    let f = (run.state.mass_kg - 600.0) / 300.0;
    let d = plant.delivered(&run.state, &c, false);
    let expected = -(1.0 - f) * 0.02 * 1600.0;
    assert!(
        (d.engine_torque_body_nm.z - expected).abs() < 1e-12,
        "{}",
        d.engine_torque_body_nm
    );
    // AND the body has turned about z under it (pitch rate negative)
    assert!(run.state.omega_body.0.z < 0.0);
}

#[test]
fn without_a_dry_inertia_the_mass_properties_are_fixed() {
    let (plant, _, _) = Plant::new(&PlantParameters::default()).unwrap();
    assert!(plant.mass_properties.is_none());
    let p = PlantParameters {
        inertia_dry_body_kgm2: Vector3::new(300.0, 0.0, 350.0),
        ..Default::default()
    };
    assert_eq!(p.validate().unwrap_err().field, "inertia_dry_body_kgm2");
}
