//! The error-state Kalman filter. The nominal state (position, velocity, attitude, IMU
//! biases) is propagated with the IMU; the 15-element error state `(dr, dv, dtheta, db_a,
//! db_g)` carries the covariance. The scalar measurements of a communication point accumulate
//! the error estimate, which is then injected into the nominal state once and reset to zero
//! (docs/filter.md gives the equations).
// Matrix formulas read best with their indices.
#![allow(clippy::needless_range_loop)]
use super::covariance::{self, Matrix, Sparse, BA, BG, MA, MG, N, R as IR, SA, SG, THETA, V as IV};
use super::measurement::{self, Plane, Prediction};
use super::parameters::FilterParameters;
use super::rotation::{self, skew, Quaternion};
use lander_math::frames::{Body, BodyToNue, Nue};
use nalgebra::{Matrix3, Matrix6, Vector3};
use serde::{Deserialize, Serialize};

/// One IMU sample: specific force and body rate as measured, in body axes.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Imu {
    pub accel_body_mps2: [f64; 3],
    pub gyro_body_radps: [f64; 3],
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Eskf {
    pub r_nue_m: [f64; 3],
    pub v_nue_mps: [f64; 3],
    pub q_body_to_nue: Quaternion,
    pub accel_bias_mps2: [f64; 3],
    pub gyro_bias_radps: [f64; 3],
    pub accel_calibration: Calibration,
    pub gyro_calibration: Calibration,
    /// The error state's covariance, in the order of [`covariance`].
    pub p: Matrix,
}

/// The estimated calibration errors of one IMU triad, in LanderSensors' model
/// `m = (I + diag(s)) (x - mu x x) + b + n`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Calibration {
    pub scale_factor: [f64; 3],
    pub misalignment_rad: [f64; 3],
}

impl Calibration {
    /// The body-axis value of a measurement less its bias `u`, to first order in the
    /// calibration errors: `x = u - diag(s) u + mu x u`.
    pub fn compensate(&self, u: &Vector3<f64>) -> Vector3<f64> {
        let s = v3(&self.scale_factor);
        u - s.component_mul(u) + v3(&self.misalignment_rad).cross(u)
    }

    fn add(&mut self, dx: &[f64; N], scale_at: usize, misalignment_at: usize) {
        for i in 0..3 {
            self.scale_factor[i] += dx[scale_at + i];
            self.misalignment_rad[i] += dx[misalignment_at + i];
        }
    }

    fn is_finite(&self) -> bool {
        self.scale_factor
            .iter()
            .chain(&self.misalignment_rad)
            .all(|x| x.is_finite())
    }
}

/// What one scalar measurement did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Update {
    /// Normalised innovation squared `nu^2 / s` (1 degree of freedom).
    pub nis: f64,
    /// False when the chi-square gate rejected it.
    pub applied: bool,
}

fn v3(a: &[f64; 3]) -> Vector3<f64> {
    Vector3::from(*a)
}

impl Eskf {
    /// The initial estimate and its diagonal covariance from the parameters (biases zero, with
    /// the sensors' bias 1-sigmas).
    pub fn start(params: &FilterParameters) -> Eskf {
        let mut p = [[0.0; N]; N];
        let sigmas = [
            (IR, params.r0_sigma_m),
            (IV, params.v0_sigma_mps),
            (THETA, params.attitude0_sigma_rad),
            (BA, params.accel.bias_sigma),
            (BG, params.gyro.bias_sigma),
            (SA, params.accel.scale_factor_sigma),
            (SG, params.gyro.scale_factor_sigma),
            (MA, params.accel.misalignment_sigma),
            (MG, params.gyro.misalignment_sigma),
        ];
        for (at, sigma) in sigmas {
            for i in at..at + 3 {
                p[i][i] = sigma * sigma;
            }
        }
        Eskf {
            r_nue_m: params.r0_nue_m,
            v_nue_mps: params.v0_nue_mps,
            q_body_to_nue: rotation::normalized(&params.q0_body_to_nue),
            accel_bias_mps2: [0.0; 3],
            gyro_bias_radps: [0.0; 3],
            accel_calibration: Calibration::default(),
            gyro_calibration: Calibration::default(),
            p,
        }
    }

    pub fn rotation(&self) -> Matrix3<f64> {
        rotation::matrix(&self.q_body_to_nue)
    }

    /// The body rate: the gyro's less the estimated bias, calibrated.
    pub fn omega_body(&self, imu: &Imu) -> [f64; 3] {
        let u = v3(&imu.gyro_body_radps) - v3(&self.gyro_bias_radps);
        self.gyro_calibration.compensate(&u).into()
    }

    /// From the sample's time over `h` seconds, the IMU sample held over the step.
    ///
    /// Nominal: `a = R (f_m - b_a) + g`, `r += v h + a h^2 / 2`, `v += a h`,
    /// `q = q exp((w_m - b_g) h)`. Error: `P = F P F^T + Q` with `F` the exact transition
    /// of the linearised error dynamics over the step for a held sample.
    ///
    /// `linearised_at`: the state this point's measurements were linearised about, before
    /// their correction (`None` when there were none). Then the attitude columns of `F` are
    /// the smallest change that maps the unobservable heading direction of that state to the
    /// propagated state's (an observability-constrained EKF, see [`Heading`]); without it,
    /// each correction moves the estimate and that direction with it, and the filter gains
    /// heading information that no measurement holds.
    pub fn propagate(
        &mut self,
        params: &FilterParameters,
        imu: &Imu,
        h: f64,
        linearised_at: Option<&Heading>,
    ) {
        let r = self.rotation();
        let f = self
            .accel_calibration
            .compensate(&(v3(&imu.accel_body_mps2) - v3(&self.accel_bias_mps2)));
        let w = v3(&self.omega_body(imu));
        let g = Vector3::new(0.0, -params.gravity_mps2, 0.0);
        // The body turns by w h over the step while the specific force acts: the velocity
        // takes its integral, R (f + (h / 2) w x f) h, and the position its double integral,
        // R (f + (h / 3) w x f) h^2 / 2. Taken at the step's start attitude instead, the
        // estimate gains h f (1 - cos tilt) / 2 of Up velocity on every tilt the guidance
        // commands, whichever way it leans.
        let turning = w.cross(&f);
        let a = r * (f + turning * (0.5 * h)) + g;
        let a_r = r * (f + turning * (h / 3.0)) + g;
        let (pos, vel) = (v3(&self.r_nue_m), v3(&self.v_nue_mps));
        self.r_nue_m = (pos + vel * h + a_r * (0.5 * h * h)).into();
        self.v_nue_mps = (vel + a * h).into();
        let turn = rotation::exp(&(w * h));
        self.q_body_to_nue = rotation::normalized(&rotation::mul(&self.q_body_to_nue, &turn));

        let mut rf = r * skew(&f);
        // The accelerometer's misalignment turns the specific force as an attitude error
        // does; the heading constraint below concerns the attitude alone.
        let rf_misaligned = rf;
        let skew_w = skew(&w);
        let rf_w = rf * skew_w;
        let mut tr: Sparse = Vec::with_capacity(192);
        for i in 0..N {
            if !(THETA..THETA + 3).contains(&i) {
                tr.push((i, i, 1.0));
            }
        }
        let mut back = rotation::matrix(&turn).transpose();
        // Blocks -(h^2/2) R [f]x and -h R [f]x are -(h^2/2) rf and -h rf.
        let mut rf_r = rf;
        if let Some(before) = linearised_at {
            let up = Vector3::new(0.0, 1.0, 0.0);
            let u = before.rotation.transpose() * up;
            let after = self.rotation();
            // dtheta row: R_after^T R_before maps R_before^T e to R_after^T e exactly.
            back = after.transpose() * before.rotation;
            // Rows dv and dr: A* = A - (A u - w) u^T (u is a unit vector), with w what the
            // attitude column must give for the rows to map the heading direction.
            let w_v = up.cross(&(v3(&self.v_nue_mps) - before.v_nue));
            let w_r = up.cross(&(v3(&self.r_nue_m) - before.r_nue - before.v_nue * h));
            let a_v = -h * rf;
            let a_r = -0.5 * h * h * rf;
            let a_v = a_v - (a_v * u - w_v) * u.transpose();
            let a_r = a_r - (a_r * u - w_r) * u.transpose();
            rf = a_v / -h;
            rf_r = a_r / (-0.5 * h * h);
        }
        for a in 0..3 {
            tr.push((IR + a, IV + a, h));
            tr.push((THETA + a, BG + a, -h));
            // The calibration errors: df = -diag(f) ds_a - [f]x dmu_a, and the same of w.
            // The rate error also turns the specific force within the step (the w x f term):
            // dv = -(h^2 / 2) R [f]x dw, dr = -(h^3 / 6) R [f]x dw, with
            // dw = -db_g - diag(w) ds_g - [w]x dmu_g.
            tr.push((THETA + a, SG + a, -h * w[a]));
            for b in 0..3 {
                let (v_of_w, r_of_w) = (0.5 * h * h, h * h * h / 6.0);
                tr.push((IV + a, BG + b, v_of_w * rf_misaligned[(a, b)]));
                tr.push((IR + a, BG + b, r_of_w * rf_misaligned[(a, b)]));
                tr.push((IV + a, SG + b, v_of_w * rf_misaligned[(a, b)] * w[b]));
                tr.push((IR + a, SG + b, r_of_w * rf_misaligned[(a, b)] * w[b]));
                tr.push((IV + a, MG + b, v_of_w * rf_w[(a, b)]));
                tr.push((IR + a, MG + b, r_of_w * rf_w[(a, b)]));
            }
            for b in 0..3 {
                tr.push((IR + a, SA + b, -0.5 * h * h * r[(a, b)] * f[b]));
                tr.push((IV + a, SA + b, -h * r[(a, b)] * f[b]));
                tr.push((IR + a, MA + b, -0.5 * h * h * rf_misaligned[(a, b)]));
                tr.push((IV + a, MA + b, -h * rf_misaligned[(a, b)]));
                tr.push((THETA + a, MG + b, -h * skew_w[(a, b)]));
            }
            for b in 0..3 {
                tr.push((IR + a, THETA + b, -0.5 * h * h * rf_r[(a, b)]));
                tr.push((IR + a, BA + b, -0.5 * h * h * r[(a, b)]));
                tr.push((IV + a, THETA + b, -h * rf[(a, b)]));
                tr.push((IV + a, BA + b, -h * r[(a, b)]));
                tr.push((THETA + a, THETA + b, back[(a, b)]));
            }
        }
        self.p = covariance::propagate(&self.p, &tr, &process_noise(params, h));
    }

    /// One scalar measurement `y` of noise variance `variance` with the model `pred`, into
    /// the error estimate `dx` of this communication point. The nominal state is corrected
    /// once, by [`Eskf::inject`], after all of them, so that every measurement of a point is
    /// linearised about the same state (the one [`Eskf::propagate`]'s constraint names). Not
    /// applied when `gate` is set and the NIS exceeds it, or when the innovation variance is
    /// not positive and finite (then the NIS reads infinity).
    pub fn update(
        &mut self,
        dx: &mut [f64; N],
        pred: &Prediction,
        y: f64,
        variance: f64,
        gate: Option<f64>,
    ) -> Update {
        let (s, k) = covariance::gain(&self.p, &pred.jacobian, variance);
        if !(s > 0.0 && s.is_finite()) {
            return Update {
                nis: f64::INFINITY,
                applied: false,
            };
        }
        let h_dx: f64 = (0..N).map(|i| pred.jacobian[i] * dx[i]).sum();
        let nu = y - pred.value - h_dx;
        let nis = nu * nu / s;
        if gate.is_some_and(|g| nis > g) {
            return Update {
                nis,
                applied: false,
            };
        }
        self.p = covariance::joseph(&self.p, &pred.jacobian, &k, variance);
        for i in 0..N {
            dx[i] += k[i] * nu;
        }
        Update { nis, applied: true }
    }

    /// Adds the error estimate `dx` to the nominal state and resets it: `q = q exp(dtheta)`,
    /// and the covariance of the reset error `G P G^T` with `G = I - [dtheta / 2]x` on the
    /// attitude block.
    pub fn inject(&mut self, dx: &[f64; N]) {
        let add = |x: &mut [f64; 3], at: usize| {
            for i in 0..3 {
                x[i] += dx[at + i];
            }
        };
        add(&mut self.r_nue_m, IR);
        add(&mut self.v_nue_mps, IV);
        add(&mut self.accel_bias_mps2, BA);
        add(&mut self.gyro_bias_radps, BG);
        self.accel_calibration.add(dx, SA, MA);
        self.gyro_calibration.add(dx, SG, MG);
        let dtheta = Vector3::new(dx[THETA], dx[THETA + 1], dx[THETA + 2]);
        self.q_body_to_nue =
            rotation::normalized(&rotation::mul(&self.q_body_to_nue, &rotation::exp(&dtheta)));
        if dtheta != Vector3::zeros() {
            let g = Matrix3::identity() - skew(&(dtheta * 0.5));
            self.p = covariance::transform_block(&self.p, THETA, &g);
        }
    }

    /// The altimeter's slant range `y`; `None` when the estimate's beam misses the terrain.
    pub fn update_altimeter(
        &mut self,
        dx: &mut [f64; N],
        params: &FilterParameters,
        y: f64,
        interval_s: f64,
    ) -> Option<Update> {
        let plane = Plane::new(params.terrain_height_m, &params.terrain_slope_normal_nue);
        let beam = Body(rotation::unit(&v3(&params.altimeter_beam_body)));
        let r = Nue::from(self.r_nue_m);
        let attitude = BodyToNue::of(&self.q_body_to_nue);
        let mut pred = measurement::altimeter(&plane, &r, &attitude, &beam)?;
        let sigma0 = params.altimeter_noise_sigma_m;
        let prop = params.altimeter_noise_proportional * pred.value;
        // The range's second-order part under the covariance of (dr, dtheta).
        let at = |i: usize| if i < 3 { IR + i } else { THETA + i - 3 };
        let p_z = Matrix6::from_fn(|i, j| self.p[at(i)][at(j)]);
        let (mean, variance) =
            measurement::altimeter_second_order(&plane, &r, &attitude, &beam, &p_z);
        pred.value += mean;
        let noise = sigma0 * sigma0 + prop * prop + variance.max(0.0) * repeats(interval_s);
        Some(self.update(dx, &pred, y, noise, gate(params)))
    }

    /// Velocimeter beam `i`'s line-of-sight velocity `y`. The model `y = v . R b` is bilinear
    /// in the velocity and attitude errors: `y = y_hat + H dx + dv^T C dtheta` with
    /// `C = -R [b]x`. The bilinear term's mean and variance under the current covariance
    /// (second-order filter) are added to the prediction and the noise: early in a run, with
    /// metres per second of velocity error and centiradians of attitude error, it is of the
    /// order of the noise itself, and left out it makes the filter overconfident.
    pub fn update_velocimeter(
        &mut self,
        dx: &mut [f64; N],
        params: &FilterParameters,
        i: usize,
        y: f64,
        interval_s: f64,
    ) -> Update {
        let beam = Body(rotation::unit(&v3(&params.velocimeter_beams_body()[i])));
        let attitude = BodyToNue::of(&self.q_body_to_nue);
        let mut pred = measurement::velocimeter(&Nue::from(self.v_nue_mps), &attitude, &beam);
        let c = -attitude.matrix() * skew(&beam.0);
        let block = |at: usize, bt: usize| Matrix3::from_fn(|a, b| self.p[at + a][bt + b]);
        let (pvv, ptt, ptv) = (block(IV, IV), block(THETA, THETA), block(THETA, IV));
        // Isserlis: E[dv^T C dt] = tr(C P_tv), Var = tr(C P_tt C^T P_vv) + tr(C P_tv C P_tv).
        let mean = (c * ptv).trace();
        let variance = (c * ptt * c.transpose() * pvv).trace() + (c * ptv * c * ptv).trace();
        pred.value += mean;
        let sigma = params.velocimeter_noise_sigma_mps;
        self.update(
            dx,
            &pred,
            y,
            sigma * sigma + variance.max(0.0) * repeats(interval_s),
            gate(params),
        )
    }

    /// The state the next measurements are linearised about, as the heading constraint of
    /// [`Eskf::propagate`] needs it.
    pub fn heading(&self) -> Heading {
        Heading {
            r_nue: v3(&self.r_nue_m),
            v_nue: v3(&self.v_nue_mps),
            rotation: self.rotation(),
        }
    }

    pub fn covariance_diagonal(&self) -> [f64; N] {
        std::array::from_fn(|i| self.p[i][i])
    }

    /// Whether every value is finite and the covariance's diagonal non-negative.
    pub fn is_sound(&self) -> bool {
        let values = self
            .r_nue_m
            .iter()
            .chain(&self.v_nue_mps)
            .chain(&self.q_body_to_nue);
        let biases = self.accel_bias_mps2.iter().chain(&self.gyro_bias_radps);
        values.chain(biases).all(|x| x.is_finite())
            && self.accel_calibration.is_finite()
            && self.gyro_calibration.is_finite()
            && self.p.iter().flatten().all(|x| x.is_finite())
            && (0..N).all(|i| self.p[i][i] >= 0.0)
    }
}

/// Over a flat terrain without a heading reference, a rotation of the whole state about Up
/// changes no measurement: the error-state direction
/// `u = (e_up x r, e_up x v, R^T e_up, 0, 0)` is unobservable. The measurement Jacobians
/// annihilate `u` at their linearisation point; the propagation must map the `u` of that
/// point to the `u` of the propagated state, or the EKF finds heading information in its own
/// relinearisation. This is what `u` is made of, at a linearisation point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Heading {
    pub r_nue: Vector3<f64>,
    pub v_nue: Vector3<f64>,
    pub rotation: Matrix3<f64>,
}

/// How long the linearisation error of a measurement stays the same error, s. It is a
/// function of the estimation errors (the second-order terms of the altimeter and velocimeter
/// models), which change as fast as the estimate converges, not with each update: with the
/// default initial 1-sigmas the velocity and tilt errors the velocimeter couples take about a
/// second to settle (the tilt is seen through the `f x dtheta` acceleration it makes). Over
/// that time every update repeats one error, where white noise would average out.
pub const LINEARISATION_CORRELATION_S: f64 = 1.0;

/// The second-order terms' variance is counted once per [`LINEARISATION_CORRELATION_S`], not
/// once per update: `n` updates of one common error of variance `v` and white noise of
/// variance `r` inform like `n` updates of white noise of variance `r + n v` (to first order
/// in `v / r`). With updates every `interval_s`, `n = LINEARISATION_CORRELATION_S /
/// interval_s`, at least 1. Counted once per update, the error reads as information that grows
/// with the update rate: at 0.01 s the NEES of velocity and attitude was a third above its
/// degrees of freedom over the first seconds, and the accelerometer bias kept the excess.
fn repeats(interval_s: f64) -> f64 {
    (LINEARISATION_CORRELATION_S / interval_s).max(1.0)
}

fn gate(params: &FilterParameters) -> Option<f64> {
    params.chi2_gating.then_some(params.chi2_gate)
}

/// The process noise of one step of `h` seconds. The IMU's white noise is one sample held
/// over the step, of variance `density^2 / sample_period` per axis: it enters the position as
/// `-R n h^2 / 2`, the velocity as `-R n h`, the attitude as `-n h` (isotropic, so `R` drops
/// out). The biases walk by `random_walk^2 h`.
pub fn process_noise(params: &FilterParameters, h: f64) -> Matrix {
    let t = params.sample_period_s;
    let va = params.accel.noise_density * params.accel.noise_density / t;
    let vg = params.gyro.noise_density * params.gyro.noise_density / t;
    let wa = params.accel.bias_random_walk * params.accel.bias_random_walk * h;
    let wg = params.gyro.bias_random_walk * params.gyro.bias_random_walk * h;
    let mut q = [[0.0; N]; N];
    for a in 0..3 {
        q[IR + a][IR + a] = 0.25 * h * h * h * h * va;
        q[IR + a][IV + a] = 0.5 * h * h * h * va;
        q[IV + a][IR + a] = 0.5 * h * h * h * va;
        q[IV + a][IV + a] = h * h * va;
        q[THETA + a][THETA + a] = h * h * vg;
        q[BA + a][BA + a] = wa;
        q[BG + a][BG + a] = wg;
    }
    q
}
