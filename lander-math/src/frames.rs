//! Vectors that carry their frame, so that NUE components and body components cannot be
//! mixed up: a `Body` where a `Nue` is expected does not compile, and the only way from one
//! to the other is the attitude ([`BodyToNue`]). The wrapped components are the plain
//! nalgebra vector, and every operation here is the one the caller would have written on it
//! (same operations in the same order, so the same bits).
use crate::quaternion::{matrix, Quaternion};
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// Components in the local frame of the landing site: axis 1 North, axis 2 Up, axis 3 East,
/// origin at the landing site on the surface, fixed to the Moon.
// Transparent: an FMU state that held the bare vector reads and writes the same bytes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Nue(pub Vector3<f64>);

/// Components in body axes: 1 = yaw (x), 2 = roll (y) = the thrust axis, 3 = pitch (z).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Body(pub Vector3<f64>);

macro_rules! frame_vector {
    ($frame:ident) => {
        impl $frame {
            #[inline]
            pub fn new(x: f64, y: f64, z: f64) -> Self {
                Self(Vector3::new(x, y, z))
            }

            #[inline]
            pub fn zeros() -> Self {
                Self(Vector3::zeros())
            }

            #[inline]
            pub fn dot(&self, other: &Self) -> f64 {
                self.0.dot(&other.0)
            }

            #[inline]
            pub fn norm(&self) -> f64 {
                self.0.norm()
            }

            #[inline]
            pub fn to_array(self) -> [f64; 3] {
                self.0.into()
            }
        }

        impl From<[f64; 3]> for $frame {
            #[inline]
            fn from(components: [f64; 3]) -> Self {
                Self(Vector3::from(components))
            }
        }

        impl std::ops::Add for $frame {
            type Output = Self;
            #[inline]
            fn add(self, other: Self) -> Self {
                Self(self.0 + other.0)
            }
        }

        impl std::ops::Sub for $frame {
            type Output = Self;
            #[inline]
            fn sub(self, other: Self) -> Self {
                Self(self.0 - other.0)
            }
        }

        impl std::ops::Neg for $frame {
            type Output = Self;
            #[inline]
            fn neg(self) -> Self {
                Self(-self.0)
            }
        }

        /// A scale keeps the frame: `v * k`, the vector on the left as nalgebra has it.
        impl std::ops::Mul<f64> for $frame {
            type Output = Self;
            #[inline]
            fn mul(self, k: f64) -> Self {
                Self(self.0 * k)
            }
        }
    };
}

frame_vector!(Nue);
frame_vector!(Body);

/// An attitude as the rotation it applies: body components into NUE ones (`v_nue = R v_body`,
/// `R` the direction cosine matrix of the unit `q_body_to_nue`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyToNue(Matrix3<f64>);

impl BodyToNue {
    /// The rotation of the unit quaternion `q_body_to_nue` (scalar first).
    #[inline]
    pub fn of(q_body_to_nue: &Quaternion) -> Self {
        Self(matrix(q_body_to_nue))
    }

    /// `R`, for a caller that forms products with it (covariances, Jacobians).
    #[inline]
    pub fn matrix(&self) -> &Matrix3<f64> {
        &self.0
    }

    #[inline]
    pub fn to_nue(&self, v: &Body) -> Nue {
        Nue(self.0 * v.0)
    }

    /// `R^T v`.
    #[inline]
    pub fn to_body(&self, v: &Nue) -> Body {
        Body(self.0.transpose() * v.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pitch_of_90_deg_tips_the_thrust_axis_towards_south_and_back() {
        // +90 deg about body z (East when upright): z x y = -x, the thrust axis points South.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let attitude = BodyToNue::of(&[h, 0.0, 0.0, h]);
        let thrust = attitude.to_nue(&Body::new(0.0, 1.0, 0.0));
        assert!(
            (thrust - Nue::new(-1.0, 0.0, 0.0)).0.norm() < 1e-15,
            "{thrust:?}"
        );
        let back = attitude.to_body(&thrust);
        assert!(
            (back - Body::new(0.0, 1.0, 0.0)).0.norm() < 1e-15,
            "{back:?}"
        );
    }
}
