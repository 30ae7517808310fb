//! Exact partial derivatives of LanderGnc's outputs with respect to its inputs at a
//! communication point (FMI's directional derivatives in Co-Simulation, Step Mode).
//!
//! **What is differentiated.** FMI defines the partials in Step Mode as those of the
//! equations `outputs = f(inputs, rest)` the FMU solves in that state, the rest (its memory)
//! held. LanderGnc's outputs at a communication point are the sample at that point, computed
//! from the inputs there and the committed memory (`fmu.rs`: a get evaluates the sample, the
//! step commits it), and its `ModelStructure` declares every output dependent on every input.
//! So the partials here are those of the sample at the instance's current time: the attitude
//! law's torque with respect to `q_body_to_nue` (through the normalisation of the input
//! quaternion) and `omega_body`, the thrust with respect to `mass`, the angle errors and
//! `phi_b`, `tilt_error`; every other output (guidance command and phase, reference attitude,
//! time-to-go, supervision, the torque model's zero duties) is held over the sample and has
//! zero partials. A sample that opens a guidance cycle also solves the guidance from `r_nue`,
//! `v_nue` and `mass`: its partials with respect to those three are refused (naming the
//! sample), those with respect to the attitude and rates stay exact.
//!
//! **How.** Forward mode: one pass of the law in dual numbers (value and one directional
//! derivative) seeded with the master's seed, a second copy of the path written for them
//! (quaternions scalar-first, transcendental functions through libm); the f64 path that flies
//! is untouched. Saturated channels have zero partials, as the saturation is flat there.
use crate::attitude::gains::AttitudeGains;
use crate::attitude::profile::PhiProfile;
use crate::attitude::reference;
use crate::attitude::ControlLaw;
use crate::controller::{gnc_advance, NavigationInputs};
use crate::guidance::sequencer::GuidanceState;
use crate::params::GncDesign;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A value and its derivative along the seed.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Dual {
    v: f64,
    d: f64,
}

impl Dual {
    const fn c(v: f64) -> Self {
        Self { v, d: 0.0 }
    }
    fn sqrt(self) -> Self {
        let r = libm::sqrt(self.v);
        Self {
            v: r,
            d: self.d / (2.0 * r),
        }
    }
    fn atan2(self, x: Self) -> Self {
        let n = self.v * self.v + x.v * x.v;
        Self {
            v: libm::atan2(self.v, x.v),
            d: (x.v * self.d - self.v * x.d) / n,
        }
    }
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = libm::sincos(self.v);
        (
            Self {
                v: s,
                d: c * self.d,
            },
            Self {
                v: c,
                d: -s * self.d,
            },
        )
    }
}

impl Add for Dual {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            v: self.v + o.v,
            d: self.d + o.d,
        }
    }
}
impl Sub for Dual {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self {
            v: self.v - o.v,
            d: self.d - o.d,
        }
    }
}
impl Mul for Dual {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Self {
            v: self.v * o.v,
            d: self.d * o.v + self.v * o.d,
        }
    }
}
impl Div for Dual {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        Self {
            v: self.v / o.v,
            d: (self.d * o.v - self.v * o.d) / (o.v * o.v),
        }
    }
}
impl Neg for Dual {
    type Output = Self;
    fn neg(self) -> Self {
        Self {
            v: -self.v,
            d: -self.d,
        }
    }
}

/// A quaternion scalar first, `[w, x, y, z]`.
type Quat = [Dual; 4];
type Vec3 = [Dual; 3];

fn mul(a: &Quat, b: &Quat) -> Quat {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

fn conj(q: &Quat) -> Quat {
    [q[0], -q[1], -q[2], -q[3]]
}

/// `q` or `-q`, whichever has a non-negative scalar part (by value, as `canonical`).
fn canonical(q: Quat) -> Quat {
    if q[0].v < 0.0 {
        q.map(|c| -c)
    } else {
        q
    }
}

fn constant(q: &crate::conventions::Attitude) -> Quat {
    [q.w, q.i, q.j, q.k].map(Dual::c)
}

/// `q ⊗ [0, v] ⊗ q*`, the vector part.
fn rotate(q: &Quat, v: &Vec3) -> Vec3 {
    let r = mul(&mul(q, &[Dual::c(0.0), v[0], v[1], v[2]]), &conj(q));
    [r[1], r[2], r[3]]
}

fn cross(a: &Vec3, b: &Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: &Vec3, b: &Vec3) -> Dual {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: &Vec3) -> Dual {
    dot(a, a).sqrt()
}

/// `[cos(angle/2), 0, sin(angle/2), 0]`: a rotation about the thrust axis.
fn about_thrust_axis(angle: Dual) -> Quat {
    let (s, c) = (angle * Dual::c(0.5)).sin_cos();
    [c, Dual::c(0.0), s, Dual::c(0.0)]
}

const THRUST_AXIS: Vec3 = [Dual::c(0.0), Dual::c(1.0), Dual::c(0.0)];

/// `phi_b` (attitude/phi_b.rs): the third 1-3-2 angle; its derivative is 0 only where the
/// angle itself jumps.
fn phi_b(q: &Quat) -> Dual {
    let a31 = Dual::c(2.0) * (q[1] * q[3] + q[0] * q[2]);
    let a11 = q[0] * q[0] + q[1] * q[1] - q[2] * q[2] - q[3] * q[3];
    a31.atan2(a11)
}

/// `2 q_ev` of `canonical(q_ref^-1 ⊗ q)` (attitude/coupled.rs).
fn coupled_error(q: &Quat, q_ref: &Quat) -> Vec3 {
    let e = canonical(mul(&conj(q_ref), q));
    [e[1], e[2], e[3]].map(|c| c * Dual::c(2.0))
}

/// The reduced law's target (attitude/reduced.rs). The tilt onto the reference thrust axis
/// is the shortest-arc rotation `normalise([1 + u.v, u x v])`, the same rotation as the law's
/// axis-angle form and smooth where the axes meet, so that its derivative is defined there.
fn reduced_target(q: &Quat, q_ref: &Quat, weight: f64) -> Quat {
    let now = rotate(q, &THRUST_AXIS);
    let target = rotate(q_ref, &THRUST_AXIS);
    let axis = cross(&now, &target);
    let tilt = libm::atan2(norm(&axis).v, dot(&now, &target).v);
    if tilt > std::f64::consts::PI - 1e-4 {
        return *q_ref;
    }
    let raw = [Dual::c(1.0) + dot(&now, &target), axis[0], axis[1], axis[2]];
    let length = (raw[0] * raw[0] + raw[1] * raw[1] + raw[2] * raw[2] + raw[3] * raw[3]).sqrt();
    let tilt_nue = raw.map(|c| c / length);
    let tilted = mul(&tilt_nue, q);
    let remaining = canonical(mul(&conj(&tilted), q_ref));
    let alpha = Dual::c(2.0) * remaining[2].atan2(remaining[0]);
    mul(
        &tilted,
        &about_thrust_axis(alpha * Dual::c(weight.clamp(0.0, 1.0))),
    )
}

/// The braking-limited error (attitude/gains.rs): the error itself below the corner, the
/// braking limit above it.
fn shaped(e: Dual, kp: f64, kd: f64, braking: f64) -> Dual {
    if !(braking.is_finite() && kp > 0.0) {
        return e;
    }
    let magnitude = if e.v < 0.0 { -e } else { e };
    let limit = Dual::c(kd / kp) * (Dual::c(2.0 * braking) * magnitude).sqrt();
    if magnitude.v <= limit.v || e.v == 0.0 {
        e
    } else if e.v > 0.0 {
        limit
    } else {
        -limit
    }
}

/// The PD torque (attitude/gains.rs `pd_torque_body`), unsaturated.
fn pd_torque(gains: &AttitudeGains, error: &Vec3, omega: &Vec3, omega_ref: [f64; 3]) -> Vec3 {
    let inertia_omega: Vec3 = [0, 1, 2].map(|i| Dual::c(gains.inertia_kgm2[i]) * omega[i]);
    let gyroscopic = cross(omega, &inertia_omega);
    [0, 1, 2].map(|i| {
        let e = shaped(
            error[i],
            gains.kp_nm_per_rad[i],
            gains.kd_nms_per_rad[i],
            gains.braking_radps2[i],
        );
        -(Dual::c(gains.kp_nm_per_rad[i]) * e)
            - Dual::c(gains.kd_nms_per_rad[i]) * (omega[i] - Dual::c(omega_ref[i]))
            + gyroscopic[i]
    })
}

/// An input of LanderGnc, by element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    R(usize),
    V(usize),
    Q(usize),
    Omega(usize),
    Mass,
}

impl Input {
    /// The input's name as the model description has it (`r_nue[1]`).
    fn name(self) -> String {
        match self {
            Input::R(i) => format!("r_nue[{}]", i + 1),
            Input::V(i) => format!("v_nue[{}]", i + 1),
            Input::Q(i) => format!("q_body_to_nue[{}]", i + 1),
            Input::Omega(i) => format!("omega_body[{}]", i + 1),
            Input::Mass => "mass".to_owned(),
        }
    }
}

/// An output whose partials are computed; every other output is held over the sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Output {
    ThrustCmd,
    Torque(usize),
    ErrYaw,
    ErrRoll,
    ErrPitch,
    PhiB,
    TiltError,
    /// Held over the sample: zero partials.
    Held,
}

/// The memory and time a sample is taken with.
#[derive(Debug, Clone, Copy)]
pub struct At<'a> {
    pub design: &'a GncDesign,
    pub start_time_s: f64,
    pub guidance: &'a GuidanceState,
    pub profile: &'a PhiProfile,
    pub inputs: &'a NavigationInputs,
    pub time_s: f64,
}

/// `sensitivity = J seed` for the sample at `at`: `J` the partials of `unknowns` with
/// respect to `knowns`. The error says why a partial is not given.
pub fn directional(
    at: &At,
    unknowns: &[Output],
    knowns: &[Input],
    seed: &[f64],
    sensitivity: &mut [f64],
) -> Result<(), String> {
    let advance = gnc_advance(
        at.design,
        at.start_time_s,
        at.guidance,
        at.profile,
        at.inputs,
        at.time_s,
    );
    let solves = advance.guidance.last_cycle != at.guidance.last_cycle;
    if solves {
        if let Some((known, _)) = knowns
            .iter()
            .zip(seed)
            .find(|(k, s)| matches!(k, Input::R(_) | Input::V(_) | Input::Mass) && **s != 0.0)
        {
            return Err(format!(
                "t = {} s: the sample opens a guidance cycle and solves the guidance from \
                 r_nue, v_nue and mass; its partials with respect to {} are not given (ask \
                 between guidance cycles, or for the attitude and rates)",
                at.time_s,
                known.name()
            ));
        }
    }
    let nav = at.inputs;
    let mut q_raw: Quat = nav.q_body_to_nue.map(Dual::c);
    let mut omega: Vec3 = nav.omega_body_radps.map(Dual::c);
    let mut mass = Dual::c(nav.mass_kg);
    for (known, s) in knowns.iter().zip(seed) {
        match *known {
            Input::Q(i) => q_raw[i].d += s,
            Input::Omega(i) => omega[i].d += s,
            Input::Mass => mass.d += s,
            Input::R(_) | Input::V(_) => {}
        }
    }
    sensitivity.fill(0.0);
    // Degenerate inputs give the safe outputs, constants.
    if advance.attitude.is_none() {
        return Ok(());
    }
    let length =
        (q_raw[0] * q_raw[0] + q_raw[1] * q_raw[1] + q_raw[2] * q_raw[2] + q_raw[3] * q_raw[3])
            .sqrt();
    let q = q_raw.map(|c| c / length);
    let settings = &at.design.attitude;
    let roll = advance.roll;
    let q_guid = constant(&reference::q_guid(&advance.guidance.a_thrust_cmd_nue));
    let phi_b = phi_b(&q);
    let q_ref = mul(
        &q_guid,
        &constant(&settings.phi_cmd_rotation.at(roll.phi_rad)),
    );
    let error: Vec3 = match settings.law {
        ControlLaw::Decoupled => {
            let lateral = mul(&q_guid, &about_thrust_axis(phi_b));
            let e = canonical(mul(&conj(&lateral), &q));
            [
                e[1] * Dual::c(2.0),
                phi_b - Dual::c(roll.phi_rad),
                e[3] * Dual::c(2.0),
            ]
        }
        ControlLaw::Coupled => coupled_error(&q, &q_ref),
        ControlLaw::Reduced => {
            let target = reduced_target(&q, &q_ref, settings.reduced_yaw_weight);
            coupled_error(&q, &target)
        }
    };
    let torque = pd_torque(&settings.gains, &error, &omega, [0.0, roll.rate_radps, 0.0]);
    let now = rotate(&q, &THRUST_AXIS);
    let guided = rotate(&q_guid, &THRUST_AXIS);
    let across = cross(&now, &guided);
    let thrust = {
        let a = &advance.guidance.a_thrust_cmd_nue.0;
        let value = mass * Dual::c(a.norm());
        let p = &at.design.params;
        if advance.guidance.engine_cut || value.v > p.thrust_max_n || value.v < p.thrust_min_n {
            Dual::c(0.0)
        } else {
            value
        }
    };
    for (out, unknown) in sensitivity.iter_mut().zip(unknowns) {
        *out = match *unknown {
            Output::ThrustCmd => thrust.d,
            Output::Torque(i) => {
                let limit = settings.torque_limit_body_nm[i];
                if torque[i].v.is_nan() || torque[i].v.abs() > limit {
                    0.0
                } else {
                    torque[i].d
                }
            }
            Output::ErrYaw => error[0].d,
            Output::ErrRoll => error[1].d,
            Output::ErrPitch => error[2].d,
            Output::PhiB => phi_b.d,
            Output::TiltError => {
                let sine = norm(&across);
                if sine.v == 0.0 {
                    return Err(format!(
                        "t = {} s: tilt_error is 0, where it has no derivative (|angle|)",
                        at.time_s
                    ));
                }
                sine.atan2(dot(&now, &guided)).d
            }
            Output::Held => 0.0,
        };
    }
    Ok(())
}

/// [`directional`] for variables named as the declarations name them (`torque_cmd_body`,
/// element 0-based); `thrusters`: the thruster model, whose duties have no partials here.
pub fn by_name<'n>(
    at: &At,
    unknowns: impl Iterator<Item = (&'n str, usize)>,
    knowns: impl Iterator<Item = (&'n str, usize)>,
    seed: &[f64],
    sensitivity: &mut [f64],
) -> Result<(), String> {
    let thrusters = at.design.thrusters.is_some();
    let unknowns = unknowns
        .map(|(name, i)| {
            Ok(match name {
                "thrust_cmd" => Output::ThrustCmd,
                "torque_cmd_body" => Output::Torque(i),
                "err_yaw" => Output::ErrYaw,
                "err_roll" => Output::ErrRoll,
                "err_pitch" => Output::ErrPitch,
                "phi_b" => Output::PhiB,
                "tilt_error" => Output::TiltError,
                "rcs_duty" if thrusters => {
                    return Err(format!(
                        "rcs_duty[{}]: the thruster model's pulse modulation has no \
                         derivative",
                        i + 1
                    ))
                }
                _ => Output::Held,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let knowns = knowns
        .map(|(name, i)| match name {
            "r_nue" => Ok(Input::R(i)),
            "v_nue" => Ok(Input::V(i)),
            "q_body_to_nue" => Ok(Input::Q(i)),
            "omega_body" => Ok(Input::Omega(i)),
            "mass" => Ok(Input::Mass),
            other => Err(format!("'{other}' is not an input of LanderGnc")),
        })
        .collect::<Result<Vec<_>, String>>()?;
    directional(at, &unknowns, &knowns, seed, sensitivity)
}

#[cfg(test)]
// std's functions here build test attitudes, independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;
    use crate::controller::gnc_sample;
    use crate::params::GncParameters;

    /// A small deterministic generator (xorshift), uniform in [-1, 1).
    struct Draws(u64);
    impl Draws {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    const INPUTS: [Input; 14] = [
        Input::R(0),
        Input::R(1),
        Input::R(2),
        Input::V(0),
        Input::V(1),
        Input::V(2),
        Input::Q(0),
        Input::Q(1),
        Input::Q(2),
        Input::Q(3),
        Input::Omega(0),
        Input::Omega(1),
        Input::Omega(2),
        Input::Mass,
    ];
    const OUTPUTS: [Output; 8] = [
        Output::ThrustCmd,
        Output::Torque(0),
        Output::Torque(1),
        Output::Torque(2),
        Output::ErrYaw,
        Output::ErrRoll,
        Output::ErrPitch,
        Output::PhiB,
    ];

    fn nudge(nav: &NavigationInputs, input: Input, delta: f64) -> NavigationInputs {
        let mut n = *nav;
        match input {
            Input::R(i) => n.r_nue_m[i] += delta,
            Input::V(i) => n.v_nue_mps[i] += delta,
            Input::Q(i) => n.q_body_to_nue[i] += delta,
            Input::Omega(i) => n.omega_body_radps[i] += delta,
            Input::Mass => n.mass_kg += delta,
        }
        n
    }

    fn value(sample: &crate::controller::GncOutputs, output: Output) -> f64 {
        match output {
            Output::ThrustCmd => sample.thrust_cmd_n,
            Output::Torque(i) => sample.torque_cmd_body_nm[i],
            Output::ErrYaw => sample.err_yaw_rad,
            Output::ErrRoll => sample.err_roll_rad,
            Output::ErrPitch => sample.err_pitch_rad,
            Output::PhiB => sample.phi_b_rad,
            Output::TiltError => sample.tilt_error_rad,
            Output::Held => 0.0,
        }
    }

    /// A sample of the law with the guidance solved (held over the sample), at a random
    /// attitude within 70 deg of upright and random rates.
    struct Case {
        design: GncDesign,
        guidance: GuidanceState,
        profile: PhiProfile,
        nav: NavigationInputs,
        time_s: f64,
    }

    fn case(law: i32, torque_limit: f64, draws: &mut Draws) -> Case {
        let params = GncParameters {
            control_law: law,
            torque_limit_body_nm: [torque_limit; 3],
            ..GncParameters::default()
        };
        let design = params.design().unwrap();
        let axis = nalgebra::Vector3::new(draws.next(), draws.next(), draws.next());
        let angle = 1.2 * draws.next();
        let q =
            nalgebra::UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle)
                * nalgebra::UnitQuaternion::from_axis_angle(
                    &nalgebra::Vector3::y_axis(),
                    3.0 * draws.next(),
                );
        let nav = NavigationInputs {
            // Near the hover target, so that the guidance's command is inside the engines'
            // range (at its limit the thrust has a corner, one-sided partials).
            r_nue_m: [draws.next(), 799.5 + 0.5 * draws.next(), draws.next()],
            v_nue_mps: [0.1 * draws.next(), 0.1 * draws.next(), 0.1 * draws.next()],
            q_body_to_nue: [q.w, q.i, q.j, q.k],
            omega_body_radps: [0.3 * draws.next(), 0.3 * draws.next(), 0.3 * draws.next()],
            mass_kg: 880.0 + 10.0 * draws.next(),
        };
        // Mid-cycle: the guidance of this cycle solved already, as a committed step leaves it.
        let time_s = 5.05;
        let profile = PhiProfile::default();
        let solved = gnc_advance(
            &design,
            0.0,
            &GuidanceState::initial(1.62),
            &profile,
            &nav,
            time_s,
        );
        Case {
            design,
            guidance: solved.guidance,
            profile,
            nav,
            time_s,
        }
    }

    fn exact(c: &Case, known: Input) -> Vec<f64> {
        let at = At {
            design: &c.design,
            start_time_s: 0.0,
            guidance: &c.guidance,
            profile: &c.profile,
            inputs: &c.nav,
            time_s: c.time_s,
        };
        let mut column = vec![f64::NAN; OUTPUTS.len()];
        directional(&at, &OUTPUTS, &[known], &[1.0], &mut column).unwrap();
        column
    }

    fn central(c: &Case, known: Input, h: f64) -> Vec<f64> {
        let at = |nav: &NavigationInputs| {
            gnc_sample(&c.design, 0.0, &c.guidance, &c.profile, nav, c.time_s).outputs
        };
        let (plus, minus) = (at(&nudge(&c.nav, known, h)), at(&nudge(&c.nav, known, -h)));
        OUTPUTS
            .iter()
            .map(|&o| (value(&plus, o) - value(&minus, o)) / (2.0 * h))
            .collect()
    }

    #[test]
    fn every_law_s_partials_match_central_differences_at_random_attitudes_and_rates() {
        let mut draws = Draws(0x9e37_79b9_7f4a_7c15);
        for law in [1, 2, 3] {
            for _ in 0..40 {
                // GIVEN a point of the law's smooth part (limits out of reach)
                let c = case(law, 1e9, &mut draws);
                for known in INPUTS {
                    // WHEN the exact column is asked for
                    let exact = exact(&c, known);
                    // THEN it is the central difference of the f64 path that flies, to the
                    // difference's own error (step 1e-6: truncation 1e-12 x the third
                    // derivative, rounding 1e-16 x |value| / 1e-6)
                    let fd = central(&c, known, 1e-6);
                    for (k, (e, f)) in exact.iter().zip(&fd).enumerate() {
                        let tolerance = 1e-5 * (1.0 + f.abs());
                        assert!(
                            (e - f).abs() < tolerance,
                            "law {law}, d {:?} / d {known:?}: exact {e}, differences {f}",
                            OUTPUTS[k]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn the_rate_partials_are_the_pd_law_s_by_hand() {
        // d tau / d omega = -Kd + d(omega x I omega)/d omega = -Kd + [omega]x I - [I omega]x,
        // unsaturated, for every law (the error does not depend on omega)
        let mut draws = Draws(7);
        for law in [1, 2, 3] {
            let c = case(law, 1e9, &mut draws);
            let g = &c.design.attitude.gains;
            let w = nalgebra::Vector3::from(c.nav.omega_body_radps);
            let inertia = nalgebra::Matrix3::from_diagonal(&g.inertia_kgm2);
            let expected = -nalgebra::Matrix3::from_diagonal(&g.kd_nms_per_rad)
                + w.cross_matrix() * inertia
                - (inertia * w).cross_matrix();
            for j in 0..3 {
                let column = exact(&c, Input::Omega(j));
                for i in 0..3 {
                    assert!(
                        (column[1 + i] - expected[(i, j)]).abs()
                            < 1e-9 * (1.0 + expected[(i, j)].abs()),
                        "law {law}: d tau_{i} / d omega_{j} = {} vs {}",
                        column[1 + i],
                        expected[(i, j)]
                    );
                }
            }
        }
    }

    #[test]
    fn near_the_reference_the_attitude_partials_are_minus_kp() {
        // GIVEN the attitude on the reference (coupled law: its error is the body rotation
        // from the reference; the decoupled law's roll error is the 1-3-2 angle, which a
        // tilted attitude couples to the other axes), at rest
        let mut draws = Draws(11);
        let mut c = case(1, 1e9, &mut draws);
        let q_ref = reference::q_guid(&c.guidance.a_thrust_cmd_nue)
            * c.design.attitude.phi_cmd_rotation.at(0.0);
        c.nav.q_body_to_nue = [q_ref.w, q_ref.i, q_ref.j, q_ref.k];
        c.nav.omega_body_radps = [0.0; 3];
        // WHEN the attitude turns by a small body rotation delta: dq = q (0, delta / 2)
        let g = &c.design.attitude.gains;
        for axis in 0..3 {
            let mut delta = [0.0; 3];
            delta[axis] = 1.0;
            let dq = q_ref.into_inner()
                * nalgebra::Quaternion::new(0.0, delta[0] / 2.0, delta[1] / 2.0, delta[2] / 2.0);
            let at = At {
                design: &c.design,
                start_time_s: 0.0,
                guidance: &c.guidance,
                profile: &c.profile,
                inputs: &c.nav,
                time_s: c.time_s,
            };
            let mut torque = [0.0; 3];
            directional(
                &at,
                &[Output::Torque(0), Output::Torque(1), Output::Torque(2)],
                &[Input::Q(0), Input::Q(1), Input::Q(2), Input::Q(3)],
                &[dq.w, dq.i, dq.j, dq.k],
                &mut torque,
            )
            .unwrap();
            // THEN the torque answers with -Kp on that axis alone
            for i in 0..3 {
                let expected = if i == axis { -g.kp_nm_per_rad[i] } else { 0.0 };
                assert!(
                    (torque[i] - expected).abs() < 1e-6 * g.kp_nm_per_rad[i],
                    "axis {axis}: {torque:?}"
                );
            }
        }
    }

    #[test]
    fn saturated_torques_have_zero_partials_and_a_guidance_solve_refuses_position() {
        let mut draws = Draws(3);
        let c = case(2, 116.0, &mut draws);
        let at = At {
            design: &c.design,
            start_time_s: 0.0,
            guidance: &c.guidance,
            profile: &c.profile,
            inputs: &c.nav,
            time_s: c.time_s,
        };
        let outputs = gnc_sample(&c.design, 0.0, &c.guidance, &c.profile, &c.nav, c.time_s).outputs;
        let mut column = [f64::NAN; 3];
        directional(&at, &OUTPUTS[1..4], &[Input::Omega(0)], &[1.0], &mut column).unwrap();
        let mut saturated = 0;
        for (partial, torque) in column.iter().zip(outputs.torque_cmd_body_nm) {
            if torque.abs() >= 116.0 {
                assert_eq!(*partial, 0.0);
                saturated += 1;
            }
        }
        assert!(saturated > 0, "{:?}", outputs.torque_cmd_body_nm);
        // A sample that opens a guidance cycle: position refused, attitude given
        let fresh = GuidanceState::initial(1.62);
        let opening = At {
            guidance: &fresh,
            ..at
        };
        let error = directional(
            &opening,
            &[Output::ThrustCmd],
            &[Input::R(1)],
            &[1.0],
            &mut [0.0],
        )
        .unwrap_err();
        assert!(
            error.contains("opens a guidance cycle") && error.contains("r_nue[2]"),
            "{error}"
        );
        directional(
            &opening,
            &[Output::Torque(0)],
            &[Input::Omega(0)],
            &[1.0],
            &mut [0.0],
        )
        .unwrap();
    }
}
