//! Pulse-width pulse-frequency (PWPF) modulation of one thruster, sampled with exact pulse ends.
//!
//! The classic modulator: a first-order filter `Tm x' = Km (u - y) - x` of the demand `u`
//! (fraction of full thrust) minus the thruster's output `y` (1 on, 0 off) drives a Schmitt
//! trigger that switches on at `x >= Uon` and off at `x <= Uoff`. Between switchings `x` is an
//! exponential, so it is propagated in closed form:
//! * a pulse starts only at a sample (the duty output fires from the step's start), when
//!   `x >= Uon` there;
//! * it ends at the exact time `x` reaches `Uoff`, possibly inside the period; the on-time
//!   is the duty, and a pulse that fills the period carries on into the next one.
//!
//! Over a pulse cycle `x` averages about `(Uon + Uoff) / 2`, which lowers the mean output
//! by that over `Km`: the modulator adds it back to every positive demand (bias
//! compensation), so the mean thrust follows the demand (`tests/thrusters.rs` measures it).
//! Demands below about `(Uon - Uoff) / (2 Km)` stay unfired: the dead zone.
use serde::{Deserialize, Serialize};

/// The modulator's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PwpfSettings {
    /// Filter gain Km.
    pub gain: f64,
    /// Filter time constant Tm, s.
    pub time_constant_s: f64,
    /// Trigger on and off thresholds, `0 < off < on`.
    pub on_threshold: f64,
    pub off_threshold: f64,
}

/// One thruster's modulator state: part of the FMU state.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Pwpf {
    pub filter: f64,
    pub on: bool,
}

impl PwpfSettings {
    /// The filter value after `dt` s towards `target` from `x`.
    fn relax(&self, x: f64, target: f64, dt: f64) -> f64 {
        target + (x - target) * libm::exp(-dt / self.time_constant_s)
    }
}

impl Pwpf {
    /// Advances over a period of `period_s` with the demand `demand` (clamped to [0, 1]);
    /// returns the on-time from the period's start, s.
    pub fn step(&mut self, settings: &PwpfSettings, demand: f64, period_s: f64) -> f64 {
        let s = settings;
        let demand = if demand.is_nan() {
            0.0
        } else {
            demand.clamp(0.0, 1.0)
        };
        let compensated = if demand > 0.0 {
            demand + 0.5 * (s.on_threshold + s.off_threshold) / s.gain
        } else {
            0.0
        };
        if !self.on && self.filter >= s.on_threshold {
            self.on = true;
        }
        if !self.on {
            self.filter = s.relax(self.filter, s.gain * compensated, period_s);
            return 0.0;
        }
        let target_on = s.gain * (compensated - 1.0);
        // While on, x falls towards Km (u - 1); it crosses Uoff after t_off.
        let t_off = if target_on < s.off_threshold && self.filter > s.off_threshold {
            s.time_constant_s * libm::log((self.filter - target_on) / (s.off_threshold - target_on))
        } else if self.filter <= s.off_threshold {
            0.0
        } else {
            f64::INFINITY
        };
        if t_off >= period_s {
            self.filter = s.relax(self.filter, target_on, period_s);
            return period_s;
        }
        self.on = false;
        self.filter = s.relax(s.off_threshold, s.gain * compensated, period_s - t_off);
        t_off
    }
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;

    const SETTINGS: PwpfSettings = PwpfSettings {
        gain: 10.0,
        time_constant_s: 0.5,
        on_threshold: 0.5,
        off_threshold: 0.2,
    };

    fn mean_output(demand: f64) -> f64 {
        let (mut m, period, n) = (Pwpf::default(), 0.01, 20_000);
        let mut on_s = 0.0;
        for k in 0..n {
            let t = m.step(&SETTINGS, demand, period);
            if k >= n / 2 {
                on_s += t;
            }
        }
        on_s / (period * (n / 2) as f64)
    }

    #[test]
    fn no_demand_never_fires_and_full_demand_always_fires() {
        assert_eq!(mean_output(0.0), 0.0);
        // Sums of 10 000 periods of 0.01 s: round-off only.
        assert!((mean_output(1.0) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_mean_output_follows_the_demand_within_2_percent_above_the_dead_zone() {
        for demand in [0.1, 0.2, 0.35, 0.5, 0.75, 0.9] {
            let mean = mean_output(demand);
            assert!((mean / demand - 1.0).abs() < 0.02, "{demand}: {mean}");
        }
    }

    #[test]
    fn a_pulse_ends_exactly_where_the_filter_reaches_the_off_threshold() {
        // GIVEN the trigger at its on threshold and a zero demand: x falls towards -Km
        let mut m = Pwpf {
            filter: 0.5,
            on: false,
        };
        let t = m.step(&SETTINGS, 0.0, 0.1);
        // THEN it fires for Tm ln((0.5 + 10) / (0.2 + 10)) and is off, past the threshold
        let expected = 0.5 * (10.5f64 / 10.2).ln();
        assert!((t - expected).abs() < 1e-15, "{t} vs {expected}");
        assert!(!m.on && m.filter < 0.2);
    }
}
