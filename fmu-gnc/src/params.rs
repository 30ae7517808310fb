//! The GNC parameters, their defaults (paper Tables I-II and the ERRATA modelling defaults)
//! and their validation (relations between them; each value's own bounds are declared in
//! `fmu.rs`).
use crate::actuation::allocation::{default_layout_column, Allocator, DEFAULT_THRUSTER_FORCE_N};
use crate::actuation::pwpf::PwpfSettings;
use crate::actuation::{RcsModel, THRUSTER_COUNT};
use crate::attitude::gains::AttitudeGains;
use crate::attitude::profile::ProfileLimits;
use crate::attitude::{AttitudeSettings, ControlLaw, ThrustAxisRotation};
use crate::guidance::pv::PvGains;
use crate::guidance::sequencer::{Handover, Retarget, Scenario};
use crate::guidance::terminal::TerminalDescent;
use crate::supervision::consistency::MonitorSettings;
use crate::supervision::feasibility::Limits;
use crate::supervision::SupervisionSettings;
use lander_math::frames::Nue;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// All parameters, SI units, NUE / body axes as named.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GncParameters {
    /// The value of an item of [`ControlLaw`].
    pub control_law: i32,
    pub phi_cmd_rad: f64,
    /// Absolute simulation time at which `phi_cmd` is applied (0 before it).
    pub phi_cmd_time_s: f64,
    pub control_bandwidth_hz: f64,
    pub control_damping: f64,
    pub guidance_bandwidth_hz: f64,
    pub guidance_damping: f64,
    pub guidance_cycle_s: f64,
    pub inertia_body_kgm2: [f64; 3],
    pub thrust_min_n: f64,
    pub thrust_max_n: f64,
    pub torque_limit_body_nm: [f64; 3],
    pub gravity_mps2: f64,
    pub hover_target_nue_m: [f64; 3],
    pub hover_duration_s: f64,
    pub descent_target_nue_m: [f64; 3],
    pub descent_time_to_go_s: f64,
    pub descent_freeze_time_to_go_s: f64,
    pub target_hover_duration_s: f64,
    /// The descent's cubic starts from the hover's last command (the paper), else from zero
    /// net acceleration ([`Handover`]).
    pub descent_from_hover_command: bool,
    pub reduced_yaw_weight: f64,
    pub rate_shaping_margin: f64,
    /// Terminal-descent sink rate after the target hover; 0 = none (the paper).
    pub terminal_descent_speed_mps: f64,
    /// The terminal descent's slowing profile and engine cut-off (`TerminalDescent`).
    pub terminal_final_speed_mps: f64,
    pub terminal_flare_time_s: f64,
    pub terminal_ground_height_m: f64,
    pub engine_cutoff_height_m: f64,
    /// Shaped thrust-axis manoeuvre: rate and acceleration limits of the profile `phi_cmd` is
    /// followed through; 0 = that one unlimited, both 0 = the paper's step.
    pub phi_rate_limit_radps: f64,
    pub phi_accel_limit_radps2: f64,
    /// Retarget (beyond the paper): time after the start at which the site becomes
    /// `retarget_site_nue_m`; negative = never (the paper).
    pub retarget_time_s: f64,
    pub retarget_site_nue_m: [f64; 3],
    /// Tilt from vertical the re-planned divert may count on.
    pub retarget_max_tilt_rad: f64,
    /// Re-plan the divert for the lateral authority (else only move the target).
    pub retarget_replan: bool,
    /// Enumeration value: 1 torque per axis, 2 eight thrusters.
    pub rcs_model: i32,
    /// Thruster geometry (thruster `k` at `3k..3k+3`), as the plant's; body axes.
    pub rcs_position_body_m: [f64; 3 * THRUSTER_COUNT],
    pub rcs_direction_body: [f64; 3 * THRUSTER_COUNT],
    pub rcs_thruster_force_n: f64,
    /// Beyond the thrusters' reach, serve the tilt torque first (else keep the direction).
    pub rcs_tilt_first: bool,
    pub pwpf_gain: f64,
    pub pwpf_time_constant_s: f64,
    pub pwpf_on_threshold: f64,
    pub pwpf_off_threshold: f64,
    /// The period a duty refers to: the communication step, s.
    pub rcs_duty_period_s: f64,
    /// The input consistency monitor (supervision, beyond the paper) is on.
    pub input_monitor: bool,
    /// A command at a limit of its range for longer than this is reported, s.
    pub saturation_time_s: f64,
}

/// Everything the samples use that follows from the parameters alone, derived once from
/// validated parameters (at the end of initialization), not at every sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GncDesign {
    pub params: GncParameters,
    pub scenario: Scenario,
    pub attitude: AttitudeSettings,
    /// `None`: the paper's step in `phi_cmd`.
    pub roll_profile: Option<ProfileLimits>,
    /// `None`: the torque model (no thrusters to drive).
    pub thrusters: Option<ThrusterDesign>,
    /// What the supervision reads of the parameters.
    pub supervision: SupervisionSettings,
}

/// The thruster chain as the samples use it: allocation geometry and modulator settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThrusterDesign {
    pub allocator: Allocator,
    pub pwpf: PwpfSettings,
}

impl Default for GncParameters {
    fn default() -> Self {
        Self {
            control_law: ControlLaw::Decoupled as i32,
            phi_cmd_rad: 0.0,
            phi_cmd_time_s: 12.0,
            control_bandwidth_hz: 0.5,
            control_damping: 0.8,
            guidance_bandwidth_hz: 0.06,
            guidance_damping: 0.8,
            guidance_cycle_s: 0.1,
            inertia_body_kgm2: [400.0, 300.0, 450.0],
            thrust_min_n: 720.0,
            thrust_max_n: 1600.0,
            torque_limit_body_nm: [116.0; 3],
            gravity_mps2: 1.62,
            hover_target_nue_m: [0.0, 800.0, 0.0],
            hover_duration_s: 12.0,
            descent_target_nue_m: [0.0, 150.0, 0.0],
            descent_time_to_go_s: 130.0,
            descent_freeze_time_to_go_s: 5.0,
            target_hover_duration_s: 30.0,
            descent_from_hover_command: true,
            reduced_yaw_weight: 0.4,
            rate_shaping_margin: 0.0,
            terminal_descent_speed_mps: 0.0,
            terminal_final_speed_mps: 0.0,
            terminal_flare_time_s: 0.0,
            terminal_ground_height_m: 0.0,
            engine_cutoff_height_m: -1.0,
            phi_rate_limit_radps: 0.0,
            phi_accel_limit_radps2: 0.0,
            retarget_time_s: -1.0,
            retarget_site_nue_m: [0.0, 150.0, 0.0],
            retarget_max_tilt_rad: 15.0 * std::f64::consts::PI / 180.0,
            retarget_replan: true,
            rcs_model: RcsModel::Torque as i32,
            rcs_position_body_m: default_layout_column(false),
            rcs_direction_body: default_layout_column(true),
            rcs_thruster_force_n: DEFAULT_THRUSTER_FORCE_N,
            rcs_tilt_first: true,
            // PWPF: Km 10, Tm 0.5 s, Uon 0.5, Uoff 0.2 (docs/rcs-layout.md explains the choice).
            pwpf_gain: 10.0,
            pwpf_time_constant_s: 0.5,
            pwpf_on_threshold: 0.5,
            pwpf_off_threshold: 0.2,
            rcs_duty_period_s: 0.01,
            input_monitor: true,
            // Twice the longest saturation of the shipped scenarios (14 s: full-fidelity's
            // unshaped 150 deg roll from t = 0 holds the roll torque at its limit).
            saturation_time_s: 30.0,
        }
    }
}

/// Beyond these the products and powers the guidance forms (gains times position errors,
/// the cubic's `1 / tgo^3`, sums of durations) could overflow; no landing comes near them.
/// Durations: 11 days. Targets: 10 000 km, beyond the Moon's radius.
pub const MAX_DURATION_S: f64 = 1e6;
pub const MAX_TARGET_M: f64 = 1e7;
/// A guidance cycle shorter than 1 ms is no sampled guidance (and its Nyquist-bounded gains
/// would grow as `1 / cycle^2`).
pub const MIN_GUIDANCE_CYCLE_S: f64 = 1e-3;
/// Ten times Earth's: a gravity that makes the thrust terms overflow is refused long before.
pub const MAX_GRAVITY_MPS2: f64 = 100.0;

/// A damping ratio beyond this is no design (and its gains grow without bound).
pub const MAX_DAMPING: f64 = 100.0;
/// The largest inertia; with it, the gyroscopic term `omega x I omega` stays finite for any
/// admissible body rate.
pub const MAX_INERTIA_KGM2: f64 = 1e9;
/// The body rate up to which the gains' torques must stay finite (`Kd omega`); the error
/// term `Kp e` is checked up to a full turn.
pub const MAX_ADMISSIBLE_RATE_RADPS: f64 = 1e3;

/// Thrust-axis command and profile limits: two turns either way; 100 rad/s and 1e4 rad/s2
/// are far beyond any RCS, and keep the profile's squares and quotients finite.
pub const MAX_PHI_CMD_RAD: f64 = 4.0 * std::f64::consts::PI;
pub const MAX_PHI_RATE_RADPS: f64 = 100.0;
pub const MAX_PHI_ACCEL_RADPS2: f64 = 1e4;

/// Thrust and torque limits: thirty Saturn V first stages, and a torque to match; with them
/// the thrust-per-mass terms of the guidance stay finite.
pub const MAX_THRUST_N: f64 = 1e9;
pub const MAX_TORQUE_NM: f64 = 1e9;

pub use fmi_model::parameter::ParameterError;

fn check(ok: bool, field: &'static str, value: f64, reason: &str) -> Result<(), ParameterError> {
    ParameterError::require(ok, field, None, value, reason)
}

fn check_at(
    ok: bool,
    field: &'static str,
    index: Option<usize>,
    value: f64,
    reason: &str,
) -> Result<(), ParameterError> {
    ParameterError::require(ok, field, index, value, reason)
}

impl GncParameters {
    /// What the declarations cannot say (each value on its own is checked against its
    /// declaration first, [`GncParameters::check`]): relations between parameters, and gains
    /// that overflow in combination. The error names the field.
    pub fn validate(&self) -> Result<(), ParameterError> {
        let p = self;
        // Guidance is held over its cycle: a loop faster than the cycle's Nyquist rate is not a
        // loop any more (and absurd values overflow the gains to NaN).
        check(
            p.guidance_bandwidth_hz <= 0.5 / p.guidance_cycle_s,
            "guidance_bandwidth_hz",
            p.guidance_bandwidth_hz,
            "must be <= 0.5 / guidance_cycle (the Nyquist rate of the guidance cycle)",
        )?;
        let gains = p.attitude_gains();
        // Kp = I w^2 and Kd = 2 zeta w I: the bandwidth is the factor that can grow without a
        // bound of its own, so it is the one named.
        check(
            gains
                .kp_nm_per_rad
                .iter()
                .all(|k| (k * std::f64::consts::TAU).is_finite())
                && gains
                    .kd_nms_per_rad
                    .iter()
                    .all(|k| (k * MAX_ADMISSIBLE_RATE_RADPS).is_finite()),
            "control_bandwidth_hz",
            p.control_bandwidth_hz,
            "gives gains whose torques overflow with this inertia",
        )?;
        check(
            p.thrust_max_n >= p.thrust_min_n,
            "thrust_max_n",
            p.thrust_max_n,
            "must be >= thrust_min",
        )?;
        // The last solve then has tgo >= one guidance cycle: no division by a vanishing tgo.
        check(
            p.descent_freeze_time_to_go_s >= p.guidance_cycle_s,
            "descent_freeze_time_to_go_s",
            p.descent_freeze_time_to_go_s,
            "must be >= guidance_cycle",
        )?;
        check(
            p.terminal_final_speed_mps <= p.terminal_descent_speed_mps
                || p.terminal_flare_time_s == 0.0,
            "terminal_final_speed_mps",
            p.terminal_final_speed_mps,
            "must be, with a flare time, <= terminal_descent_speed",
        )?;
        self.validate_rcs()
    }

    /// The thruster chain's relations (checked in either RCS model).
    fn validate_rcs(&self) -> Result<(), ParameterError> {
        let p = self;
        for k in 0..THRUSTER_COUNT {
            let d = &p.rcs_direction_body[3 * k..3 * k + 3];
            let norm = d.iter().map(|x| x * x).sum::<f64>().sqrt();
            check_at(
                (norm - 1.0).abs() <= 1e-6,
                "rcs_direction_body",
                Some(3 * k),
                d[0],
                "the thruster's direction must be a unit vector (norm within 1e-6 of 1)",
            )?;
        }
        check(
            p.pwpf_on_threshold > p.pwpf_off_threshold,
            "pwpf_on_threshold",
            p.pwpf_on_threshold,
            "must be > pwpf_off_threshold (the trigger's hysteresis)",
        )
    }

    /// The RCS model (torque for values `validate` refuses).
    pub fn rcs(&self) -> RcsModel {
        RcsModel::from_index(self.rcs_model).unwrap_or(RcsModel::Torque)
    }

    pub fn allocator(&self) -> Allocator {
        Allocator::new(
            &self.rcs_position_body_m,
            &self.rcs_direction_body,
            self.rcs_thruster_force_n,
        )
    }

    pub fn pwpf_settings(&self) -> PwpfSettings {
        PwpfSettings {
            gain: self.pwpf_gain,
            time_constant_s: self.pwpf_time_constant_s,
            on_threshold: self.pwpf_on_threshold,
            off_threshold: self.pwpf_off_threshold,
        }
    }

    /// Check, then derive what the samples use.
    pub fn design(&self) -> Result<GncDesign, ParameterError> {
        self.check()?;
        Ok(self.design_unchecked())
    }

    /// What the samples use, from parameters that may not be valid (outputs shown in
    /// initialization mode, before validation): an unknown law shows the decoupled one.
    pub fn design_unchecked(&self) -> GncDesign {
        GncDesign {
            params: *self,
            scenario: self.scenario(),
            attitude: self.attitude_settings_for(
                ControlLaw::from_index(self.control_law).unwrap_or(ControlLaw::Decoupled),
            ),
            roll_profile: ProfileLimits::from_parameters(
                self.phi_rate_limit_radps,
                self.phi_accel_limit_radps2,
            ),
            thrusters: (self.rcs() == RcsModel::Thrusters).then(|| ThrusterDesign {
                allocator: self.allocator(),
                pwpf: self.pwpf_settings(),
            }),
            supervision: self.supervision_settings(),
        }
    }

    /// What the supervision reads of these parameters.
    pub fn supervision_settings(&self) -> SupervisionSettings {
        SupervisionSettings {
            monitor: MonitorSettings {
                gravity_mps2: self.gravity_mps2,
                inertia_body_kgm2: self.inertia_body_kgm2,
                torque_is_applied: self.rcs() == RcsModel::Torque,
            },
            monitor_enabled: self.input_monitor,
            limits: Limits::new(
                (self.thrust_min_n, self.thrust_max_n),
                self.torque_limit_body_nm,
                self.saturation_time_s,
            ),
        }
    }

    /// The guidance scenario these parameters describe.
    pub fn scenario(&self) -> Scenario {
        Scenario {
            hover_target_nue: Nue::from(self.hover_target_nue_m),
            hover_duration_s: self.hover_duration_s,
            descent_target_nue: Nue::from(self.descent_target_nue_m),
            descent_time_to_go_s: self.descent_time_to_go_s,
            freeze_time_to_go_s: self.descent_freeze_time_to_go_s,
            target_hover_duration_s: self.target_hover_duration_s,
            guidance_cycle_s: self.guidance_cycle_s,
            gravity_mps2: self.gravity_mps2,
            pv_gains: PvGains::from_bandwidth(self.guidance_bandwidth_hz, self.guidance_damping),
            thrust_min_n: self.thrust_min_n,
            thrust_max_n: self.thrust_max_n,
            terminal: TerminalDescent {
                speed_mps: self.terminal_descent_speed_mps,
                final_speed_mps: self.terminal_final_speed_mps,
                flare_time_s: self.terminal_flare_time_s,
                ground_height_m: self.terminal_ground_height_m,
                cutoff_height_m: self.engine_cutoff_height_m,
            },
            retarget: (self.retarget_time_s >= 0.0).then(|| Retarget {
                time_s: self.retarget_time_s,
                site_nue: Nue::from(self.retarget_site_nue_m),
                max_tilt_rad: self.retarget_max_tilt_rad,
                replan: self.retarget_replan,
            }),
            handover: if self.descent_from_hover_command {
                Handover::HoverCommand
            } else {
                Handover::ZeroNet
            },
        }
    }

    /// The attitude settings these parameters describe; the law is validated.
    pub fn attitude_settings(&self) -> Result<AttitudeSettings, ParameterError> {
        self.check()?;
        Ok(self.design_unchecked().attitude)
    }

    fn attitude_gains(&self) -> AttitudeGains {
        AttitudeGains::from_bandwidth(
            self.control_bandwidth_hz,
            self.control_damping,
            Vector3::from(self.inertia_body_kgm2),
        )
        .with_braking(
            &Vector3::from(self.torque_limit_body_nm),
            self.rate_shaping_margin,
        )
    }

    fn attitude_settings_for(&self, law: ControlLaw) -> AttitudeSettings {
        AttitudeSettings {
            law,
            gains: self.attitude_gains(),
            torque_limit_body_nm: Vector3::from(self.torque_limit_body_nm),
            reduced_yaw_weight: self.reduced_yaw_weight,
            phi_cmd_rotation: ThrustAxisRotation::new(self.phi_cmd_rad),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid() {
        assert_eq!(GncParameters::default().check(), Ok(()));
    }

    #[test]
    fn the_descent_starts_from_the_hover_command_unless_told_otherwise() {
        let paper = GncParameters::default();
        assert_eq!(paper.scenario().handover, Handover::HoverCommand);
        let flight = GncParameters {
            descent_from_hover_command: false,
            ..paper
        };
        assert_eq!(flight.scenario().handover, Handover::ZeroNet);
    }

    #[test]
    fn bad_values_are_refused_by_name() {
        type Spoil = fn(&mut GncParameters);
        let cases: [(&str, Spoil); 28] = [
            ("retarget_time_s", |p| p.retarget_time_s = 2e6),
            ("retarget_max_tilt_rad", |p| p.retarget_max_tilt_rad = 0.0),
            ("retarget_site_nue_m[2]", |p| p.retarget_site_nue_m[2] = 2e7),
            // each past a bound beyond which a product or power of the laws could overflow
            ("thrust_max_n", |p| p.thrust_max_n = 2e9),
            ("guidance_cycle_s", |p| p.guidance_cycle_s = 1e-4),
            ("descent_time_to_go_s", |p| p.descent_time_to_go_s = 1e300),
            ("gravity_mps2", |p| p.gravity_mps2 = 1e300),
            ("descent_target_nue_m[0]", |p| {
                p.descent_target_nue_m[0] = -2e7
            }),
            ("phi_cmd_rad", |p| p.phi_cmd_rad = 1e300),
            ("phi_rate_limit_radps", |p| p.phi_rate_limit_radps = 1e300),
            ("phi_accel_limit_radps2", |p| {
                p.phi_accel_limit_radps2 = -1.0
            }),
            ("inertia_body_kgm2[2]", |p| p.inertia_body_kgm2[2] = 1e300),
            ("guidance_damping", |p| p.guidance_damping = 1e300),
            ("control_law", |p| {
                // One past the last law, however many there are.
                let last = <ControlLaw as fmi_model::Enumeration>::TYPE.max();
                p.control_law = last.unwrap_or(0) + 1
            }),
            ("phi_cmd_rad", |p| p.phi_cmd_rad = f64::NAN),
            ("control_bandwidth_hz", |p| p.control_bandwidth_hz = 0.0),
            ("control_damping", |p| p.control_damping = -0.1),
            ("guidance_bandwidth_hz", |p| p.guidance_bandwidth_hz = -1.0),
            ("guidance_cycle_s", |p| p.guidance_cycle_s = 0.0),
            ("inertia_body_kgm2[1]", |p| p.inertia_body_kgm2[1] = -300.0),
            ("torque_limit_body_nm[2]", |p| {
                p.torque_limit_body_nm[2] = -1.0
            }),
            ("thrust_max_n", |p| p.thrust_min_n = 2000.0),
            ("descent_freeze_time_to_go_s", |p| {
                p.descent_freeze_time_to_go_s = 0.0
            }),
            ("reduced_yaw_weight", |p| p.reduced_yaw_weight = 1.5),
            ("rate_shaping_margin", |p| p.rate_shaping_margin = -0.1),
            ("guidance_bandwidth_hz", |p| {
                p.guidance_bandwidth_hz = 1.7e162
            }),
            ("control_bandwidth_hz", |p| p.control_bandwidth_hz = 1e300),
            ("hover_target_nue_m[1]", |p| {
                p.hover_target_nue_m[1] = f64::INFINITY
            }),
        ];
        for (name, spoil) in cases {
            let mut p = GncParameters::default();
            spoil(&mut p);
            let err = p.check().unwrap_err();
            let named = match err.index {
                Some(k) => format!("{}[{k}]", err.field),
                None => err.field.to_string(),
            };
            assert_eq!(named, name, "{err}");
        }
    }
}
