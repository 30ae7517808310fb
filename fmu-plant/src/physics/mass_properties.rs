//! Inertia and centre of mass moving with the propellant (optional; off by default: the
//! inertia is `inertia_body` and the centre of mass fixed, exactly as without).
//!
//! With the propellant fraction `f = (m - m_dry) / (m0 - m_dry)` (clamped to [0, 1]):
//! * `I(m) = I_dry + f (I_wet - I_dry)` per principal axis, `I_wet = inertia_body` (at m0);
//! * the centre of mass sits at `(1 - f) c_dry` from where it is at m0 (body axes), so the
//!   thrust acts at `thrust_point_body - (1 - f) c_dry` from it: the engine torque gains
//!   `-(1 - f) c_dry x F`.
//!
//! Euler's equations use `I(m)` as it stands, `I w' + w x I w = tau`: the propellant leaves
//! with the body's angular velocity and carries its own angular momentum away (no jet
//! damping, no `I' w` term; see `docs/plant-actuators.md`, *Mass properties*).
use super::parameters::PlantParameters;
use super::rigid_body::PrincipalInertia;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MassProperties {
    pub inertia_dry_body_kgm2: PrincipalInertia,
    pub inertia_wet_body_kgm2: PrincipalInertia,
    pub com_offset_dry_body_m: Vector3<f64>,
    pub dry_mass_kg: f64,
    pub propellant_kg: f64,
}

impl MassProperties {
    /// `None` unless `inertia_dry_body` is set (all three > 0).
    pub fn new(p: &PlantParameters) -> Option<Self> {
        let dry = p.inertia_dry_body_kgm2;
        (dry.iter().all(|i| *i > 0.0)).then_some(Self {
            inertia_dry_body_kgm2: dry,
            inertia_wet_body_kgm2: p.inertia_body_kgm2,
            com_offset_dry_body_m: p.com_offset_dry_body_m,
            dry_mass_kg: p.dry_mass_kg,
            propellant_kg: p.m0_kg - p.dry_mass_kg,
        })
    }

    /// Propellant fraction in [0, 1].
    pub fn fraction(&self, mass_kg: f64) -> f64 {
        ((mass_kg - self.dry_mass_kg) / self.propellant_kg).clamp(0.0, 1.0)
    }

    pub fn inertia_body_kgm2(&self, mass_kg: f64) -> PrincipalInertia {
        let f = self.fraction(mass_kg);
        self.inertia_dry_body_kgm2 + (self.inertia_wet_body_kgm2 - self.inertia_dry_body_kgm2) * f
    }

    /// Where the centre of mass is, relative to where it is at m0, body axes, m.
    pub fn com_offset_body_m(&self, mass_kg: f64) -> Vector3<f64> {
        self.com_offset_dry_body_m * (1.0 - self.fraction(mass_kg))
    }

    /// The engine torque the moved centre of mass adds for a thrust force (body axes), N m.
    pub fn engine_torque_shift_body_nm(
        &self,
        mass_kg: f64,
        thrust_body_n: &Vector3<f64>,
    ) -> Vector3<f64> {
        -self.com_offset_body_m(mass_kg).cross(thrust_body_n)
    }
}
