//! Cubic-polynomial descent guidance (paper Sec. III, eq. (eq3) and eq. (gui_lin_eq)).
//!
//! The net (kinematic) acceleration is a cubic in the time since the solve,
//! `a_net(s) = C0 + C1 s + C2 s^2 + C3 s^3`, whose coefficients satisfy the two-point boundary
//! value problem over `[0, tgo]` per axis: start and end acceleration, end velocity and end
//! position of the double integrator `r'' = a_net` (ERRATA 8: net, not thrust, acceleration).
use lander_math::frames::Nue;
use serde::{Deserialize, Serialize};

/// Boundary conditions of one solve, all in NUE.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryConditions {
    pub r0_nue: Nue,
    pub v0_nue: Nue,
    /// Net acceleration at the start (the previous command, for continuity).
    pub a0_net_nue: Nue,
    pub rf_nue: Nue,
    pub vf_nue: Nue,
    pub af_net_nue: Nue,
}

/// The cubic's coefficients per axis: `coeffs[k]` multiplies `s^k`, NUE components.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CubicAcceleration {
    pub coeffs: [Nue; 4],
}

impl CubicAcceleration {
    /// Paper Sec. III, eq. (eq3): the net acceleration `s` seconds after the solve.
    pub fn net_acceleration_nue(&self, s: f64) -> Nue {
        let [c0, c1, c2, c3] = self.coeffs.map(|c| c.0);
        Nue(c0 + (c1 + (c2 + c3 * s) * s) * s)
    }
}

/// The 4x4 matrix of paper Sec. III, eq. (gui_lin_eq) for a given `tgo`. Rows: acceleration at
/// 0, acceleration at tgo, velocity change over tgo, position change over tgo minus `v0 tgo`.
pub fn boundary_value_matrix(tgo_s: f64) -> nalgebra::Matrix4<f64> {
    let t = tgo_s;
    let (t2, t3, t4, t5) = (t * t, t * t * t, t * t * t * t, t * t * t * t * t);
    nalgebra::Matrix4::new(
        1.0,
        0.0,
        0.0,
        0.0,
        1.0,
        t,
        t2,
        t3,
        t,
        t2 / 2.0,
        t3 / 3.0,
        t4 / 4.0,
        t2 / 2.0,
        t3 / 6.0,
        t4 / 12.0,
        t5 / 20.0,
    )
}

/// The right-hand side of paper Sec. III, eq. (gui_lin_eq) for one axis `i`.
pub fn boundary_value_rhs(bc: &BoundaryConditions, tgo_s: f64, i: usize) -> nalgebra::Vector4<f64> {
    nalgebra::Vector4::new(
        bc.a0_net_nue.0[i],
        bc.af_net_nue.0[i],
        bc.vf_nue.0[i] - bc.v0_nue.0[i],
        bc.rf_nue.0[i] - bc.r0_nue.0[i] - bc.v0_nue.0[i] * tgo_s,
    )
}

/// Paper Sec. III, eq. (gui_lin_eq) solved in closed form, all three axes at once.
///
/// `C0 = a0` from the first row. Scaling the unknowns as `x_k = C_k tgo^k` turns the other three
/// rows into a constant 3x3 system `[[1,1,1],[1/2,1/3,1/4],[1/6,1/12,1/20]] x = [A, B, D]`
/// whose inverse is the integer matrix `[[3,-24,60],[-12,84,-180],[10,-60,120]]`, with
/// `A = af - a0`, `B = (dv - a0 tgo)/tgo`, `D = (dr - v0 tgo - a0 tgo^2/2)/tgo^2`.
///
/// `tgo_s` must be positive; the sequencer freezes the coefficients before it gets small.
pub fn solve_cubic(bc: &BoundaryConditions, tgo_s: f64) -> CubicAcceleration {
    let t = tgo_s;
    let a0 = bc.a0_net_nue.0;
    let (r0, v0) = (bc.r0_nue.0, bc.v0_nue.0);
    let big_a = bc.af_net_nue.0 - a0;
    let big_b = (bc.vf_nue.0 - v0 - a0 * t) / t;
    let big_d = (bc.rf_nue.0 - r0 - v0 * t - a0 * (0.5 * t * t)) / (t * t);
    let x1 = big_a * 3.0 - big_b * 24.0 + big_d * 60.0;
    let x2 = big_a * -12.0 + big_b * 84.0 - big_d * 180.0;
    let x3 = big_a * 10.0 - big_b * 60.0 + big_d * 120.0;
    CubicAcceleration {
        coeffs: [a0, x1 / t, x2 / (t * t), x3 / (t * t * t)].map(Nue),
    }
}

/// Position and velocity of the double integrator `r'' = a_net(s)` driven open loop by
/// `cubic` from `bc`'s start, at `s`, integrated analytically term by term (`C_k s^k`
/// integrates to `C_k s^(k+1)/(k+1)` and `C_k s^(k+2)/((k+1)(k+2))`): the independent check
/// of a solve's boundary conditions.
#[cfg(test)]
// std's powi is a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
pub(crate) fn integrate_open_loop(
    bc: &BoundaryConditions,
    cubic: &CubicAcceleration,
    s: f64,
) -> (Nue, Nue) {
    let mut v = bc.v0_nue.0;
    let mut r = bc.r0_nue.0 + bc.v0_nue.0 * s;
    for (k, c) in cubic.coeffs.iter().map(|c| c.0).enumerate() {
        let k = k as i32;
        v += c * s.powi(k + 1) / f64::from(k + 1);
        r += c * s.powi(k + 2) / f64::from((k + 1) * (k + 2));
    }
    (Nue(r), Nue(v))
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;

    fn descent_case() -> BoundaryConditions {
        BoundaryConditions {
            r0_nue: Nue::new(12.0, 800.0, -7.0),
            v0_nue: Nue::new(0.3, -1.5, 0.2),
            a0_net_nue: Nue::new(0.01, -0.05, 0.02),
            rf_nue: Nue::new(0.0, 150.0, 0.0),
            vf_nue: Nue::zeros(),
            af_net_nue: Nue::zeros(),
        }
    }

    #[test]
    fn closed_form_matches_a_generic_lu_solve() {
        let bc = descent_case();
        for tgo in [0.5, 5.0, 37.3, 130.0] {
            let closed = solve_cubic(&bc, tgo);
            let lu = boundary_value_matrix(tgo).lu();
            for i in 0..3 {
                let c = lu.solve(&boundary_value_rhs(&bc, tgo, i)).unwrap();
                for k in 0..4 {
                    let scale = c[k].abs().max(1e-12);
                    assert!(
                        (closed.coeffs[k].0[i] - c[k]).abs() / scale < 1e-9,
                        "tgo {tgo} axis {i} C{k}: closed {} lu {}",
                        closed.coeffs[k].0[i],
                        c[k]
                    );
                }
            }
        }
    }

    #[test]
    fn double_integrator_meets_the_boundary_conditions() {
        // GIVEN a double integrator r'' = a_net(s) driven open loop by one solve
        let bc = descent_case();
        let tgo = 130.0;
        let cubic = solve_cubic(&bc, tgo);
        // WHEN it is integrated analytically over [0, tgo]
        let (r, v) = integrate_open_loop(&bc, &cubic, tgo);
        // THEN it arrives at the target position and velocity with the wanted accelerations
        assert!((r - bc.rf_nue).norm() < 1e-9, "r(tgo) = {r:?}");
        assert!((v - bc.vf_nue).norm() < 1e-11, "v(tgo) = {v:?}");
        assert!((cubic.net_acceleration_nue(0.0) - bc.a0_net_nue).norm() < 1e-15);
        assert!((cubic.net_acceleration_nue(tgo) - bc.af_net_nue).norm() < 1e-12);
    }

    #[test]
    fn already_on_target_at_rest_needs_no_acceleration() {
        let bc = BoundaryConditions {
            r0_nue: Nue::new(0.0, 150.0, 0.0),
            v0_nue: Nue::zeros(),
            a0_net_nue: Nue::zeros(),
            rf_nue: Nue::new(0.0, 150.0, 0.0),
            vf_nue: Nue::zeros(),
            af_net_nue: Nue::zeros(),
        };
        let cubic = solve_cubic(&bc, 42.0);
        assert!(cubic.coeffs.iter().all(|c| c.norm() < 1e-15));
    }
}
