//! The tube a result signal must stay in around its reference, built as fmpy's
//! `validate_signal` (`fmpy.cross_check`) builds its band, so that a verdict here and one in
//! fmpy can be compared: the reference resampled on [`POINTS`] evenly spaced times over the
//! window (and, unlike fmpy, at its own times too); at each, the least and the greatest
//! resampled value within the time tolerance on either side; those widened by the
//! half-width; the result's samples inside the window compared with that band,
//! interpolated linearly at their times.
//!
//! A reference thinned to every k-th communication point (as ours are, to keep FMUs small)
//! vouches for those points only: between two of its rows a noisy or fast signal does what
//! the reference cannot show. So the result is judged at the samples whose times the
//! reference has; only when it shares no time with the reference (a reference written on
//! another tool's grid) at all of its samples, as fmpy judges them.
//!
//! fmpy's half-width is `dy` times the reference's range over the window (times its value
//! when it is constant, and 0.5 when it is zero throughout); here it is the relative
//! tolerance times the same scale, and never less than the absolute tolerance, which takes
//! the place of the 0.5. fmpy's cross-check accepts a signal with up to 10 % of its samples
//! outside; here one sample outside fails it.

/// Resampling points of the reference over the window: fmpy's `num`.
pub const POINTS: usize = 1000;

/// How far a result may stray from its reference.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Tolerances {
    /// Of the reference's range over the window (of its value when it is constant): fmpy's
    /// `dy`.
    pub relative: f64,
    /// The least half-width of the tube, in the signal's unit.
    pub absolute: f64,
    /// Of the window's length, on either side of each time: fmpy's `dx = 21` of its 1000
    /// points is 10 intervals either side, 0.01.
    pub time: f64,
}

impl Default for Tolerances {
    /// fmpy's: `dy = 0.1`, `dx = 21`; no absolute floor.
    fn default() -> Self {
        Tolerances {
            relative: 0.1,
            absolute: 0.0,
            time: 0.01,
        }
    }
}

/// Why `value` cannot be the `which` tolerance ("relative", "absolute", "time"), if it
/// cannot: each is a finite number at least 0, the time one at most 1.
pub fn problem(which: &str, value: f64) -> Option<String> {
    let most = if which == "time" { 1.0 } else { f64::INFINITY };
    if value.is_finite() && value >= 0.0 && value <= most {
        None
    } else if most.is_finite() {
        Some(format!("{value} is not a number from 0 to {most}"))
    } else {
        Some(format!("{value} is not a finite number at least 0"))
    }
}

/// One signal's comparison with its reference.
#[derive(Debug, Clone, PartialEq)]
pub struct SignalCheck {
    pub name: String,
    /// The result's samples inside the window.
    pub samples: usize,
    /// How many of them lie outside the tube.
    pub outside: usize,
    /// The half-width of the tube.
    pub half_width: f64,
    /// The largest distance from the reference (interpolated at the result's times), and
    /// the time of it.
    pub largest_deviation: (f64, f64),
    /// The farthest a sample lies beyond the tube, its time, its value and the tube there;
    /// `None` when every sample is inside.
    pub worst_outside: Option<Outside>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outside {
    pub by: f64,
    pub time: f64,
    pub value: f64,
    pub tube: (f64, f64),
}

impl SignalCheck {
    pub fn passes(&self) -> bool {
        self.outside == 0
    }

    /// One line: the verdict, the largest deviation and where, and for a failure the worst
    /// sample outside the tube.
    pub fn describe(&self) -> String {
        let (deviation, at) = self.largest_deviation;
        match &self.worst_outside {
            None => format!(
                "{}: pass: largest deviation {deviation:.3e} at t = {} s, inside the tube \
                 of half-width {:.3e} ({} samples)",
                self.name,
                seconds(at),
                self.half_width,
                self.samples
            ),
            Some(o) => format!(
                "{}: FAIL: {} of {} samples outside the tube; the worst at t = {} s, {:.6} \
                 against a tube of [{:.6}, {:.6}], {:.3e} beyond it; largest deviation \
                 {deviation:.3e} at t = {} s",
                self.name,
                self.outside,
                self.samples,
                seconds(o.time),
                o.value,
                o.tube.0,
                o.tube.1,
                o.by,
                seconds(at)
            ),
        }
    }
}

/// A time as people read it: 4.02, not the 4.0200000000000005 a sum of steps gives.
fn seconds(t: f64) -> String {
    let text = format!("{t:.9}");
    text.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// Whether `t` is one of the sorted `xp`, to a billionth of its size: times written as the
/// shortest decimal read back to the same bits, a sum of steps to within a few ulps.
fn is_among(t: f64, xp: &[f64]) -> bool {
    let near = 1e-9 * t.abs().max(1.0);
    let after = xp.partition_point(|&x| x < t - near);
    xp.get(after).is_some_and(|&x| (x - t).abs() <= near)
}

/// `xp`, `fp` linearly interpolated at `x`, held beyond the ends (numpy's `interp`).
fn interp(x: f64, xp: &[f64], fp: &[f64]) -> f64 {
    let after = xp.partition_point(|&t| t <= x);
    if after == 0 {
        return fp[0];
    }
    if after == xp.len() {
        return fp[xp.len() - 1];
    }
    let (x0, x1) = (xp[after - 1], xp[after]);
    if x1 == x0 {
        return fp[after];
    }
    fp[after - 1] + (fp[after] - fp[after - 1]) * ((x - x0) / (x1 - x0))
}

/// Compares `values` at `times` with the reference `ref_values` at `ref_times` over the
/// window [`start`, `stop`].
#[allow(clippy::too_many_arguments)]
pub fn check(
    name: &str,
    times: &[f64],
    values: &[f64],
    ref_times: &[f64],
    ref_values: &[f64],
    start: f64,
    stop: f64,
    tolerances: &Tolerances,
) -> SignalCheck {
    // Of the samples at one repeated time only the first is kept, as fmpy does: the band
    // then rises over the interval after the event, which the time tolerance covers.
    let mut xp = Vec::with_capacity(ref_times.len());
    let mut fp = Vec::with_capacity(ref_times.len());
    for (&t, &y) in ref_times.iter().zip(ref_values) {
        if xp.last().is_none_or(|&last| t > last) {
            xp.push(t);
            fp.push(y);
        }
    }
    // fmpy's points, and the reference's own times in the window: on the points alone a
    // spike narrower than their spacing would leave the reference outside its own tube.
    let mut band_t: Vec<f64> = (0..POINTS)
        .map(|i| start + (stop - start) * i as f64 / (POINTS - 1) as f64)
        .chain(xp.iter().copied().filter(|&t| t > start && t < stop))
        .collect();
    band_t.sort_by(f64::total_cmp);
    band_t.dedup();
    let band: Vec<f64> = band_t.iter().map(|&t| interp(t, &xp, &fp)).collect();
    let (low, high) = band
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &y| {
            (l.min(y), h.max(y))
        });
    let scale = if high > low { high - low } else { low.abs() };
    let half_width = (tolerances.relative * scale).max(tolerances.absolute);
    // fmpy's reach: a whole number of its points' intervals either side.
    let interval = (stop - start) / (POINTS - 1) as f64;
    let reach = (tolerances.time * (POINTS - 1) as f64).round() * interval + 1e-9 * interval;
    let mut lower = Vec::with_capacity(band_t.len());
    let mut upper = Vec::with_capacity(band_t.len());
    let mut first = 0;
    for &t in &band_t {
        while band_t[first] < t - reach {
            first += 1;
        }
        let (mut least, mut most) = (f64::INFINITY, f64::NEG_INFINITY);
        for (&u, &y) in band_t[first..].iter().zip(&band[first..]) {
            if u > t + reach {
                break;
            }
            least = least.min(y);
            most = most.max(y);
        }
        lower.push(least - half_width);
        upper.push(most + half_width);
    }
    let mut result = SignalCheck {
        name: name.to_owned(),
        samples: 0,
        outside: 0,
        half_width,
        largest_deviation: (0.0, start),
        worst_outside: None,
    };
    let inside_window = |t: f64| t >= start && t <= stop;
    let shared = times.iter().any(|&t| inside_window(t) && is_among(t, &xp));
    for (&t, &y) in times.iter().zip(values) {
        if !inside_window(t) || (shared && !is_among(t, &xp)) {
            continue;
        }
        result.samples += 1;
        let deviation = (y - interp(t, &xp, &fp)).abs();
        if deviation > result.largest_deviation.0 || deviation.is_nan() {
            result.largest_deviation = (deviation, t);
        }
        let tube = (interp(t, &band_t, &lower), interp(t, &band_t, &upper));
        // NaN is outside every tube.
        let inside = y >= tube.0 && y <= tube.1;
        if !inside {
            result.outside += 1;
            let by = if y.is_nan() {
                f64::INFINITY
            } else {
                (tube.0 - y).max(y - tube.1)
            };
            if result.worst_outside.is_none_or(|w| by > w.by) {
                result.worst_outside = Some(Outside {
                    by,
                    time: t,
                    value: y,
                    tube,
                });
            }
        }
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize, stop: f64) -> Vec<f64> {
        (0..=n).map(|i| stop * i as f64 / n as f64).collect()
    }

    #[test]
    fn a_signal_equal_to_its_reference_passes_and_one_perturbed_fails_where_it_strays() {
        let t = grid(200, 2.0);
        let y: Vec<f64> = t.iter().map(|t| libm::sin(3.0 * t)).collect();
        let same = check("y", &t, &y, &t, &y, 0.0, 2.0, &Tolerances::default());
        assert!(same.passes(), "{}", same.describe());
        assert_eq!(same.samples, 201);
        assert_eq!(same.largest_deviation.0, 0.0);

        let mut bent = y.clone();
        bent[150] += 0.5;
        let strayed = check("y", &t, &bent, &t, &y, 0.0, 2.0, &Tolerances::default());
        assert!(!strayed.passes());
        assert_eq!(strayed.outside, 1);
        let worst = strayed.worst_outside.unwrap();
        assert_eq!(worst.time, 1.5);
        assert!(strayed.describe().contains("FAIL") && strayed.describe().contains("t = 1.5 s"));
        // The range of sin over [0, 2] is 2: the tube is 0.2 wide either side.
        assert!((strayed.half_width - 0.2).abs() < 1e-3);
    }

    #[test]
    fn a_step_a_little_late_stays_inside_the_time_tolerance() {
        let t = grid(1000, 10.0);
        let step =
            |at: f64| -> Vec<f64> { t.iter().map(|&t| if t >= at { 1.0 } else { 0.0 }).collect() };
        let tol = Tolerances {
            relative: 0.01,
            ..Tolerances::default()
        };
        // 0.01 of 10 s either side.
        assert!(check("s", &t, &step(5.05), &t, &step(5.0), 0.0, 10.0, &tol).passes());
        assert!(!check("s", &t, &step(5.3), &t, &step(5.0), 0.0, 10.0, &tol).passes());
    }

    #[test]
    fn a_constant_reference_is_held_to_its_absolute_tolerance_and_nan_always_fails() {
        let t = grid(10, 1.0);
        let zero = vec![0.0; 11];
        let mut off = zero.clone();
        off[3] = 1e-7;
        assert!(!check("z", &t, &off, &t, &zero, 0.0, 1.0, &Tolerances::default()).passes());
        let tol = Tolerances {
            absolute: 1e-6,
            ..Tolerances::default()
        };
        assert!(check("z", &t, &off, &t, &zero, 0.0, 1.0, &tol).passes());
        off[5] = f64::NAN;
        let nan = check("z", &t, &off, &t, &zero, 0.0, 1.0, &tol);
        assert_eq!(nan.outside, 1);
        assert_eq!(nan.worst_outside.unwrap().time, 0.5);
    }

    #[test]
    fn a_thinned_reference_judges_the_result_at_its_own_times_only() {
        let fine = grid(100, 1.0);
        // Noise between the reference's rows, which it cannot vouch for.
        let noisy: Vec<f64> = (0..=100)
            .map(|k| if k % 10 == 0 { 0.0 } else { 5.0 })
            .collect();
        let coarse = grid(10, 1.0);
        let zero = vec![0.0; 11];
        let tol = Tolerances::default();
        let c = check("n", &fine, &noisy, &coarse, &zero, 0.0, 1.0, &tol);
        assert!(c.passes(), "{}", c.describe());
        assert_eq!(c.samples, 11);
        // A reference on another grid shares no time: every sample is judged.
        let shifted: Vec<f64> = coarse.iter().map(|t| t + 0.005).collect();
        let c = check("n", &fine, &noisy, &shifted, &zero, 0.0, 1.0, &tol);
        assert_eq!(c.samples, 101);
        assert!(!c.passes());
    }

    #[test]
    fn samples_outside_the_window_are_not_judged() {
        let t = grid(10, 1.0);
        let y = vec![1.0; 11];
        let mut late = y.clone();
        late[10] = 5.0;
        let c = check("y", &t, &late, &t, &y, 0.0, 0.95, &Tolerances::default());
        assert!(c.passes());
        assert_eq!(c.samples, 10);
    }

    #[test]
    fn tolerances_out_of_range_are_named() {
        assert_eq!(
            problem("relative", -1.0).as_deref(),
            Some("-1 is not a finite number at least 0")
        );
        assert!(problem("absolute", f64::NAN).is_some());
        assert_eq!(
            problem("time", 2.0).as_deref(),
            Some("2 is not a number from 0 to 1")
        );
        assert_eq!(problem("time", 0.5), None);
        assert_eq!(problem("absolute", 1e9), None);
    }
}
