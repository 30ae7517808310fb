//! The terminal descent (phase 5, beyond the paper): straight down over the site after the
//! target hover, at a sink rate that may slow with height, and the engine cut-off.
//!
//! Flown profiles slow down near the ground (Apollo's P66 and Chandrayaan-3's terminal
//! descent end at 0.5-1 m/s) and cut the engine at a small height or on a touchdown sensor,
//! so the lander falls the last metre with its engines off rather than digging a crater
//! or bouncing on its own thrust. The profile here:
//!
//! ```text
//! sink(h) = speed                              flare_time = 0 (constant sink, the default)
//! sink(h) = clamp(h / flare_time, final, speed) otherwise, h = height above the ground
//! ```
//!
//! Inside the clamp the reference is `h' = -h / flare_time`, an exponential approach whose
//! time constant is `flare_time`; its derivative, `sink / flare_time` upward, is fed forward,
//! so the velocity loop does not lag the slowing reference. Below `cutoff_height` (heights
//! from the navigation input at the guidance cycle, 10 Hz by default) the engine is cut for
//! the rest of the flight; a fall from the cut-off height `h_c` at sink `v` reaches the
//! ground at `sqrt(v^2 + 2 g h_c)`.

/// The terminal descent's profile and cut-off, in SI; heights above `ground_height_m`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TerminalDescent {
    /// Sink rate high up, m/s; 0 = no terminal descent (the hover is held: the paper).
    pub speed_mps: f64,
    /// Sink rate at the ground, m/s, in [0, `speed_mps`]; used only with a flare time.
    pub final_speed_mps: f64,
    /// Time constant of the slowing sink, s; 0 = a constant `speed_mps`.
    pub flare_time_s: f64,
    /// Up coordinate of the ground under the site, m.
    pub ground_height_m: f64,
    /// Height above the ground at or below which the engine is cut, m; negative = never.
    pub cutoff_height_m: f64,
}

impl TerminalDescent {
    /// The paper's: no terminal descent.
    pub const NONE: TerminalDescent = TerminalDescent {
        speed_mps: 0.0,
        final_speed_mps: 0.0,
        flare_time_s: 0.0,
        ground_height_m: 0.0,
        cutoff_height_m: -1.0,
    };

    /// Whether phase 5 follows the target hover.
    pub fn enabled(&self) -> bool {
        self.speed_mps > 0.0
    }

    /// The commanded sink rate (m/s, positive down) at altitude `altitude_m` (Up), and the
    /// upward acceleration of the reference to feed forward.
    pub fn sink_rate_mps(&self, altitude_m: f64) -> (f64, f64) {
        if self.flare_time_s <= 0.0 {
            return (self.speed_mps, 0.0);
        }
        let exponential = (altitude_m - self.ground_height_m) / self.flare_time_s;
        if exponential >= self.speed_mps {
            (self.speed_mps, 0.0)
        } else if exponential <= self.final_speed_mps {
            (self.final_speed_mps, 0.0)
        } else {
            (exponential, exponential / self.flare_time_s)
        }
    }

    /// Whether the engine is to be cut at altitude `altitude_m` (Up).
    pub fn cuts_off_at(&self, altitude_m: f64) -> bool {
        self.cutoff_height_m >= 0.0 && altitude_m - self.ground_height_m <= self.cutoff_height_m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flaring() -> TerminalDescent {
        TerminalDescent {
            speed_mps: 2.0,
            final_speed_mps: 0.5,
            flare_time_s: 10.0,
            ground_height_m: 3.0,
            cutoff_height_m: 1.0,
        }
    }

    #[test]
    fn without_a_flare_time_the_sink_rate_is_constant() {
        let constant = TerminalDescent {
            speed_mps: 1.0,
            ..TerminalDescent::NONE
        };
        for altitude in [150.0, 1.0, -5.0] {
            assert_eq!(constant.sink_rate_mps(altitude), (1.0, 0.0));
        }
        assert!(constant.enabled() && !TerminalDescent::NONE.enabled());
        assert!(
            !constant.cuts_off_at(-100.0),
            "a negative cut-off height never cuts"
        );
    }

    #[test]
    fn the_sink_slows_with_height_between_the_two_speeds() {
        let p = flaring();
        // 40 m above the ground: 4 m/s would exceed the top speed
        assert_eq!(p.sink_rate_mps(43.0), (2.0, 0.0));
        // 10 m above: h / tau = 1 m/s, and the reference slows at 1 / 10 m/s^2
        let (sink, ff) = p.sink_rate_mps(13.0);
        assert!((sink - 1.0).abs() < 1e-15 && (ff - 0.1).abs() < 1e-15);
        // 2 m above: the final speed
        assert_eq!(p.sink_rate_mps(5.0), (0.5, 0.0));
    }

    #[test]
    fn following_the_profile_takes_the_exponential_time() {
        // GIVEN the profile flown exactly (h' = -sink(h)) from 20 m (sink = top speed)
        let p = flaring();
        let (mut h, dt) = (20.0, 1e-4);
        let mut t = 0.0;
        let mut t_at_final = None;
        while h > 0.0 {
            let (sink, _) = p.sink_rate_mps(h + p.ground_height_m);
            if sink == p.final_speed_mps && t_at_final.is_none() {
                t_at_final = Some(t);
            }
            h -= sink * dt;
            t += dt;
        }
        // THEN from 20 m to tau * final = 5 m takes tau ln(20 / 5) (exponential), and the
        // last 5 m at the final speed 10 s
        let expected = 10.0 * libm::log(20.0f64 / 5.0);
        let t_at_final = t_at_final.unwrap();
        assert!(
            (t_at_final - expected).abs() < 1e-3,
            "{t_at_final} vs {expected}"
        );
        assert!((t - t_at_final - 10.0).abs() < 1e-3, "{t}");
    }

    #[test]
    fn the_engine_is_cut_at_and_below_the_cut_off_height() {
        let p = flaring();
        assert!(!p.cuts_off_at(4.0 + 1e-9));
        assert!(p.cuts_off_at(4.0));
        assert!(p.cuts_off_at(0.0));
    }
}
