//! Translation over a flat, non-rotating Moon (paper eq. 2): `r' = v`, `v' = g + a_thrust`,
//! all in the landing-site NUE frame. Curvature, the fall-off of gravity with height and the
//! Moon's rotation (Coriolis, centrifugal) are neglected; `translation_spherical` keeps them.
use super::frames::Nue;
use nalgebra::{Vector3, Vector6};

/// Layout of the translational state of this model: `[r_nue (m), v_nue (m/s)]`.
#[inline]
pub fn pack(r_nue: &Nue, v_nue: &Nue) -> Vector6<f64> {
    let (r, v) = (&r_nue.0, &v_nue.0);
    Vector6::new(r.x, r.y, r.z, v.x, v.y, v.z)
}

#[inline]
pub fn position_nue(x: &Vector6<f64>) -> Nue {
    Nue::new(x[0], x[1], x[2])
}

#[inline]
pub fn velocity_nue(x: &Vector6<f64>) -> Nue {
    Nue::new(x[3], x[4], x[5])
}

/// Altitude above the flat surface in m.
#[inline]
pub fn altitude(x: &Vector6<f64>) -> f64 {
    x[1]
}

/// Time derivative of the state for surface gravity `gravity_mps2` (> 0, acting along -Up) and
/// the thrust acceleration `a_thrust_nue` in m/s^2.
#[inline]
pub fn derivative(x: &Vector6<f64>, gravity_mps2: f64, a_thrust_nue: &Nue) -> Vector6<f64> {
    let a_nue = a_thrust_nue.0 - Vector3::new(0.0, gravity_mps2, 0.0);
    Vector6::new(x[3], x[4], x[5], a_nue.x, a_nue.y, a_nue.z)
}
