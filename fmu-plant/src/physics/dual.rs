//! Forward-mode automatic differentiation: a dual number `value + tangent ε` (`ε² = 0`)
//! carries the derivative along one direction through every operation, exactly (to
//! round-off), with no step size. [`Scalar`] is what the plant's equations need of a
//! number; `f64` and [`Dual`] implement it, so one generic copy of the equations gives the
//! value and the directional derivative `J · seed` in one pass.
//!
//! Written here rather than taken from a crate: the transcendental functions go through
//! `libm`, as everywhere in the models, so the derivatives have the same bits on every
//! platform (docs/floating-point.md); a dual-number crate calls std's.
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A real number as the plant's equations use it.
pub trait Scalar:
    Copy
    + std::fmt::Debug
    + From<f64>
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
    /// The value (the real part of a dual number): what every branch decides on.
    fn value(self) -> f64;
    fn sqrt(self) -> Self;
    /// `(sin, cos)` through `libm`.
    fn sin_cos(self) -> (Self, Self);

    /// `|x|`, the branch `x` at 0.
    fn abs(self) -> Self {
        if self.value() < 0.0 {
            -self
        } else {
            self
        }
    }

    /// `max(x, bound)` for a constant bound: the bound (derivative 0) where it wins,
    /// including a tie, as `f64::max` of the plant returns the same value there.
    fn max_const(self, bound: f64) -> Self {
        if self.value() > bound {
            self
        } else {
            Self::from(bound)
        }
    }

    /// `min(x, bound)` for a constant bound (see [`Scalar::max_const`]).
    fn min_const(self, bound: f64) -> Self {
        if self.value() < bound {
            self
        } else {
            Self::from(bound)
        }
    }
}

impl Scalar for f64 {
    fn value(self) -> f64 {
        self
    }
    fn sqrt(self) -> f64 {
        f64::sqrt(self)
    }
    fn sin_cos(self) -> (f64, f64) {
        libm::sincos(self)
    }
}

/// `re + eps ε`: a value and its derivative along one direction.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Dual {
    pub re: f64,
    pub eps: f64,
}

impl Dual {
    pub const fn new(re: f64, eps: f64) -> Dual {
        Dual { re, eps }
    }
}

impl From<f64> for Dual {
    fn from(re: f64) -> Dual {
        Dual { re, eps: 0.0 }
    }
}

impl Scalar for Dual {
    fn value(self) -> f64 {
        self.re
    }
    fn sqrt(self) -> Dual {
        let root = f64::sqrt(self.re);
        Dual::new(root, self.eps / (2.0 * root))
    }
    fn sin_cos(self) -> (Dual, Dual) {
        let (s, c) = libm::sincos(self.re);
        (Dual::new(s, c * self.eps), Dual::new(c, -s * self.eps))
    }
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual::new(self.re + o.re, self.eps + o.eps)
    }
}

impl Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        Dual::new(self.re - o.re, self.eps - o.eps)
    }
}

impl Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        Dual::new(self.re * o.re, self.eps * o.re + self.re * o.eps)
    }
}

impl Div for Dual {
    type Output = Dual;
    fn div(self, o: Dual) -> Dual {
        Dual::new(
            self.re / o.re,
            (self.eps * o.re - self.re * o.eps) / (o.re * o.re),
        )
    }
}

impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        Dual::new(-self.re, -self.eps)
    }
}

impl Add<f64> for Dual {
    type Output = Dual;
    fn add(self, o: f64) -> Dual {
        Dual::new(self.re + o, self.eps)
    }
}

impl Sub<f64> for Dual {
    type Output = Dual;
    fn sub(self, o: f64) -> Dual {
        Dual::new(self.re - o, self.eps)
    }
}

impl Mul<f64> for Dual {
    type Output = Dual;
    fn mul(self, o: f64) -> Dual {
        Dual::new(self.re * o, self.eps * o)
    }
}

impl Div<f64> for Dual {
    type Output = Dual;
    fn div(self, o: f64) -> Dual {
        Dual::new(self.re / o, self.eps / o)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tangent_is_the_derivative_of_each_operation() {
        let x = Dual::new(0.7, 1.0);
        // d/dx sqrt(x^2 + 1) = x / sqrt(x^2 + 1); d/dx (x / (x + 2)) = 2 / (x + 2)^2.
        let y = (x * x + 1.0).sqrt();
        assert!((y.eps - 0.7 / f64::sqrt(1.49)).abs() < 1e-16);
        let r = x / (x + 2.0);
        assert!((r.eps - 2.0 / (2.7 * 2.7)).abs() < 1e-16);
        assert_eq!((x * 3.0 - x).eps, 2.0);
        let (s, c) = Dual::new(0.3, 2.0).sin_cos();
        assert_eq!(s.eps, 2.0 * libm::cos(0.3));
        assert_eq!(c.eps, -2.0 * libm::sin(0.3));
        let q = Dual::new(3.0, 1.0) / Dual::new(2.0, 0.5);
        assert_eq!(q.eps, (1.0 * 2.0 - 3.0 * 0.5) / 4.0);
        assert_eq!(Dual::new(-2.0, 1.0).abs().eps, -1.0);
        assert_eq!(Dual::new(2.0, 1.0).max_const(2.0).eps, 0.0);
        assert_eq!(Dual::new(2.5, 1.0).max_const(2.0).eps, 1.0);
    }
}
