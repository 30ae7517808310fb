//! The rigid body and its slosh pendulums as one mechanical system: the body's linear and
//! angular accelerations and the pendulums' accelerations solved together, from one
//! symmetric mass matrix, at every evaluation (docs/plant-slosh.md derives it).
//!
//! Body axes, about the rigid part's centre of mass `O` (the point the plant's position,
//! thrust line and inertia refer to). Unknowns `u = (s, alpha, a_1, a_2)`: `s` the specific
//! force of `O` (its acceleration minus gravity: what an accelerometer there reads), `alpha`
//! the body's angular acceleration, `a_i` pendulum i's angular acceleration in its tangent
//! plane. The sloshing mass sits at `r_i = hinge_i + L_i e_i`, `e_i` a unit vector (the
//! spherical pendulum, no small-angle approximation, no chart edge); with `t_1, t_2` an
//! orthonormal basis of the plane normal to `e_i`, `e_i'' = a_1 t_1 + a_2 t_2 - |e_i'|^2 e_i`,
//! and the mass's acceleration minus gravity is `B_i u + w_i`:
//! * `B_i = [1, -[r_i]x, J_i]`, `J_i = L_i [t_1 t_2]`;
//! * `w_i = omega x (omega x r_i) + 2 omega x L_i e_i' - L_i |e_i'|^2 e_i`.
//!
//! Newton-Euler of the whole system and the pendulums' equations projected on their tangent
//! planes (the rod force drops out) give `M u = b` with
//! `M = diag(m_r, I, 0) + sum m_i B_i^T B_i` and
//! `b = (F, tau - omega x I omega, 0) - sum m_i B_i^T w_i + (0, 0, J_i^T d_i)`: exactly the
//! equations of the Lagrangian `T - V` of rigid body and pendulums, so that without damping
//! the energy and the angular momentum the loads leave alone are conserved.
//!
//! Damping acts between each mass and its tank: `d_i = -c_i rho_i'` on the mass and its
//! reaction on the tank at the mass, `c_i = 2 zeta m_i sqrt(s_axial / L_i)`; an internal
//! force, it dissipates energy and leaves the momenta alone.
use super::rigid_body::PrincipalInertia;
use super::slosh::{Pendulum, Slosh, SloshState, TANK_COUNT};
use nalgebra::{Matrix3, Matrix3x2, SMatrix, SVector, Vector2, Vector3};

const N: usize = 6 + 2 * TANK_COUNT;

/// What acts on the rigid part at a state, body axes: the external force (engines, RCS,
/// contact) and torque about `O`, the rigid part's inertia, the body rate, the total mass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidLoads {
    pub mass_kg: f64,
    pub inertia_body_kgm2: PrincipalInertia,
    pub force_body_n: Vector3<f64>,
    pub torque_body_nm: Vector3<f64>,
    pub omega_body: Vector3<f64>,
}

/// The accelerations of the coupled system at a state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coupled {
    /// Specific force of the rigid part's centre of mass, body axes, m/s^2.
    pub specific_force_body_mps2: Vector3<f64>,
    /// Angular acceleration of the body, rad/s^2.
    pub alpha_body_radps2: Vector3<f64>,
    /// The pendulums' derivative (rates, accelerations).
    pub derivative: SloshState,
}

/// Where a sloshing mass is and how it moves relative to the body, body axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bob {
    /// Position relative to `O`, m.
    pub position_body_m: Vector3<f64>,
    /// Velocity relative to the body (as seen in body axes), m/s.
    pub velocity_body_mps: Vector3<f64>,
    /// `L [t_1 t_2]`: the mass's velocity per tangential angular rate.
    jacobian: Matrix3x2<f64>,
    /// `-L |e'|^2 e`, the acceleration that keeps the mass on its sphere, m/s^2.
    convective_mps2: Vector3<f64>,
}

/// Pendulum `k`'s mass at state `s`.
pub fn bob(p: &Pendulum, s: &SloshState, k: usize) -> Bob {
    let e = s.direction(k).normalize();
    let rate = s.direction_rate(k);
    // The body axis least along `e` gives a well-conditioned tangent basis; the equations
    // only see the plane it spans, so a switch of axis changes nothing.
    let a = e.abs();
    let axis = if a.x <= a.y && a.x <= a.z {
        Vector3::x()
    } else if a.y <= a.z {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let t1 = (axis - e * e.dot(&axis)).normalize();
    let t2 = e.cross(&t1);
    let l = p.length_m;
    Bob {
        position_body_m: p.hinge_body_m + e * l,
        velocity_body_mps: rate * l,
        jacobian: Matrix3x2::from_columns(&[t1 * l, t2 * l]),
        convective_mps2: -e * (l * rate.norm_squared()),
    }
}

fn skew(r: &Vector3<f64>) -> Matrix3<f64> {
    r.cross_matrix()
}

/// The coupled accelerations of the rigid body with the pendulums `pendulums` (those at the
/// current mass) in state `s`.
pub fn solve(
    slosh: &Slosh,
    pendulums: &[Pendulum; TANK_COUNT],
    s: &SloshState,
    loads: &RigidLoads,
) -> Coupled {
    let omega = &loads.omega_body;
    let inertia = &loads.inertia_body_kgm2;
    let sloshing_kg: f64 = pendulums
        .iter()
        .filter(|p| p.is_active())
        .map(|p| p.mass_kg)
        .sum();
    let rigid_kg = loads.mass_kg - sloshing_kg;
    let axial = (loads.force_body_n.y / loads.mass_kg).max(0.0);
    let mut m = SMatrix::<f64, N, N>::zeros();
    let mut b = SVector::<f64, N>::zeros();
    for i in 0..3 {
        m[(i, i)] = rigid_kg;
        m[(3 + i, 3 + i)] = inertia[i];
    }
    b.fixed_rows_mut::<3>(0).copy_from(&loads.force_body_n);
    b.fixed_rows_mut::<3>(3)
        .copy_from(&(loads.torque_body_nm - omega.cross(&inertia.component_mul(omega))));
    for (k, p) in pendulums.iter().enumerate() {
        let q = 6 + 2 * k;
        if !p.is_active() {
            // No liquid: the pendulum stands still where it is.
            m[(q, q)] = 1.0;
            m[(q + 1, q + 1)] = 1.0;
            continue;
        }
        let bob = bob(p, s, k);
        let r = &bob.position_body_m;
        let mut bi = SMatrix::<f64, 3, N>::zeros();
        bi.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&Matrix3::identity());
        bi.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-skew(r)));
        bi.fixed_view_mut::<3, 2>(0, q).copy_from(&bob.jacobian);
        let w = omega.cross(&omega.cross(r))
            + 2.0 * omega.cross(&bob.velocity_body_mps)
            + bob.convective_mps2;
        m += bi.transpose() * bi * p.mass_kg;
        b -= bi.transpose() * w * p.mass_kg;
        let c = 2.0 * slosh.damping_ratio * p.mass_kg * libm::sqrt(axial / p.length_m);
        let damping: Vector2<f64> = bob.jacobian.transpose() * (-c * bob.velocity_body_mps);
        b[q] += damping.x;
        b[q + 1] += damping.y;
    }
    let u = match m.cholesky() {
        Some(chol) => chol.solve(&b),
        // Positive definite for any positive masses and inertia; a non-finite state
        // leaves non-finite accelerations for the step's finiteness check to refuse.
        None => SVector::<f64, N>::repeat(f64::NAN),
    };
    let mut derivative = SloshState::default();
    for (k, p) in pendulums.iter().enumerate() {
        if p.is_active() {
            let bob = bob(p, s, k);
            let tangential = bob.jacobian * Vector2::new(u[6 + 2 * k], u[7 + 2 * k]);
            let acceleration = (tangential + bob.convective_mps2) / p.length_m;
            derivative.0[6 * k..6 * k + 3].copy_from_slice(&s.0[6 * k + 3..6 * k + 6]);
            derivative.0[6 * k + 3..6 * k + 6].copy_from_slice(acceleration.as_slice());
        }
    }
    Coupled {
        specific_force_body_mps2: u.fixed_rows::<3>(0).into_owned(),
        alpha_body_radps2: u.fixed_rows::<3>(3).into_owned(),
        derivative,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::slosh::SloshParameters;

    fn default_slosh() -> Slosh {
        Slosh::new(
            &SloshParameters {
                enabled: true,
                ..SloshParameters::default()
            },
            600.0,
            900.0,
        )
    }

    fn hover(omega: Vector3<f64>, torque: Vector3<f64>) -> RigidLoads {
        RigidLoads {
            mass_kg: 900.0,
            inertia_body_kgm2: Vector3::new(400.0, 300.0, 450.0),
            force_body_n: Vector3::new(0.0, 1458.0, 0.0),
            torque_body_nm: torque,
            omega_body: omega,
        }
    }

    #[test]
    fn at_rest_on_the_thrust_axis_nothing_sloshes_and_the_body_feels_thrust_over_mass() {
        let slosh = default_slosh();
        let c = solve(
            &slosh,
            &slosh.pendulums,
            &slosh.initial_state(&SloshParameters::default()),
            &hover(Vector3::zeros(), Vector3::zeros()),
        );
        assert!(
            c.derivative.0.iter().all(|d| d.abs() < 1e-15),
            "{:?}",
            c.derivative
        );
        assert!(c.alpha_body_radps2.norm() < 1e-15);
        let s = c.specific_force_body_mps2;
        assert!((s.y - 1458.0 / 900.0).abs() < 1e-14 && s.x.abs() < 1e-15 && s.z.abs() < 1e-15);
    }

    #[test]
    fn a_torque_about_the_thrust_axis_turns_body_and_propellant_together() {
        // GIVEN the default tanks at rest
        let slosh = default_slosh();
        let tau = 10.0;
        let c = solve(
            &slosh,
            &slosh.pendulums,
            &slosh.initial_state(&SloshParameters::default()),
            &hover(Vector3::zeros(), Vector3::new(0.0, tau, 0.0)),
        );
        // THEN at the first instant the sloshing masses lag: the body alone turns at tau / I
        // and each mass stays behind by alpha r_x along z relative to its tank
        let alpha = c.alpha_body_radps2.y;
        assert!((alpha - tau / 300.0).abs() < 1e-12, "{alpha}");
        let d = &c.derivative.0;
        let l = slosh.pendulums[0].length_m;
        assert!(
            (d[5] * l - alpha * 0.6).abs() < 1e-12 && (d[11] * l + alpha * 0.6).abs() < 1e-12,
            "{d:?}"
        );
        // AND turning at 0.3 rad/s flings them outward: omega x (omega x r) = -w^2 r
        let w = 0.3;
        let c = solve(
            &slosh,
            &slosh.pendulums,
            &slosh.initial_state(&SloshParameters::default()),
            &hover(Vector3::new(0.0, w, 0.0), Vector3::zeros()),
        );
        let d = &c.derivative.0;
        assert!(d[3] > 0.0 && d[9] < 0.0, "{d:?}");
    }
}
