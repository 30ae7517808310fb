//! Shaped thrust-axis manoeuvre (beyond the paper): instead of stepping the reference by
//! `phi_cmd`, which asks a saturated RCS for a rate it cannot brake (70-80 deg/s at 150 deg),
//! the reference angle follows `phi_cmd` through the time-optimal profile under a rate and an
//! acceleration limit (bang-coast-bang, or bang-bang when the coast rate is not reached). The
//! profile's rate and acceleration are fed forward to the laws.
//!
//! The profile is propagated in closed form between samples, so it is the same curve whatever
//! the sample times, and it is exact at every sample.
use lander_math::frames::Body;
use serde::{Deserialize, Serialize};

/// The limits of the profile, each infinite when unlimited (not both).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProfileLimits {
    pub rate_radps: f64,
    pub accel_radps2: f64,
}

impl ProfileLimits {
    /// From the parameters, where 0 means "no limit on this one"; `None` (both 0) is the
    /// paper's step. Limits must be finite and >= 0 (validated).
    pub fn from_parameters(max_rate_radps: f64, max_accel_radps2: f64) -> Option<Self> {
        let unlimited_if_zero = |x: f64| if x > 0.0 { x } else { f64::INFINITY };
        (max_rate_radps > 0.0 || max_accel_radps2 > 0.0).then(|| Self {
            rate_radps: unlimited_if_zero(max_rate_radps),
            accel_radps2: unlimited_if_zero(max_accel_radps2),
        })
    }
}

/// The reference rotation about the thrust axis at a sample, with its derivatives.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RollReference {
    pub phi_rad: f64,
    pub rate_radps: f64,
    /// The acceleration the profile applies from this sample on.
    pub accel_radps2: f64,
}

impl RollReference {
    /// The paper's reference: the commanded angle, at rest.
    pub fn step(phi_cmd_rad: f64) -> Self {
        Self {
            phi_rad: phi_cmd_rad,
            ..Self::default()
        }
    }

    /// Reference body rate: a rotation about body y (the thrust axis).
    pub fn omega_body(&self) -> Body {
        Body::new(0.0, self.rate_radps, 0.0)
    }

    /// Reference body angular acceleration, about body y.
    pub fn alpha_body(&self) -> Body {
        Body::new(0.0, self.accel_radps2, 0.0)
    }
}

/// The profile's memory (part of the FMU state): where it was at its last sample and the
/// target it has been heading for since.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct PhiProfile {
    pub phi_rad: f64,
    pub rate_radps: f64,
    pub target_rad: f64,
    /// Time of the last sample; `None` before the first.
    pub time_s: Option<f64>,
}

impl PhiProfile {
    /// The profile at `t_s`: propagated from the last sample towards the target held since
    /// then (so a new `phi_cmd` starts moving the profile at the sample that first sees it),
    /// then heading for `target_rad`. A time before the last sample does not move it.
    pub fn advance(
        &self,
        limits: &ProfileLimits,
        t_s: f64,
        target_rad: f64,
    ) -> (Self, RollReference) {
        let elapsed_s = self.time_s.map_or(0.0, |t0| (t_s - t0).max(0.0));
        let (phi_rad, rate_radps, _) =
            Manoeuvre::plan(self.phi_rad, self.rate_radps, self.target_rad, limits).at(elapsed_s);
        let (_, _, accel_radps2) = Manoeuvre::plan(phi_rad, rate_radps, target_rad, limits).at(0.0);
        let next = Self {
            phi_rad,
            rate_radps,
            target_rad,
            time_s: Some(t_s),
        };
        let reference = RollReference {
            phi_rad,
            rate_radps,
            accel_radps2,
        };
        (next, reference)
    }
}

/// The time-optimal manoeuvre from `(phi0, rate0)` to rest at `target`: accelerate (or brake)
/// towards the peak rate, coast, brake to rest. Computed in the frame where the motion is
/// towards positive angles (`sign`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Manoeuvre {
    phi0_rad: f64,
    target_rad: f64,
    sign: f64,
    rate0_radps: f64,
    accel1_radps2: f64,
    accel_radps2: f64,
    peak_rate_radps: f64,
    t1_s: f64,
    t2_s: f64,
    t3_s: f64,
    dist1_rad: f64,
    dist2_rad: f64,
}

impl Manoeuvre {
    pub fn plan(phi0_rad: f64, rate0_radps: f64, target_rad: f64, limits: &ProfileLimits) -> Self {
        let a = limits.accel_radps2;
        let gap_rad = target_rad - phi0_rad;
        // Where braking now would stop, relative to the target, decides the direction.
        let overshoot_rad = gap_rad - rate0_radps * rate0_radps.abs() / (2.0 * a);
        let sign = if overshoot_rad > 0.0 || (overshoot_rad == 0.0 && rate0_radps >= 0.0) {
            1.0
        } else {
            -1.0
        };
        let dist_rad = sign * gap_rad;
        let u0 = sign * rate0_radps;
        let free_peak = if a.is_infinite() {
            if dist_rad > 0.0 {
                f64::INFINITY
            } else {
                0.0
            }
        } else {
            (a * dist_rad + 0.5 * u0 * u0).max(0.0).sqrt()
        };
        let peak = free_peak.min(limits.rate_radps);
        let accel1 = if peak >= u0 { a } else { -a };
        let (t1_s, dist1_rad) = if a.is_infinite() {
            (0.0, 0.0)
        } else {
            (
                (peak - u0) / accel1,
                (peak * peak - u0 * u0) / (2.0 * accel1),
            )
        };
        let (t3_s, dist3_rad) = if a.is_infinite() {
            (0.0, 0.0)
        } else {
            (peak / a, peak * peak / (2.0 * a))
        };
        let dist2_rad = (dist_rad - dist1_rad - dist3_rad).max(0.0);
        let t2_s = if peak > 0.0 { dist2_rad / peak } else { 0.0 };
        Self {
            phi0_rad,
            target_rad,
            sign,
            rate0_radps: u0,
            accel1_radps2: accel1,
            accel_radps2: a,
            peak_rate_radps: peak,
            t1_s,
            t2_s,
            t3_s,
            dist1_rad,
            dist2_rad,
        }
    }

    /// Time from the start to rest at the target.
    pub fn duration_s(&self) -> f64 {
        self.t1_s + self.t2_s + self.t3_s
    }

    /// Angle, rate and acceleration `tau_s` after the start (the acceleration of the phase
    /// that begins at `tau_s`).
    pub fn at(&self, tau_s: f64) -> (f64, f64, f64) {
        let (s, u0, a1, a, up) = (
            self.sign,
            self.rate0_radps,
            self.accel1_radps2,
            self.accel_radps2,
            self.peak_rate_radps,
        );
        let coast_end_s = self.t1_s + self.t2_s;
        if tau_s < self.t1_s {
            let d = u0 * tau_s + 0.5 * a1 * tau_s * tau_s;
            (self.phi0_rad + s * d, s * (u0 + a1 * tau_s), s * a1)
        } else if tau_s < coast_end_s {
            let d = self.dist1_rad + up * (tau_s - self.t1_s);
            (self.phi0_rad + s * d, s * up, 0.0)
        } else if tau_s < coast_end_s + self.t3_s {
            let tb = tau_s - coast_end_s;
            let d = self.dist1_rad + self.dist2_rad + up * tb - 0.5 * a * tb * tb;
            (self.phi0_rad + s * d, s * (up - a * tb), -s * a)
        } else {
            (self.target_rad, 0.0, 0.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits(rate: f64, accel: f64) -> ProfileLimits {
        ProfileLimits::from_parameters(rate, accel).unwrap()
    }

    /// Rest to rest over `d`: `d / v + v / a` when the coast rate is reached, else `2 sqrt(d / a)`.
    fn minimum_time_s(d: f64, v: f64, a: f64) -> f64 {
        if d >= v * v / a {
            d / v + v / a
        } else {
            2.0 * (d / a).sqrt()
        }
    }

    #[test]
    fn rest_to_rest_takes_the_analytic_minimum_time() {
        for (d, v, a) in [
            (150f64.to_radians(), 0.1, 0.05),  // bang-coast-bang
            (-150f64.to_radians(), 0.1, 0.05), // the other way
            (0.02, 0.1, 0.05),                 // bang-bang: the coast rate is not reached
            (1.0, 0.5, 2.0),
        ] {
            let m = Manoeuvre::plan(0.3, 0.0, 0.3 + d, &limits(v, a));
            let expected = minimum_time_s(d.abs(), v, a);
            assert!(
                (m.duration_s() - expected).abs() < 1e-12 * expected,
                "{d} {v} {a}"
            );
            let (phi, rate, accel) = m.at(m.duration_s());
            assert_eq!((phi, rate, accel), (0.3 + d, 0.0, 0.0));
            // just before the end it is still moving: no earlier arrival
            let (phi, _, _) = m.at(0.999 * m.duration_s());
            assert!((phi - 0.3 - d).abs() > 0.0);
        }
    }

    #[test]
    fn only_one_limit_set_gives_a_ramp_or_a_bang_bang() {
        let ramp = Manoeuvre::plan(0.0, 0.0, 2.0, &limits(0.5, 0.0));
        assert_eq!(ramp.duration_s(), 4.0);
        assert_eq!(ramp.at(1.0), (0.5, 0.5, 0.0));
        let bang = Manoeuvre::plan(0.0, 0.0, 2.0, &limits(0.0, 0.5));
        assert!((bang.duration_s() - 4.0).abs() < 1e-15);
        assert!(
            ProfileLimits::from_parameters(0.0, 0.0).is_none(),
            "both 0 = off"
        );
    }

    /// Sampled densely along manoeuvres from moving starts: within the limits, continuous in
    /// angle and rate, and the rate is the derivative of the angle.
    #[test]
    fn the_profile_never_exceeds_its_limits_and_is_continuous() {
        let lim = limits(0.2, 0.08);
        for (phi0, rate0, target) in [
            (0.0, 0.0, 2.6),
            (0.0, 0.15, -1.0), // moving away from the target
            (1.0, 0.2, 1.05),  // too fast to stop in time: overshoots and comes back
            (-2.0, -0.05, 3.0),
            (0.5, 0.0, 0.5),
        ] {
            let m = Manoeuvre::plan(phi0, rate0, target, &lim);
            let dt = 1e-4;
            let (mut phi_prev, mut rate_prev, _) = m.at(0.0);
            assert_eq!((phi_prev, rate_prev), (phi0, rate0));
            let steps = ((m.duration_s() + 1.0) / dt) as usize;
            for k in 1..=steps {
                let (phi, rate, accel) = m.at(k as f64 * dt);
                assert!(rate.abs() <= lim.rate_radps * (1.0 + 1e-12));
                assert!(accel.abs() <= lim.accel_radps2);
                assert!((rate - rate_prev).abs() <= lim.accel_radps2 * dt * (1.0 + 1e-9));
                // The rate is piecewise linear: the trapezoid is exact within a phase and off
                // by at most a dt / 4 across a change of acceleration.
                let mean_rate = (phi - phi_prev) / dt;
                assert!(
                    (mean_rate - 0.5 * (rate + rate_prev)).abs()
                        <= 0.25 * lim.accel_radps2 * dt + 1e-10,
                    "{phi0} {rate0} {target} at {k}"
                );
                (phi_prev, rate_prev) = (phi, rate);
            }
            assert_eq!((phi_prev, rate_prev), (target, 0.0));
        }
    }

    #[test]
    fn advancing_in_any_steps_follows_the_same_curve() {
        let lim = limits(0.2, 0.08);
        let target = 150f64.to_radians();
        let whole = Manoeuvre::plan(0.0, 0.0, target, &lim);
        let start = PhiProfile::default().advance(&lim, 12.0, target).0;
        let mut profile = start;
        let mut t = 12.0;
        for h in [0.01, 0.3, 0.07, 1.0, 2.5, 0.01, 4.0, 0.2]
            .iter()
            .cycle()
            .take(40)
        {
            t += h;
            let (next, reference) = profile.advance(&lim, t, target);
            let (phi, rate, _) = whole.at(t - 12.0);
            assert!((reference.phi_rad - phi).abs() < 1e-12, "t {t}");
            assert!((reference.rate_radps - rate).abs() < 1e-12, "t {t}");
            profile = next;
        }
        assert_eq!(profile.phi_rad, target);
    }

    #[test]
    fn a_new_target_starts_moving_the_profile_at_the_next_sample() {
        let lim = limits(0.2, 0.08);
        let (p, r) = PhiProfile::default().advance(&lim, 12.0, 1.0);
        assert_eq!((r.phi_rad, r.rate_radps, r.accel_radps2), (0.0, 0.0, 0.08));
        let (_, r) = p.advance(&lim, 12.5, 1.0);
        assert!((r.phi_rad - 0.5 * 0.08 * 0.25).abs() < 1e-15);
        assert!((r.rate_radps - 0.04).abs() < 1e-15);
    }
}
