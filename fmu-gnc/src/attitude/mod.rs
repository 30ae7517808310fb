//! Reference attitude and the three attitude control laws (paper Sec. III-IV, plus the
//! reduced law for comparison), all pure functions of the current sample.
pub mod errors;
pub mod gains;
pub mod phi_b;
pub mod profile;
pub mod reference;

use crate::conventions::{self, Attitude};
use gains::{saturate_torque_body, AttitudeGains};
use lander_math::frames::{Body, Nue};
use nalgebra::Vector3;
use profile::RollReference;
use serde::{Deserialize, Serialize};

/// The attitude laws, each written once: its variant, its value in the `control_law`
/// enumeration, its name and description there, and its module. The enum, its FMI items (and
/// the values a refusal lists), [`ControlLaw::from_index`] and the dispatch of a sample all
/// come from this table: a new law is its own module with a `torque` function taking
/// [`LawInputs`], and one row here.
macro_rules! control_laws {
    ($($(#[$doc:meta])* $variant:ident = $value:literal, $name:literal, $description:literal, $module:ident;)+) => {
        $(pub mod $module;)+

        /// Which attitude law runs; exchanged as the Enumeration parameter `control_law`.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
        pub enum ControlLaw {
            $($(#[$doc])* $variant = $value,)+
        }

        fmi_model::enumeration! {
            ControlLaw = "ControlLaw", "Attitude control law" {
                $($variant: $name, $description;)+
            }
        }

        impl ControlLaw {
            /// The unsaturated torque of the law and the angle errors it acted on, body axes.
            #[inline(always)]
            fn torque(self, inputs: &LawInputs) -> (Body, Body) {
                match self {
                    $(ControlLaw::$variant => $module::torque(inputs),)+
                }
            }
        }
    };
}

control_laws! {
    /// Classical quaternion PD on the full reference attitude (paper Sec. IV).
    Coupled = 1, "coupled", "classical quaternion PD on q_ref", coupled;
    /// The paper's decoupled thrust-axis law (paper Sec. IV).
    Decoupled = 2, "decoupled", "decoupled thrust-axis control (the paper)", decoupled;
    /// PX4-style reduced attitude (Brescianini et al. 2013).
    Reduced = 3, "reduced", "PX4-style reduced attitude (Brescianini et al. 2013)", reduced;
}

impl ControlLaw {
    /// The law of a `control_law` value, `None` if it is no item.
    pub fn from_index(value: i32) -> Option<Self> {
        <Self as fmi_model::Enumeration>::from_value(value)
    }
}

/// What every law is given at one sample.
#[derive(Debug, Clone, Copy)]
pub struct LawInputs<'a> {
    pub settings: &'a AttitudeSettings,
    pub q_body_to_nue: &'a Attitude,
    pub omega_body: &'a Body,
    /// The full reference attitude, `q_guid ⊗ q_phi`.
    pub q_ref: &'a Attitude,
    /// The thrust-axis split of the attitude error, computed once per sample.
    pub split: &'a errors::ThrustAxisErrors,
    pub roll: &'a RollReference,
}

/// Everything an attitude law needs besides the current sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AttitudeSettings {
    pub law: ControlLaw,
    pub gains: AttitudeGains,
    pub torque_limit_body_nm: Vector3<f64>,
    /// Weight of the rotation about the thrust axis in the reduced law, [0, 1].
    pub reduced_yaw_weight: f64,
    /// The rotation to the commanded angle about the thrust axis, computed once: the
    /// reference of every sample once phi_cmd is active.
    pub phi_cmd_rotation: ThrustAxisRotation,
}

/// A rotation about the thrust axis, kept with its angle: `q_phi(phi_rad)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThrustAxisRotation {
    phi_rad: f64,
    q_phi: Attitude,
}

impl ThrustAxisRotation {
    pub fn new(phi_rad: f64) -> Self {
        Self {
            phi_rad,
            q_phi: reference::q_phi(phi_rad),
        }
    }

    /// `q_phi(phi_rad)`: the kept rotation when the angle is its own (to the bit), else
    /// computed.
    pub fn at(&self, phi_rad: f64) -> Attitude {
        if phi_rad.to_bits() == self.phi_rad.to_bits() {
            self.q_phi
        } else {
            reference::q_phi(phi_rad)
        }
    }
}

/// The attitude command of one control sample, with the diagnostics of the law that ran.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AttitudeCommand {
    /// Saturated per axis to the RCS limits.
    pub torque_body_nm: Body,
    pub q_ref: Attitude,
    /// The angle errors the law acted on, body axes `[yaw (x), roll (y), pitch (z)]`.
    pub angle_error_body: Body,
    pub phi_b_rad: f64,
    pub tilt_rad: f64,
}

/// One control sample: reference attitude from the guidance direction and `phi_cmd`, then the
/// selected law, then saturation (the paper's step in `phi_cmd`, at rest).
pub fn attitude_command(
    settings: &AttitudeSettings,
    q_body_to_nue: &Attitude,
    omega_body: &Body,
    a_thrust_cmd_nue: &Nue,
    phi_cmd_rad: f64,
) -> AttitudeCommand {
    tracking_attitude_command(
        settings,
        q_body_to_nue,
        omega_body,
        a_thrust_cmd_nue,
        &RollReference::step(phi_cmd_rad),
    )
}

/// As [`attitude_command`], with a moving reference about the thrust axis (a shaped manoeuvre,
/// see [`profile`]): its angle in place of `phi_cmd`, its rate and acceleration fed forward.
#[inline(always)]
pub fn tracking_attitude_command(
    settings: &AttitudeSettings,
    q_body_to_nue: &Attitude,
    omega_body: &Body,
    a_thrust_cmd_nue: &Nue,
    roll: &RollReference,
) -> AttitudeCommand {
    let reference = GuidanceReference::new(settings, a_thrust_cmd_nue, roll.phi_rad);
    command_toward(settings, &reference, q_body_to_nue, omega_body, roll)
}

/// As [`tracking_attitude_command`], with the reference attitude `reference` (for the sample's
/// guidance command and `roll`).
#[inline(always)]
pub fn command_toward(
    settings: &AttitudeSettings,
    reference: &GuidanceReference,
    q_body_to_nue: &Attitude,
    omega_body: &Body,
    roll: &RollReference,
) -> AttitudeCommand {
    let split = errors::thrust_axis_errors_toward(
        q_body_to_nue,
        &reference.q_guid,
        &reference.thrust_axis_nue,
        roll.phi_rad,
    );
    let (torque, angle_error_body) = settings.law.torque(&LawInputs {
        settings,
        q_body_to_nue,
        omega_body,
        q_ref: &reference.q_ref,
        split: &split,
        roll,
    });
    AttitudeCommand {
        torque_body_nm: saturate_torque_body(&torque, &settings.torque_limit_body_nm),
        q_ref: reference.q_ref,
        angle_error_body,
        phi_b_rad: split.phi_b_rad,
        tilt_rad: split.tilt_rad,
    }
}

/// The reference attitude of a guidance command and an angle about the thrust axis: `q_guid`,
/// the thrust direction it gives (`q_guid t`, NUE) and `q_ref = q_guid ⊗ q_phi`. Guidance
/// holds its command over a whole cycle, and the angle is `phi_cmd` but for a shaped
/// manoeuvre: a caller that keeps this between samples ([`GuidanceReference::keep`]) computes
/// `q_guid` (two `hypot`, an `atan2`, a `sincos`) once a cycle, with the same bits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuidanceReference {
    /// The bits it was computed from: the command's and the angle's (all it is a function
    /// of: [`ThrustAxisRotation::at`] is `q_phi` whatever the rotation kept).
    a_thrust_cmd_bits: [u64; 3],
    phi_bits: u64,
    q_guid: Attitude,
    thrust_axis_nue: Vector3<f64>,
    q_ref: Attitude,
}

impl GuidanceReference {
    #[inline(always)]
    pub fn new(settings: &AttitudeSettings, a_thrust_cmd_nue: &Nue, phi_rad: f64) -> Self {
        let q_guid = reference::q_guid(a_thrust_cmd_nue);
        Self {
            a_thrust_cmd_bits: command_bits(a_thrust_cmd_nue),
            phi_bits: phi_rad.to_bits(),
            q_guid,
            thrust_axis_nue: q_guid * conventions::thrust_axis_body(),
            q_ref: q_guid * settings.phi_cmd_rotation.at(phi_rad),
        }
    }

    /// The reference for `a_thrust_cmd_nue` and `phi_rad`: `kept` if it was computed from the
    /// same bits, else computed into `kept` (only `q_ref` when only the angle moved).
    #[inline(always)]
    pub fn keep<'a>(
        kept: &'a mut Option<Self>,
        settings: &AttitudeSettings,
        a_thrust_cmd_nue: &Nue,
        phi_rad: f64,
    ) -> &'a Self {
        let same_command = kept
            .as_ref()
            .is_some_and(|r| r.a_thrust_cmd_bits == command_bits(a_thrust_cmd_nue));
        if !same_command {
            return kept.insert(Self::new(settings, a_thrust_cmd_nue, phi_rad));
        }
        // Never computed here (the command was kept): out of line, so that the test of the
        // kept value is inlined.
        let r = kept.get_or_insert_with(|| Self::computed(settings, a_thrust_cmd_nue, phi_rad));
        if r.phi_bits != phi_rad.to_bits() {
            r.phi_bits = phi_rad.to_bits();
            r.q_ref = r.q_guid * settings.phi_cmd_rotation.at(phi_rad);
        }
        r
    }

    #[cold]
    #[inline(never)]
    fn computed(settings: &AttitudeSettings, a_thrust_cmd_nue: &Nue, phi_rad: f64) -> Self {
        Self::new(settings, a_thrust_cmd_nue, phi_rad)
    }
}

#[inline(always)]
fn command_bits(a_thrust_cmd_nue: &Nue) -> [u64; 3] {
    let a = &a_thrust_cmd_nue.0;
    [a.x.to_bits(), a.y.to_bits(), a.z.to_bits()]
}
