//! Reference attitude from guidance and mission (paper Sec. III, q_guid, A[phi_cmd], q_ref).
use crate::conventions::{rotation_about_thrust_axis, Attitude};
use lander_math::frames::Nue;
use nalgebra::{Matrix3, Quaternion, UnitQuaternion};

/// Paper Sec. III, q_guid with ERRATA 1-2: the shortest rotation taking the body thrust axis
/// `t = [0, 1, 0]` onto the unit direction of `a_thrust_nue`, as an attitude (body to NUE).
///
/// ERRATA 1: angle `theta = angle(t, a_hat)` (here `atan2(|t x a|, t . a)`, accurate at both
/// ends), axis `n = (t x a_hat) / |t x a_hat|`. With `t = e_y`, `t x a = [a_z, 0, -a_x]` is
/// exact (no cancellation), so `n` stays accurate however close `a_hat` is to `±t`.
///
/// ERRATA 2 policy: `a_hat = t` gives the identity; `a_hat = -t` gives a rotation by pi about
/// body z (pitch), `[0, 0, 0, 1]`. The shortest rotation has no continuous extension at `-t`;
/// this choice is the limit along the pitch plane (body x-y), the way a pitching lander gets
/// there, so inputs near `-t` in that plane map next to it. A zero vector (no direction) is
/// treated as `t`: the identity. Always a unit quaternion for finite input.
#[inline(always)]
pub fn q_guid(a_thrust_nue: &Nue) -> Attitude {
    let (ax, ay, az) = (a_thrust_nue.0.x, a_thrust_nue.0.y, a_thrust_nue.0.z);
    let sin_norm = libm::hypot(ax, az);
    if sin_norm == 0.0 {
        return if ay < 0.0 {
            UnitQuaternion::new_unchecked(Quaternion::new(0.0, 0.0, 0.0, 1.0))
        } else {
            UnitQuaternion::identity()
        };
    }
    let theta = libm::atan2(sin_norm, ay);
    let (s, c) = libm::sincos(0.5 * theta);
    // Normalise the axis after scaling to the larger component: subnormal inputs would
    // otherwise give an axis that is not unit.
    let scale = ax.abs().max(az.abs());
    let (sx, sz) = (ax / scale, az / scale);
    let norm = libm::hypot(sx, sz);
    let (nx, nz) = (sz / norm, -sx / norm);
    UnitQuaternion::new_unchecked(Quaternion::new(c, nx * s, 0.0, nz * s))
}

/// Paper Sec. III, A[phi] (and Sec. IV A[phi_b]): the frame rotation (NUE to body) by `+phi`
/// about body y, `[[c, 0, -s], [0, 1, 0], [s, 0, c]]`.
pub fn a_phi_dcm(phi_rad: f64) -> Matrix3<f64> {
    let (s, c) = libm::sincos(phi_rad);
    Matrix3::new(c, 0.0, -s, 0.0, 1.0, 0.0, s, 0.0, c)
}

/// Paper Sec. III, `q_phicmd <- A[phi_cmd]` with ERRATA 6: the attitude quaternion whose DCM
/// is A[phi], `[cos(phi/2), 0, sin(phi/2), 0]`, so that `phi_b(q_phi(phi)) = phi`. (Reading A
/// as an active rotation would flip the sign of phi and break the decoupled law.)
pub fn q_phi(phi_rad: f64) -> Attitude {
    rotation_about_thrust_axis(phi_rad)
}

/// Paper Sec. III, `q_ref = q_guid ⊗ q_phicmd`: thrust axis along the guidance direction,
/// then `phi_cmd` about it.
pub fn q_ref(q_guid: &Attitude, phi_cmd_rad: f64) -> Attitude {
    q_guid * q_phi(phi_cmd_rad)
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;
    use crate::conventions::{dcm_nue_to_body, thrust_axis_body};
    use nalgebra::Vector3;
    use std::f64::consts::PI;

    fn assert_maps_thrust_axis(a: Vector3<f64>, tol: f64) {
        let q = q_guid(&Nue(a));
        assert!(
            (q.into_inner().norm() - 1.0).abs() < 1e-14,
            "not unit for {a}"
        );
        let mapped = q * thrust_axis_body();
        assert!(
            (mapped - a.normalize()).norm() < tol,
            "a_hat {} mapped to {mapped}",
            a.normalize()
        );
    }

    #[test]
    fn q_guid_maps_thrust_axis_onto_a_dense_sphere() {
        // GIVEN a Fibonacci sphere of 20 000 directions
        let n = 20_000;
        let golden = PI * (3.0 - 5.0_f64.sqrt());
        for i in 0..n {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - y * y).sqrt();
            let phi = golden * i as f64;
            // THEN q_guid maps t onto each, to rounding
            assert_maps_thrust_axis(Vector3::new(r * phi.cos(), y, r * phi.sin()) * 3.7, 1e-14);
        }
    }

    #[test]
    fn q_guid_at_the_singular_points_follows_the_written_policy() {
        // a_hat = t: identity
        assert_eq!(q_guid(&Nue::new(0.0, 2.0, 0.0)), UnitQuaternion::identity());
        // a_hat = -t: pi about body z
        let flipped = q_guid(&Nue::new(0.0, -2.0, 0.0));
        assert_eq!(
            flipped.into_inner(),
            Quaternion::new(0.0, 0.0, 0.0, 1.0),
            "policy: pi about pitch"
        );
        assert_maps_thrust_axis(Vector3::new(0.0, -1.0, 0.0), 1e-15);
        // zero vector: no direction, identity
        assert_eq!(q_guid(&Nue::zeros()), UnitQuaternion::identity());
    }

    #[test]
    fn q_guid_on_a_ring_of_near_singular_directions() {
        for eps in [1e-3, 1e-8, 1e-12, 1e-200, 1e-310] {
            for k in 0..64 {
                let az = 2.0 * PI * k as f64 / 64.0;
                let (s, c) = az.sin_cos();
                // near +t and near -t
                assert_maps_thrust_axis(Vector3::new(eps * c, 1.0, eps * s), 1e-14);
                assert_maps_thrust_axis(Vector3::new(eps * c, -1.0, eps * s), 1e-14);
                // near +t the rotation is small: continuous with the identity
                let near_up = q_guid(&Nue::new(eps * c, 1.0, eps * s));
                assert!(near_up.angle() <= 1.0001 * eps);
            }
            // near -t in the pitch plane, from either side: next to the policy's rotation
            let policy = q_guid(&Nue::new(0.0, -1.0, 0.0));
            for side in [1.0, -1.0] {
                let near = q_guid(&Nue::new(side * eps, -1.0, 0.0));
                // cos(pi/2) = 6e-17, not 0: the policy point itself is that far from exact
                assert!(
                    near.angle_to(&policy) <= 1.0001 * eps + 2e-16,
                    "eps {eps} side {side}"
                );
            }
        }
    }

    #[test]
    fn q_phi_has_the_paper_dcm_and_rotates_about_the_thrust_axis() {
        for phi in [-3.0, -0.4, 0.0, 0.7, PI, 2.5] {
            let q = q_phi(phi);
            assert!(
                (dcm_nue_to_body(&q) - a_phi_dcm(phi)).norm() < 1e-15,
                "ERRATA 6"
            );
            assert!((q * thrust_axis_body() - thrust_axis_body()).norm() < 1e-15);
        }
    }

    #[test]
    fn q_ref_keeps_the_thrust_axis_on_guidance() {
        let a = Vector3::new(0.3, 1.0, -0.2);
        let q = q_ref(&q_guid(&Nue(a)), 2.6);
        assert!((q * thrust_axis_body() - a.normalize()).norm() < 1e-15);
    }
}
