//! How a run starts and keeps time, beyond the exchange ordering. The defaults are the
//! harness's own conventions; the alternatives reproduce another master call for call, so
//! that a comparison with it (tests/interop) can demand bit-identical trajectories instead of
//! a tolerance that would hide a real difference.
//!
//! | master                 | ordering | initial inputs | time grid     | stop time declared |
//! |------------------------|----------|----------------|---------------|--------------------|
//! | harness (default)      | either   | `Exchanged`    | `StepCounter` | yes                |
//! | fmpy `simulate_ssp`    | Jacobi   | `Zero`         | `Accumulated` | no                 |
//! | libcosim fixed step    | Jacobi   | `Exchanged`    | `Nanoseconds` | yes                |
//! | Ecos fixed step        | Jacobi   | `Exchanged`    | `Accumulated` | no                 |

/// A run's conventions; `Default` is the harness's own.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Conventions {
    pub initial_inputs: InitialInputs,
    pub time_grid: TimeGrid,
    /// Whether `fmi2SetupExperiment` declares the stop time. fmpy's `simulate_ssp` does not,
    /// and needs that: its accumulated time steps past the stop time, which an FMU that was
    /// given the stop time refuses.
    pub stop_time_declared: bool,
}

impl Default for Conventions {
    fn default() -> Self {
        Self {
            initial_inputs: InitialInputs::Exchanged,
            time_grid: TimeGrid::StepCounter,
            stop_time_declared: true,
        }
    }
}

impl Conventions {
    /// fmpy 0.3's `simulate_ssp` (with [`crate::system::Ordering::Jacobi`]).
    pub const FMPY_SIMULATE_SSP: Self = Self {
        initial_inputs: InitialInputs::Zero,
        time_grid: TimeGrid::Accumulated,
        stop_time_declared: false,
    };
    /// libcosim's `fixed_step_algorithm` (with [`crate::system::Ordering::Jacobi`]).
    pub const LIBCOSIM: Self = Self {
        initial_inputs: InitialInputs::Exchanged,
        time_grid: TimeGrid::Nanoseconds,
        stop_time_declared: true,
    };
    /// Ecos's `fixed_step_algorithm` (with [`crate::system::Ordering::Jacobi`]): it exchanges
    /// in initialization mode as libcosim does, but keeps time as a running sum of the step
    /// (`step_until` steps while the sum is below the stop time), and knows no stop time
    /// when it initializes the FMUs.
    pub const ECOS: Self = Self {
        initial_inputs: InitialInputs::Exchanged,
        time_grid: TimeGrid::Accumulated,
        stop_time_declared: false,
    };
}

/// What the connected inputs hold at the first step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum InitialInputs {
    /// Outputs are exchanged in initialization mode, so the first step sees the plant's
    /// initial state and the controller's answer to it.
    #[default]
    Exchanged,
    /// No exchange before the first step, every connected input is 0.0 at it, and the row
    /// recorded at the start time is all zeros: fmpy's `simulate_ssp` initialises every
    /// connector to 0.0 and exchanges only after stepping. Meaningful with Jacobi only
    /// (Gauss-Seidel sets each input from a fresh output before the first step).
    Zero,
}

/// How the communication points `t_k` and step sizes `h_k` are computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum TimeGrid {
    /// `t_k = start + k h` from an integer step counter, each point exact to one rounding;
    /// the last step is shortened to land on the stop time.
    #[default]
    StepCounter,
    /// `t_{k+1} = t_k + h` accumulated in floating point, stepping while `t_k < stop` with
    /// the full `h` (fmpy's `simulate_ssp`); the run ends where the sum ends.
    Accumulated,
    /// Integer nanoseconds, as libcosim's `time_point`: `t_k = (start_ns + k h_ns) / 1e9`
    /// and `h_k = t_{k+1} - t_k` (libcosim's `to_double_duration`), so `h_k` differs from
    /// `h` by rounding.
    Nanoseconds,
}

/// The communication points of one run: `next` yields `(t_k, h_k)` until the stop time.
#[derive(Debug, Clone)]
pub(super) struct Clock {
    grid: TimeGrid,
    start: f64,
    stop: f64,
    step: f64,
    k: u64,
    steps: u64,
    accumulated: f64,
    start_ns: i64,
    step_ns: i64,
    stop_ns: i64,
}

impl Clock {
    pub(super) fn new(grid: TimeGrid, start: f64, stop: f64, step: f64) -> Self {
        // A step count within 1e-9 of an integer is that integer: 172 / 0.01 is 17200.
        let ratio = (stop - start) / step;
        let steps = if (ratio - ratio.round()).abs() < 1e-9 * ratio.max(1.0) {
            ratio.round() as u64
        } else {
            ratio.ceil() as u64
        };
        let ns = |t: f64| (t * 1e9).round() as i64;
        Self {
            grid,
            start,
            stop,
            step,
            k: 0,
            steps,
            accumulated: start,
            start_ns: ns(start),
            step_ns: ns(step).max(1),
            stop_ns: ns(stop),
        }
    }

    /// The next step `(t_k, h_k)`, or `None` when the run has reached its end.
    pub(super) fn next_step(&mut self) -> Option<(f64, f64)> {
        let step = match self.grid {
            TimeGrid::StepCounter => {
                if self.k == self.steps {
                    return None;
                }
                let time = self.start + self.k as f64 * self.step;
                let h = if self.k + 1 == self.steps {
                    self.stop - time
                } else {
                    self.step
                };
                (time, h)
            }
            TimeGrid::Accumulated => {
                if self.accumulated >= self.stop {
                    return None;
                }
                let time = self.accumulated;
                self.accumulated += self.step;
                (time, self.step)
            }
            TimeGrid::Nanoseconds => {
                let t_ns = self.start_ns + self.k as i64 * self.step_ns;
                if t_ns >= self.stop_ns {
                    return None;
                }
                let next_ns = (t_ns + self.step_ns).min(self.stop_ns);
                let time = seconds(t_ns);
                (time, seconds(next_ns) - time)
            }
        };
        self.k += 1;
        Some(step)
    }

    /// The rows a run records (one per step and one at the end), give or take the rounding
    /// of an accumulated or nanosecond grid: a capacity to reserve, not a count to rely on.
    pub(super) fn rows_hint(&self) -> usize {
        usize::try_from(self.steps.saturating_add(2)).unwrap_or(usize::MAX)
    }

    /// The step counter and running sum: all that moves, so all a saved run keeps.
    pub(super) fn position(&self) -> (u64, f64) {
        (self.k, self.accumulated)
    }

    /// Goes on from a [`Clock::position`] of a clock of the same grid.
    pub(super) fn resume(&mut self, (k, accumulated): (u64, f64)) {
        self.k = k;
        self.accumulated = accumulated;
    }

    /// The time of the row recorded after the last step.
    pub(super) fn end_time(&self) -> f64 {
        match self.grid {
            TimeGrid::StepCounter => self.stop,
            TimeGrid::Accumulated => self.accumulated,
            TimeGrid::Nanoseconds => seconds(self.stop_ns),
        }
    }
}

/// Nanoseconds to seconds as `std::chrono::duration_cast<duration<double>>` does it: one
/// correctly rounded division.
fn seconds(ns: i64) -> f64 {
    ns as f64 / 1e9
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(grid: TimeGrid, start: f64, stop: f64, step: f64) -> Vec<(f64, f64)> {
        let mut clock = Clock::new(grid, start, stop, step);
        std::iter::from_fn(|| clock.next_step()).collect()
    }

    #[test]
    fn step_counter_points_are_one_product_each_and_land_on_the_stop_time() {
        let steps = all(TimeGrid::StepCounter, 0.0, 172.0, 0.01);
        assert_eq!(steps.len(), 17200);
        for (k, &(t, _)) in steps.iter().enumerate() {
            assert_eq!(t, k as f64 * 0.01);
        }
        let &(t_last, h_last) = steps.last().unwrap();
        assert_eq!(t_last + h_last, 172.0);
        // A stop time off the grid: the last step is shortened.
        let steps = all(TimeGrid::StepCounter, 0.0, 0.25, 0.1);
        assert_eq!(steps.len(), 3);
        assert!((steps[2].1 - 0.05).abs() < 1e-15);
    }

    #[test]
    fn accumulated_points_are_running_sums_and_drift_from_the_step_counter() {
        let steps = all(TimeGrid::Accumulated, 0.0, 172.0, 0.01);
        let mut sum = 0.0;
        for &(t, h) in &steps {
            assert_eq!(t, sum);
            assert_eq!(h, 0.01);
            sum += 0.01;
        }
        assert!(sum >= 172.0 && steps.last().unwrap().0 < 172.0);
        // The sum of 0.01 is not k * 0.01 for every k: that is why the mode exists.
        assert!(steps
            .iter()
            .enumerate()
            .any(|(k, &(t, _))| t != k as f64 * 0.01));
    }

    #[test]
    fn nanosecond_points_are_exact_decimals_and_steps_are_their_differences() {
        let steps = all(TimeGrid::Nanoseconds, 0.0, 172.0, 0.01);
        assert_eq!(steps.len(), 17200);
        for (k, w) in steps.windows(2).enumerate() {
            // k / 100 correctly rounded, independently of the clock's own arithmetic.
            let expected: f64 = format!("{}.{:02}", k / 100, k % 100).parse().unwrap();
            assert_eq!(w[0].0, expected);
            assert_eq!(w[0].1, w[1].0 - w[0].0);
        }
        assert!(steps.iter().any(|&(_, h)| h != 0.01));
        let &(t_last, h_last) = steps.last().unwrap();
        assert_eq!(t_last + h_last, 172.0);
    }
}
