//! The input consistency monitor: does the navigation the GNC is given move the way its own
//! rates, velocity and commands say it should? A plant wired with another convention (a
//! scalar-last or conjugate quaternion, rates in deg/s, ENU axes, another gravity, inertia or
//! mass unit) flies on for a minute or two before it fails; the inputs betray it within a
//! second.
//!
//! Over windows of [`WINDOW_S`] the monitor compares
//! - the attitude's change with the body rates integrated,
//! - the position's change with the velocity integrated,
//! - the velocity's change with gravity plus the thrust along body +y the GNC commanded, for
//!   the mass it was given,
//! - the body rates' change with what the commanded torque gives the declared inertia.
//!
//! A check that fails in [`PERSISTENCE`] windows in a row is raised, once, with the likely
//! cause: the monitor tries the usual mistakes (scalar-last, conjugate, deg/s, ENU) and names
//! the one that explains the inputs. It observes only: nothing here changes a command.
//!
//! Per sample it integrates what the judgement of the inputs as given needs; the mistakes
//! that must be integrated to be tried (rates in deg/s, the quaternion scalar-last or
//! conjugated) only in a window whose failure would raise its check, the one after a failing
//! window: the cause is named only when a check is raised, so every verdict, residual and
//! message is what integrating them in every window gives.
//!
//! Thresholds are absolute plus relative, sized so that the shipped scenarios (sensor noise,
//! the filter's estimates, engine lag, the plant's own throttle and torque limits) stay
//! well inside them and each mistake lands well outside (docs/interface.md gives the numbers).
use nalgebra::{Matrix3, Quaternion, Vector3};
use serde::{Deserialize, Serialize};

/// Length of one comparison window.
pub const WINDOW_S: f64 = 0.5;
/// Failed windows in a row that raise a check: one window may straddle a transient (a
/// guidance phase change, an engine switched on), two in a row do not.
pub const PERSISTENCE: u8 = 2;

/// Attitude: the change and the integrated rates may differ by this much (rad) plus
/// [`ATTITUDE_RELATIVE`] of the larger rotation: gyro noise and a filter's attitude
/// corrections stay below a few milliradians in a window.
pub const ATTITUDE_ABSOLUTE_RAD: f64 = 0.01;
pub const ATTITUDE_RELATIVE: f64 = 0.25;
/// Position: metres per window plus a share of the distance flown.
pub const POSITION_ABSOLUTE_M: f64 = 1.0;
pub const POSITION_RELATIVE: f64 = 0.2;
/// Acceleration: m/s2 plus, along the thrust, a share of the predicted specific force; covers a plant that
/// clamps the command to its own throttle range (800 N against a thrust_min of 720 N) and an
/// engine's lag.
pub const ACCELERATION_ABSOLUTE_MPS2: f64 = 0.3;
pub const ACCELERATION_RELATIVE: f64 = 0.3;
/// Across the thrust axis: a share of the specific force for the attitude's error (0.1 is
/// 6 deg).
pub const ACCELERATION_ACROSS: f64 = 0.1;
/// Angular response: judged only when the commanded torque should change the rates by this
/// much in a window (a steady torque against a disturbance changes them by little); raised
/// when the response is off by more than [`ANGULAR_RATIO_LIMIT`] either way.
pub const ANGULAR_MIN_PREDICTED_RADPS: f64 = 0.03;
pub const ANGULAR_RATIO_LIMIT: f64 = 10.0;

/// Bits of the monitor's status output, one per check.
pub const ATTITUDE_BIT: i32 = 1;
pub const POSITION_BIT: i32 = 2;
pub const ACCELERATION_BIT: i32 = 4;
pub const ANGULAR_BIT: i32 = 8;

/// What the GNC was given at one sample, and the command that acts from it on.
/// `repr(C)`: its numbers lie side by side, for the test of [`usable`] to read in pairs.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[repr(C)]
pub struct Observation {
    pub t_s: f64,
    pub r_nue_m: [f64; 3],
    pub v_nue_mps: [f64; 3],
    /// As exchanged: scalar first if the plant keeps the convention.
    pub q_body_to_nue: [f64; 4],
    pub omega_body_radps: [f64; 3],
    pub mass_kg: f64,
    pub thrust_cmd_n: f64,
    pub torque_cmd_body_nm: [f64; 3],
    /// The ground may push on the vehicle (terminal descent near the ground, engine cut):
    /// forces other than thrust and gravity, so the acceleration and angular checks rest.
    pub ground_contact_possible: bool,
}

/// What the monitor needs of the parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MonitorSettings {
    pub gravity_mps2: f64,
    pub inertia_body_kgm2: [f64; 3],
    /// `torque_cmd_body` is the torque the plant applies (the torque model). Thrusters
    /// deliver what the allocation and the modulators make of it, another torque from
    /// window to window: the angular check then rests.
    pub torque_is_applied: bool,
}

/// The residuals of the last window judged (as predicted before the first).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Residuals {
    /// Angle between the attitude's change and the integrated rates, rad.
    pub attitude_rad: f64,
    /// Distance between the position's change and the integrated velocity, m.
    pub position_m: f64,
    /// Difference between the velocity's change and gravity plus the commanded thrust, m/s2.
    pub acceleration_mps2: f64,
    /// The rates' change over what the commanded torque predicts (1 = as predicted; 1 when
    /// not judged).
    pub angular_response: f64,
}

impl Default for Residuals {
    fn default() -> Self {
        Residuals {
            attitude_rad: 0.0,
            position_m: 0.0,
            acceleration_mps2: 0.0,
            angular_response: 1.0,
        }
    }
}

/// The interpretations of the inputs the monitor tries when a check fails.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Reading {
    AsGiven,
    ScalarLast,
    Conjugate,
}

const READINGS: [Reading; 3] = [Reading::AsGiven, Reading::ScalarLast, Reading::Conjugate];

impl Reading {
    /// The body-to-NUE attitude `q` stands for under this reading (normalised).
    fn attitude(self, q: [f64; 4]) -> Option<Quaternion<f64>> {
        let raw = match self {
            Reading::AsGiven => lander_math::quaternion::to_nalgebra(&q),
            Reading::ScalarLast => Quaternion::new(q[3], q[0], q[1], q[2]),
            Reading::Conjugate => Quaternion::new(q[0], -q[1], -q[2], -q[3]),
        };
        let norm = raw.norm();
        (norm.is_finite() && norm > 1e-6).then(|| raw / norm)
    }

    /// [`Reading::attitude`] from the attitude `unit` the inputs as given stand for: every
    /// reading has the same norm (the same squares, summed in an order that gives the same
    /// bits), so its attitude is `unit`'s components permuted or negated, bit for bit.
    fn of_unit(self, unit: &Quaternion<f64>) -> Quaternion<f64> {
        match self {
            Reading::AsGiven => *unit,
            Reading::ScalarLast => Quaternion::new(unit.k, unit.w, unit.i, unit.j),
            Reading::Conjugate => unit.conjugate(),
        }
    }

    fn cause(self) -> &'static str {
        match self {
            Reading::AsGiven => "",
            Reading::ScalarLast => {
                "the quaternion looks scalar-last: q_body_to_nue[1] must be the scalar part"
            }
            Reading::Conjugate => {
                "the quaternion looks like its conjugate (NUE to body): q_body_to_nue must \
                 rotate body vectors into NUE"
            }
        }
    }
}

/// `q` rotating body `v` into NUE.
fn rotate(q: &Quaternion<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    let p = q * Quaternion::from_imag(*v) * q.conjugate();
    p.imag()
}

/// Body +y rotated into NUE by `q`: [`rotate`]`(q, y)` without the products by the zero and
/// unit components of `y`. `q ⊗ (0, y)` is `(-q_j, -q_k, q_w, q_i)` exactly; the product
/// with `q*` is nalgebra's, term by term. Only the sign of a zero component can differ from
/// [`rotate`]'s, which no integral sees: each starts at +0, and adding a zero of either sign
/// to +0 gives +0.
fn thrust_axis_nue(q: &Quaternion<f64>) -> [f64; 3] {
    let (pw, pi, pj, pk) = (-q.j, -q.k, q.w, q.i);
    let (cw, ci, cj, ck) = (q.w, -q.i, -q.j, -q.k);
    [
        pw * ci + pi * cw + pj * ck - pk * cj,
        pw * cj - pi * ck + pj * cw + pk * ci,
        pw * ck + pi * cj - pj * ci + pk * cw,
    ]
}

/// The rotation angle of a unit quaternion, in [0, pi].
fn angle(q: &Quaternion<f64>) -> f64 {
    2.0 * libm::atan2(q.imag().norm(), q.w.abs())
}

/// `q` advanced by body rate `omega` over `dt` (first order, renormalised).
fn advance(q: &Quaternion<f64>, omega: &Vector3<f64>, dt: f64) -> Quaternion<f64> {
    let half = omega * (0.5 * dt);
    let dq = Quaternion::new(1.0, half.x, half.y, half.z);
    let p = q * dq;
    p / p.norm()
}

/// NUE components of a vector a plant wrote in ENU order into NUE slots.
fn enu_read_as_nue(v: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(v[1], v[2], v[0])
}

/// The mistakes a window integrates besides the inputs as given (see the module's text).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
struct Diagnoses {
    /// The rates read as deg/s: the attitude check's.
    rates_in_deg: bool,
    /// The quaternion read scalar-last and conjugated: the acceleration check's.
    other_readings: bool,
}

/// What a window accumulates from its first observation on.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
struct Window {
    /// A window is open: the rest holds it (otherwise only `samples` is used).
    open: bool,
    start: Observation,
    /// The newest observation, `samples[latest]`, and the one written for the next sample:
    /// an observation is written once, where the window reads it, the two taking turns.
    samples: [Observation; 2],
    latest: bool,
    /// Body +y in NUE at `last` under each [`Reading`] integrated (the thrust axis the next
    /// sample's interval starts from).
    last_thrust_axis_nue: [[f64; 3]; 3],
    /// The body rotation the rates integrate to, as given and read as deg/s.
    rotation_from_rates: [f64; 4],
    rotation_from_rates_deg: [f64; 4],
    /// Integral of the velocity, m.
    distance_nue_m: [f64; 3],
    /// Integral of the commanded specific force along body +y under each [`Reading`], m/s.
    thrust_impulse_nue_mps: [[f64; 3]; 3],
    /// Integral of what the commanded torque gives the declared inertia, rad/s.
    rate_change_predicted_radps: [f64; 3],
    /// Once set, the thrust and torque checks rest for the window, and their integrals with
    /// them.
    contact: bool,
    diagnoses: Diagnoses,
}

/// The monitor's memory: the open window, the checks failing in a row, what it raised.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ConsistencyMonitor {
    window: Window,
    failing_in_a_row: [u8; 4],
    /// Bits of the checks raised in this run.
    pub raised: i32,
    pub residuals: Residuals,
}

fn q_of(a: [f64; 4]) -> Quaternion<f64> {
    lander_math::quaternion::to_nalgebra(&a)
}

fn a_of(q: &Quaternion<f64>) -> [f64; 4] {
    lander_math::quaternion::from_nalgebra(q)
}

/// The attitude the inputs as given stand for, when the observation can be used: every
/// value finite, a positive mass, a quaternion with a direction. `as_given` is `o`'s quaternion normalised as
/// [`Reading::attitude`] normalises it, if the caller has it.
#[inline(always)]
fn usable(o: &Observation, as_given: Option<Quaternion<f64>>) -> Option<Quaternion<f64>> {
    if all_finite(o) && o.mass_kg > 0.0 {
        as_given.or_else(|| Reading::AsGiven.attitude(o.q_body_to_nue))
    } else {
        None
    }
}

/// Whether every number of `o` is finite: `x * 0` is 0 for finite `x` and NaN otherwise, so
/// a sum of them is 0 exactly when all are, in whatever order it is added; in two running
/// sums of neighbours, a vector unit adds two at once.
#[inline(always)]
fn all_finite(o: &Observation) -> bool {
    let [r0, r1, r2] = o.r_nue_m;
    let [v0, v1, v2] = o.v_nue_mps;
    let [q0, q1, q2, q3] = o.q_body_to_nue;
    let [w0, w1, w2] = o.omega_body_radps;
    let [m0, m1, m2] = o.torque_cmd_body_nm;
    let pairs = [
        [o.t_s, r0],
        [r1, r2],
        [v0, v1],
        [v2, q0],
        [q1, q2],
        [q3, w0],
        [w1, w2],
        [o.mass_kg, o.thrust_cmd_n],
        [m0, m1],
        [m2, 0.0],
    ];
    let mut sums = [0.0f64; 2];
    for [a, b] in pairs {
        sums[0] += a * 0.0;
        sums[1] += b * 0.0;
    }
    sums[0] + sums[1] == 0.0
}

/// What a check found in a window: its residual and whether it failed.
struct Verdict {
    residual: f64,
    failed: bool,
}

impl ConsistencyMonitor {
    /// Takes the next observation (`as_given` its quaternion normalised, if the caller has
    /// it, see [`usable`]); `raise` is given the message of each check raised by it
    /// (each check raises once a run).
    pub fn observe(
        &mut self,
        settings: &MonitorSettings,
        as_given: Option<Quaternion<f64>>,
        raise: &mut impl FnMut(String),
    ) {
        let o = self.window.incoming();
        let Some(attitude) = usable(o, as_given) else {
            self.window.open = false;
            return;
        };
        if !(self.window.open && o.t_s > self.window.last().t_s) {
            self.window.latest = !self.window.latest;
            self.window.open(&attitude, self.diagnoses());
            return;
        }
        let w = &mut self.window;
        w.accumulate(settings, &attitude);
        // Times are finite here.
        if w.last().t_s - w.start.t_s >= WINDOW_S * (1.0 - 1e-9) {
            let ended = *w;
            self.judge(settings, &ended, raise);
            self.window.open(&attitude, self.diagnoses());
        }
    }

    /// Where the next observation is written before [`Self::observe`] takes it.
    pub fn incoming(&mut self) -> &mut Observation {
        &mut self.window.samples[usize::from(!self.window.latest)]
    }

    /// The observation written to [`Self::incoming`].
    pub fn next_observation(&self) -> &Observation {
        self.window.incoming()
    }

    /// What the next window integrates: the mistakes of a check whose failure in it would be
    /// raised (it failed in the window before, and has not been raised).
    fn diagnoses(&self) -> Diagnoses {
        let raises =
            |k: usize| self.failing_in_a_row[k] >= PERSISTENCE - 1 && self.raised & (1 << k) == 0;
        Diagnoses {
            rates_in_deg: raises(0),
            other_readings: raises(2),
        }
    }

    /// Out of line: once a window, and the words of a finding with it; the per-sample path
    /// stays small.
    #[inline(never)]
    fn judge(&mut self, settings: &MonitorSettings, w: &Window, raise: &mut impl FnMut(String)) {
        let mut failed = [false; 4];
        let attitude = w.attitude_check();
        self.residuals.attitude_rad = attitude.residual;
        failed[0] = attitude.failed;
        let position = w.position_check();
        self.residuals.position_m = position.residual;
        failed[1] = position.failed;
        // Thrust direction and torque response rest on the attitude and rates: judged only
        // while those agree, so one mistake is named once, by its first symptom.
        if !failed[0] && !w.contact {
            let acceleration = w.acceleration_check(settings);
            self.residuals.acceleration_mps2 = acceleration.residual;
            failed[2] = acceleration.failed;
            if settings.torque_is_applied {
                let angular = w.angular_check();
                self.residuals.angular_response = angular.residual;
                failed[3] = angular.failed;
            }
        } else {
            self.residuals.angular_response = 1.0;
        }
        for (k, failed) in failed.into_iter().enumerate() {
            let bit = 1 << k;
            if failed {
                self.failing_in_a_row[k] = self.failing_in_a_row[k].saturating_add(1);
                if self.failing_in_a_row[k] >= PERSISTENCE && self.raised & bit == 0 {
                    self.raised |= bit;
                    let message = match k {
                        0 => w.attitude_finding(),
                        1 => w.position_finding(),
                        2 => w.acceleration_finding(settings),
                        _ => w.angular_finding(settings),
                    };
                    raise(format!(
                        "input monitor, window from t = {} s to {} s: {message}",
                        w.start.t_s,
                        w.last().t_s
                    ));
                }
            } else {
                self.failing_in_a_row[k] = 0;
            }
        }
    }
}

impl Window {
    fn incoming(&self) -> &Observation {
        &self.samples[usize::from(!self.latest)]
    }

    fn last(&self) -> &Observation {
        &self.samples[usize::from(self.latest)]
    }

    /// Opens a window at the newest observation, whose attitude as given is `attitude`.
    /// Out of line: once a window.
    #[inline(never)]
    fn open(&mut self, attitude: &Quaternion<f64>, diagnoses: Diagnoses) {
        let identity = [1.0, 0.0, 0.0, 0.0];
        let mut last_thrust_axis_nue = [[0.0; 3]; 3];
        last_thrust_axis_nue[0] = thrust_axis_nue(attitude);
        if diagnoses.other_readings {
            for k in 1..3 {
                last_thrust_axis_nue[k] = thrust_axis_nue(&READINGS[k].of_unit(attitude));
            }
        }
        let o = *self.last();
        *self = Window {
            open: true,
            start: o,
            samples: self.samples,
            latest: self.latest,
            last_thrust_axis_nue,
            rotation_from_rates: identity,
            rotation_from_rates_deg: identity,
            distance_nue_m: [0.0; 3],
            thrust_impulse_nue_mps: [[0.0; 3]; 3],
            rate_change_predicted_radps: [0.0; 3],
            contact: o.ground_contact_possible,
            diagnoses,
        };
    }

    /// Integrates over `[last, o]` for the incoming observation `o`, which becomes the
    /// newest; `attitude` is `o`'s as given.
    fn accumulate(&mut self, settings: &MonitorSettings, attitude: &Quaternion<f64>) {
        let (p, o) = (
            &self.samples[usize::from(self.latest)],
            &self.samples[usize::from(!self.latest)],
        );
        let dt = o.t_s - p.t_s;
        let omega_mid =
            (Vector3::from(p.omega_body_radps) + Vector3::from(o.omega_body_radps)) * 0.5;
        self.rotation_from_rates = a_of(&advance(&q_of(self.rotation_from_rates), &omega_mid, dt));
        if self.diagnoses.rates_in_deg {
            self.rotation_from_rates_deg = a_of(&advance(
                &q_of(self.rotation_from_rates_deg),
                &(omega_mid * std::f64::consts::PI / 180.0),
                dt,
            ));
        }
        let v_mid = (Vector3::from(p.v_nue_mps) + Vector3::from(o.v_nue_mps)) * 0.5;
        self.distance_nue_m = (Vector3::from(self.distance_nue_m) + v_mid * dt).into();
        self.contact |= o.ground_contact_possible;
        if !self.contact {
            // The command read at p acts over [p, o]; the thrust axis moves with the attitude.
            let impulse = p.thrust_cmd_n / p.mass_kg * dt;
            let readings = if self.diagnoses.other_readings { 3 } else { 1 };
            for (k, reading) in READINGS.iter().enumerate().take(readings) {
                let now = thrust_axis_nue(&reading.of_unit(attitude));
                let before = std::mem::replace(&mut self.last_thrust_axis_nue[k], now);
                let sums = self.thrust_impulse_nue_mps[k].iter_mut();
                for ((sum, before), now) in sums.zip(before).zip(now) {
                    *sum += (before + now) * 0.5 * impulse;
                }
            }
            let inertia = Vector3::from(settings.inertia_body_kgm2);
            let omega = Vector3::from(p.omega_body_radps);
            let gyroscopic = omega.cross(&inertia.component_mul(&omega));
            let accel = (Vector3::from(p.torque_cmd_body_nm) - gyroscopic).component_div(&inertia);
            self.rate_change_predicted_radps =
                (Vector3::from(self.rate_change_predicted_radps) + accel * dt).into();
        }
        self.latest = !self.latest;
    }

    fn duration_s(&self) -> f64 {
        self.last().t_s - self.start.t_s
    }

    /// The attitude's change (body frame, from the window's start) under `reading`.
    fn relative_rotation(&self, reading: Reading) -> Option<Quaternion<f64>> {
        let q0 = reading.attitude(self.start.q_body_to_nue)?;
        let q1 = reading.attitude(self.last().q_body_to_nue)?;
        Some(q0.conjugate() * q1)
    }

    /// The attitude check under `reading` against `from_rates`: residual, failed, and the
    /// rotations measured and integrated (rad).
    fn attitude_mismatch(
        &self,
        reading: Reading,
        from_rates: [f64; 4],
    ) -> Option<(f64, bool, f64, f64)> {
        let measured = self.relative_rotation(reading)?;
        let predicted = q_of(from_rates);
        let residual = angle(&(predicted.conjugate() * measured));
        let tolerance =
            ATTITUDE_ABSOLUTE_RAD + ATTITUDE_RELATIVE * angle(&measured).max(angle(&predicted));
        Some((
            residual,
            residual > tolerance,
            angle(&measured),
            angle(&predicted),
        ))
    }

    fn attitude_check(&self) -> Verdict {
        match self.attitude_mismatch(Reading::AsGiven, self.rotation_from_rates) {
            Some((residual, failed, ..)) => Verdict { residual, failed },
            None => Verdict {
                residual: 0.0,
                failed: false,
            },
        }
    }

    /// The message of a failed attitude check (the window integrated the rates as deg/s).
    fn attitude_finding(&self) -> String {
        let (measured, predicted) = self
            .attitude_mismatch(Reading::AsGiven, self.rotation_from_rates)
            .map_or((0.0, 0.0), |(_, _, measured, predicted)| {
                (measured, predicted)
            });
        let deg = self.attitude_mismatch(Reading::AsGiven, self.rotation_from_rates_deg);
        let cause = if deg.is_some_and(|(_, failed, ..)| !failed) {
            "body rates look like deg/s: omega_body must be in rad/s"
        } else if let Some(reading) =
            [Reading::ScalarLast, Reading::Conjugate]
                .into_iter()
                .find(|&r| {
                    self.attitude_mismatch(r, self.rotation_from_rates)
                        .is_some_and(|(_, f, ..)| !f)
                })
        {
            reading.cause()
        } else {
            "the attitude does not turn the way omega_body says: check that omega_body is the \
             body rate in body axes (rad/s) and q_body_to_nue the scalar-first body-to-NUE \
             quaternion"
        };
        format!(
            "{cause} (q_body_to_nue turned {:.3} deg, omega_body integrates to {:.3} deg)",
            measured.to_degrees(),
            predicted.to_degrees()
        )
    }

    fn moved_and_integrated(&self) -> (Vector3<f64>, Vector3<f64>) {
        let moved = Vector3::from(self.last().r_nue_m) - Vector3::from(self.start.r_nue_m);
        (moved, Vector3::from(self.distance_nue_m))
    }

    fn position_check(&self) -> Verdict {
        let (moved, integrated) = self.moved_and_integrated();
        let residual = (moved - integrated).norm();
        let tolerance = POSITION_ABSOLUTE_M + POSITION_RELATIVE * integrated.norm();
        Verdict {
            residual,
            failed: residual > tolerance,
        }
    }

    fn position_finding(&self) -> String {
        let (moved, integrated) = self.moved_and_integrated();
        format!(
            "the position's change ({:.3} m) is not what v_nue integrates to ({:.3} m) \
             over {:.2} s: check the units of r_nue (m) and v_nue (m/s), and that both \
             are NUE (North, Up, East)",
            moved.norm(),
            integrated.norm(),
            self.duration_s()
        )
    }

    fn gravity_nue(settings: &MonitorSettings) -> Vector3<f64> {
        Vector3::new(0.0, -settings.gravity_mps2, 0.0)
    }

    /// The mean acceleration over the window, m/s2.
    fn acceleration(&self) -> Vector3<f64> {
        let dv = Vector3::from(self.last().v_nue_mps) - Vector3::from(self.start.v_nue_mps);
        dv / self.duration_s()
    }

    /// The mean specific force the commanded thrust gives under reading `k`, m/s2.
    fn predicted_force(&self, k: usize) -> Vector3<f64> {
        Vector3::from(self.thrust_impulse_nue_mps[k]) / self.duration_s()
    }

    /// The acceleration check of `acceleration` against reading `k`: residual, failed.
    fn acceleration_mismatch(
        &self,
        settings: &MonitorSettings,
        acceleration: Vector3<f64>,
        k: usize,
    ) -> Verdict {
        // Along the thrust the plant's throttle range and lag blur the magnitude; across
        // it only the attitude's error does.
        let force = self.predicted_force(k);
        let residual = acceleration - force - Self::gravity_nue(settings);
        let along = force
            .try_normalize(1e-9)
            .map_or(0.0, |axis| residual.dot(&axis));
        let across = (residual.norm_squared() - along * along).max(0.0).sqrt();
        Verdict {
            residual: residual.norm(),
            failed: along.abs() > ACCELERATION_ABSOLUTE_MPS2 + ACCELERATION_RELATIVE * force.norm()
                || across > ACCELERATION_ABSOLUTE_MPS2 + ACCELERATION_ACROSS * force.norm(),
        }
    }

    fn acceleration_check(&self, settings: &MonitorSettings) -> Verdict {
        self.acceleration_mismatch(settings, self.acceleration(), 0)
    }

    /// The message of a failed acceleration check (the window integrated the other
    /// readings).
    fn acceleration_finding(&self, settings: &MonitorSettings) -> String {
        let gravity_nue = Self::gravity_nue(settings);
        let acceleration = self.acceleration();
        let enu = self.acceleration_mismatch(settings, enu_read_as_nue(&acceleration), 0);
        let reading =
            (1..3).find(|&k| !self.acceleration_mismatch(settings, acceleration, k).failed);
        let force_measured = acceleration - gravity_nue;
        let force_predicted = self.predicted_force(0);
        let numbers = format!(
            "(v_nue changed at [{:.3}, {:.3}, {:.3}] m/s2; gravity and thrust_cmd / mass along \
             body +y predict [{:.3}, {:.3}, {:.3}] m/s2)",
            acceleration.x,
            acceleration.y,
            acceleration.z,
            (force_predicted + gravity_nue).x,
            (force_predicted + gravity_nue).y,
            (force_predicted + gravity_nue).z,
        );
        let cause = if !enu.failed {
            "position and velocity look like ENU (East, North, Up): r_nue and v_nue must be \
             North, Up, East"
                .to_string()
        } else if let Some(k) = reading {
            READINGS[k].cause().to_string()
        } else if force_predicted.norm() > ACCELERATION_ABSOLUTE_MPS2
            && force_measured.normalize().dot(&force_predicted.normalize()) < 0.866
        {
            // Say where the specific force points in body axes: a plant whose thrust is
            // along another body axis, or whose axes are another frame's, shows here.
            let q = Reading::AsGiven
                .attitude(self.last().q_body_to_nue)
                .unwrap_or_else(Quaternion::identity);
            let body = rotate(&q.conjugate(), &force_measured);
            let k = body.iamax();
            let axis = format!(
                "{}{} body",
                if body[k] < 0.0 { "-" } else { "+" },
                ["x", "y", "z"][k]
            );
            format!(
                "the velocity's change points along {axis}, not along the thrust axis \
                 (+y body): check the frame (NUE axes, body +y the thrust axis; a plant with \
                 thrust along another body axis needs the constant rotation at the interface)"
            )
        } else {
            let implied_gravity = force_predicted.y - acceleration.y;
            if (0.1..=30.0).contains(&implied_gravity)
                && (implied_gravity - settings.gravity_mps2).abs() > 0.25 * settings.gravity_mps2
            {
                format!(
                    "the vertical acceleration implies gravity {implied_gravity:.3} m/s2, not \
                     gravity = {} m/s2: set gravity to the plant's (or check mass and thrust)",
                    settings.gravity_mps2
                )
            } else {
                let ratio = force_measured.dot(&force_predicted)
                    / force_predicted.norm_squared().max(f64::MIN_POSITIVE);
                format!(
                    "the specific force is {ratio:.3e} times what thrust_cmd / mass predicts: \
                     check mass (kg), the plant's thrust (N) and its throttle range"
                )
            }
        };
        format!("{cause} {numbers}")
    }

    /// The rates' change measured and predicted over the window, rad/s.
    fn rate_changes(&self) -> (Vector3<f64>, Vector3<f64>) {
        let measured = Vector3::from(self.last().omega_body_radps)
            - Vector3::from(self.start.omega_body_radps);
        (measured, Vector3::from(self.rate_change_predicted_radps))
    }

    fn angular_check(&self) -> Verdict {
        let (measured, predicted) = self.rate_changes();
        if predicted.norm() < ANGULAR_MIN_PREDICTED_RADPS {
            return Verdict {
                residual: 1.0,
                failed: false,
            };
        }
        let ratio = measured.dot(&predicted) / predicted.norm_squared();
        Verdict {
            residual: ratio,
            failed: !(1.0 / ANGULAR_RATIO_LIMIT..=ANGULAR_RATIO_LIMIT).contains(&ratio),
        }
    }

    /// The message of a failed angular check.
    fn angular_finding(&self, settings: &MonitorSettings) -> String {
        let (measured, predicted) = self.rate_changes();
        let ratio = self.angular_check().residual;
        let inertia = Matrix3::from_diagonal(&Vector3::from(settings.inertia_body_kgm2));
        let cause = if ratio > 1e-6 {
            format!(
                "the plant's inertia looks {:.3e} times the declared one; check inertia_body \
                 (kg m2) and the torque's units (N m)",
                1.0 / ratio
            )
        } else {
            "the rates do not follow the commanded torque: check that torque_cmd_body reaches \
             the plant, in body axes and N m, and omega_body comes back from it"
                .to_string()
        };
        format!(
            "the body rates changed by {:.3e} rad/s, {ratio:.3e} times what \
             torque_cmd_body predicts for inertia_body = [{}, {}, {}] kg m2 \
             ({:.3e} rad/s): {cause}",
            measured.norm(),
            inertia[(0, 0)],
            inertia[(1, 1)],
            inertia[(2, 2)],
            predicted.norm(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Quaternions of every sign pattern and size, zeros among them.
    fn quaternions() -> Vec<[f64; 4]> {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut qs = vec![
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [-0.0, 0.0, -0.0, 1.0],
            [0.5, -0.5, 0.5, -0.5],
        ];
        for k in 0..20_000 {
            let mut q = [next(), next(), next(), next()];
            // a component exactly zero in a share of them, and some far from unit norm
            if k % 7 == 0 {
                q[k % 4] = 0.0;
            }
            if k % 11 == 0 {
                q = q.map(|c| c * 1e3);
            }
            qs.push(q);
        }
        qs
    }

    #[test]
    fn every_reading_of_the_unit_attitude_is_its_own_normalisation_bit_for_bit() {
        for q in quaternions() {
            let Some(unit) = Reading::AsGiven.attitude(q) else {
                continue;
            };
            for reading in READINGS {
                let own = reading.attitude(q).expect("the same norm");
                assert_eq!(
                    a_of(&own).map(f64::to_bits),
                    a_of(&reading.of_unit(&unit)).map(f64::to_bits),
                    "{reading:?} of {q:?}"
                );
            }
        }
    }

    #[test]
    fn the_thrust_axis_is_the_rotated_body_y_to_the_sign_of_a_zero() {
        for q in quaternions() {
            let Some(unit) = Reading::AsGiven.attitude(q) else {
                continue;
            };
            for reading in READINGS {
                let q = reading.of_unit(&unit);
                let full: [f64; 3] = rotate(&q, &Vector3::y()).into();
                // == equates the zeros of either sign, and nothing else
                assert_eq!(thrust_axis_nue(&q), full, "{q:?}");
            }
        }
    }
}
