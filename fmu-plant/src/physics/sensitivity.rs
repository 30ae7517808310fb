//! The plant's equations at one state on any [`Scalar`], for their exact derivatives: with
//! [`Dual`](super::dual::Dual) numbers seeded along a direction of the states and commands,
//! one pass gives the state derivative and the outputs with their directional derivatives
//! (Model Exchange's `J · seed`).
//!
//! A second copy of [`Plant::derivative`] (with the norm term of
//! [`Plant::continuous_derivative`]) and of the outputs, term for term, for the
//! configurations Model Exchange admits (no landing gear, slosh, valve delay, or rate limit
//! without a lag: `co_simulation_only`); the `f64` path the trajectories run on is not
//! touched. Kept in step with it by a test that compares the two at random states.
//!
//! Non-smooth points take the derivative of the branch the `f64` path takes there: a
//! saturated command (thrust range, RCS torque limit, the off threshold) has derivative 0
//! with respect to its command, the thrust rate limit's clip 0 with respect to the lag, the
//! mass below the dry mass (clamped) 0, `|torque|` the sign of the branch (+ at 0), and a
//! spent propellant or a touchdown the constants they freeze.
use super::dual::Scalar;
use super::plant::{Plant, Translation};
use super::rigid_body::PrincipalInertia;

/// Length of the Model Exchange state vector (`StateLayout::ALL`).
pub const STATES: usize = 18;

/// Where each state starts in the vector (`physics::continuous` order).
pub const TRANSLATION: usize = 0;
pub const ATTITUDE: usize = 6;
pub const OMEGA: usize = 10;
pub const MASS: usize = 13;
pub const THRUST_LAG: usize = 14;
pub const TORQUE_LAG: usize = 15;

/// What the equations depend on: the state vector and the commands.
#[derive(Debug, Clone, Copy)]
pub struct Knowns<S> {
    pub x: [S; STATES],
    pub thrust_cmd_n: S,
    pub torque_cmd_body_nm: [S; 3],
}

/// The discrete facts the equations branch on.
#[derive(Debug, Clone, Copy, Default)]
pub struct Flags {
    /// The state derivative's engines are off (propellant exhausted).
    pub exhausted: bool,
    /// The outputs' engines are off (exhausted, cut by the gear, or the run stopped).
    pub engines_off_for_outputs: bool,
    /// Touchdown: the state derivative is zero (the lander stands still).
    pub touchdown: bool,
}

/// What the equations give: the state derivative and the outputs that depend on states or
/// commands.
#[derive(Debug, Clone, Copy)]
pub struct Unknowns<S> {
    pub derivative: [S; STATES],
    pub r_nue: [S; 3],
    pub v_nue: [S; 3],
    /// `q / |q|`, the published attitude (scalar first).
    pub q_unit: [S; 4],
    pub altitude: S,
    pub thrust_n: S,
    pub rcs_torque_body_nm: [S; 3],
    pub engine_torque_body_nm: [S; 3],
    pub specific_force_body_mps2: [S; 3],
}

fn zero<S: Scalar>() -> S {
    S::from(0.0)
}

fn cross<S: Scalar>(a: &[S; 3], b: &[S; 3]) -> [S; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn constant<S: Scalar>(v: &nalgebra::Vector3<f64>) -> [S; 3] {
    [S::from(v.x), S::from(v.y), S::from(v.z)]
}

fn scaled<S: Scalar>(v: &[S; 3], k: S) -> [S; 3] {
    [v[0] * k, v[1] * k, v[2] * k]
}

fn plus<S: Scalar>(a: &[S; 3], b: &[S; 3]) -> [S; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `q / |q|`, scalar first.
fn unit<S: Scalar>(q: &[S; 4]) -> [S; 4] {
    let norm = (q[1] * q[1] + q[2] * q[2] + q[3] * q[3] + q[0] * q[0]).sqrt();
    [q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm]
}

/// `v` rotated by the normalised `q` (body to NUE), as nalgebra's unit quaternion does it.
fn rotate<S: Scalar>(q: &[S; 4], v: &[S; 3]) -> [S; 3] {
    let q = unit(q);
    let u = [q[1], q[2], q[3]];
    let t = scaled(&cross(&u, v), S::from(2.0));
    let c = cross(&u, &t);
    std::array::from_fn(|i| t[i] * q[0] + c[i] + v[i])
}

/// Euler's equations, `(tau - w x I w) / I`.
fn omega_dot<S: Scalar>(inertia: &[S; 3], w: &[S; 3], torque: &[S; 3]) -> [S; 3] {
    let momentum = [inertia[0] * w[0], inertia[1] * w[1], inertia[2] * w[2]];
    let gyro = cross(w, &momentum);
    std::array::from_fn(|i| (torque[i] - gyro[i]) / inertia[i])
}

impl Plant {
    /// The engines' steady-state thrust for a command ([`Engines::saturate`](super::actuators::Engines::saturate)).
    fn thrust_target<S: Scalar>(&self, thrust_cmd_n: S, off: bool) -> S {
        let e = &self.engines;
        if off || thrust_cmd_n.value() <= e.off_threshold_n {
            return zero();
        }
        let n = f64::from(e.count);
        thrust_cmd_n
            .max_const(n * e.min_thrust_per_engine_n)
            .min_const(n * e.max_thrust_per_engine_n)
            * e.thrust_scale
            * e.health
    }

    /// The delivered thrust (`delivered_from`).
    fn thrust_delivered<S: Scalar>(&self, target: S, lag: S, off: bool) -> S {
        if off {
            zero()
        } else if self.throttle_rate_limit_nps > 0.0 || self.engines.time_constant_s > 0.0 {
            lag
        } else {
            target
        }
    }

    /// The RCS torque delivered (torque model; none of the thrusters fires in Model Exchange,
    /// and a firing thruster's torque is a constant).
    fn rcs_torque_delivered<S: Scalar>(&self, k: &Knowns<S>) -> ([S; 3], [S; 3]) {
        let limit = self.rcs.torque_limit_nm();
        let target: [S; 3] =
            std::array::from_fn(|i| k.torque_cmd_body_nm[i].max_const(-limit).min_const(limit));
        if self.thrusters.is_some() {
            return (target, [zero(); 3]);
        }
        let delivered = std::array::from_fn(|i| {
            if self.rcs.time_constant_s > 0.0 {
                k.x[TORQUE_LAG + i]
            } else {
                target[i]
            }
        });
        (target, delivered)
    }

    fn inertia_at<S: Scalar>(&self, mass_kg: S) -> [S; 3] {
        match &self.mass_properties {
            None => constant(&self.inertia_body_kgm2),
            Some(mp) => {
                let f = ((mass_kg - mp.dry_mass_kg) / mp.propellant_kg)
                    .max_const(0.0)
                    .min_const(1.0);
                let dry: &PrincipalInertia = &mp.inertia_dry_body_kgm2;
                let wet = &mp.inertia_wet_body_kgm2;
                std::array::from_fn(|i| f * (wet[i] - dry[i]) + dry[i])
            }
        }
    }

    /// The engine torque the moved centre of mass adds (`engine_torque_shift_body_nm`).
    fn torque_shift<S: Scalar>(&self, mass_kg: S, thrust_body_n: &[S; 3]) -> [S; 3] {
        match &self.mass_properties {
            None => [zero(); 3],
            Some(mp) => {
                let f = ((mass_kg - mp.dry_mass_kg) / mp.propellant_kg)
                    .max_const(0.0)
                    .min_const(1.0);
                let offset = scaled(&constant(&mp.com_offset_dry_body_m), -f + 1.0);
                let c = cross(&offset, thrust_body_n);
                [-c[0], -c[1], -c[2]]
            }
        }
    }

    /// The state derivative and outputs at `k`: the `f64` equations on [`Scalar`]s.
    pub fn evaluate<S: Scalar>(&self, k: &Knowns<S>, flags: Flags) -> Unknowns<S> {
        let x = &k.x;
        let direction: [S; 3] = constant(&self.thrust_direction_body());
        let point: [S; 3] = constant(&self.thrust_line.point_body_m);
        let q = [
            x[ATTITUDE],
            x[ATTITUDE + 1],
            x[ATTITUDE + 2],
            x[ATTITUDE + 3],
        ];
        let omega = [x[OMEGA], x[OMEGA + 1], x[OMEGA + 2]];
        let mass = x[MASS];
        let lag = x[THRUST_LAG];
        let translation: [S; 6] = std::array::from_fn(|i| x[TRANSLATION + i]);
        let (rcs_target, rcs_torque) = self.rcs_torque_delivered(k);

        // The outputs, as `delivered_firing` and `refresh_outputs` give them.
        let off = flags.engines_off_for_outputs;
        let thrust_out = self.thrust_delivered(self.thrust_target(k.thrust_cmd_n, off), lag, off);
        let thrust_force_out = scaled(&direction, thrust_out);
        let engine_torque_out = plus(
            &cross(&point, &thrust_force_out),
            &self.torque_shift(mass, &thrust_force_out),
        );
        let specific_force = scaled(
            &thrust_force_out,
            S::from(1.0) / mass.max_const(self.dry_mass_kg),
        );
        let (r_nue, v_nue, altitude) = match &self.translation {
            Translation::Flat { .. } => (
                [translation[0], translation[1], translation[2]],
                [translation[3], translation[4], translation[5]],
                translation[1],
            ),
            Translation::Spherical(moon) => {
                let (r, v) = moon.to_nue_of(&translation);
                (r, v, translation[0] - moon.radius_m)
            }
        };

        // The state derivative, as `derivative_delivered` with the norm term.
        let off = flags.exhausted;
        let target = self.thrust_target(k.thrust_cmd_n, off);
        let thrust = self.thrust_delivered(target, lag, off);
        let mass_clamped = mass.max_const(self.dry_mass_kg);
        let thrust_body = match self.thrusters {
            None => scaled(&direction, thrust / mass_clamped),
            Some(_) => scaled(&scaled(&direction, thrust), S::from(1.0) / mass_clamped),
        };
        let a_thrust_nue = rotate(&q, &thrust_body);
        let engine_torque = cross(&point, &scaled(&direction, thrust));
        let torque = plus(
            &plus(&rcs_torque, &engine_torque),
            &self.torque_shift(mass, &scaled(&direction, thrust)),
        );
        let mut derivative = [zero(); STATES];
        let d_translation = match &self.translation {
            Translation::Flat { gravity_mps2 } => [
                translation[3],
                translation[4],
                translation[5],
                a_thrust_nue[0],
                a_thrust_nue[1] - *gravity_mps2,
                a_thrust_nue[2],
            ],
            Translation::Spherical(moon) => moon.derivative_of(&translation, &a_thrust_nue),
        };
        derivative[TRANSLATION..TRANSLATION + 6].copy_from_slice(&d_translation);
        // q' = q (x) [0, w] / 2 + k (1 - |q|^2) q
        let v = [q[1], q[2], q[3]];
        let vw = cross(&v, &omega);
        let norm_term = (-(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) + 1.0)
            * super::continuous::QUATERNION_NORM_GAIN_PER_S;
        derivative[ATTITUDE] =
            -(v[0] * omega[0] + v[1] * omega[1] + v[2] * omega[2]) * 0.5 + q[0] * norm_term;
        for i in 0..3 {
            derivative[ATTITUDE + 1 + i] = (q[0] * omega[i] + vw[i]) * 0.5 + q[1 + i] * norm_term;
        }
        let omega_dot = omega_dot(&self.inertia_at(mass), &omega, &torque);
        derivative[OMEGA..OMEGA + 3].copy_from_slice(&omega_dot);
        let rcs_flow = match (self.rcs_mass_flow_per_newton, &self.thrusters) {
            (Some(per_newton), None) if self.rcs.moment_arm_m > 0.0 => {
                (rcs_torque[0].abs() + rcs_torque[1].abs() + rcs_torque[2].abs())
                    / self.rcs.moment_arm_m
                    * per_newton
            }
            _ => zero(),
        };
        derivative[MASS] = -(thrust * self.mass_flow_per_newton()) - rcs_flow;
        if self.has_actuator_lags() {
            let tau = self.engines.time_constant_s;
            let rate = if tau > 0.0 {
                (target - lag) / tau
            } else {
                zero()
            };
            let limit = self.throttle_rate_limit_nps;
            derivative[THRUST_LAG] = if limit == 0.0 {
                rate
            } else if tau > 0.0 {
                rate.max_const(-limit).min_const(limit)
            } else {
                // A ramp without a lag (Co-Simulation only): a constant rate to the target.
                let gap = target.value() - lag.value();
                S::from(if gap > 0.0 {
                    limit
                } else if gap < 0.0 {
                    -limit
                } else {
                    0.0
                })
            };
            let tau = self.rcs.time_constant_s;
            if self.thrusters.is_none() && tau > 0.0 {
                for i in 0..3 {
                    derivative[TORQUE_LAG + i] = (rcs_target[i] - x[TORQUE_LAG + i]) / tau;
                }
            }
        }
        if flags.touchdown {
            derivative = [zero(); STATES];
        }
        Unknowns {
            derivative,
            r_nue,
            v_nue,
            q_unit: unit(&q),
            altitude,
            thrust_n: thrust_out,
            rcs_torque_body_nm: rcs_torque,
            engine_torque_body_nm: engine_torque_out,
            specific_force_body_mps2: specific_force,
        }
    }
}
