//! Quantitative robustness of a formula over a recorded run (discrete-time signal temporal
//! logic): how far the signals are from violating it, in the compared signals' unit;
//! positive holds, negative is violated. A comparison `a < b` at a sample has robustness
//! `b - a`; `not` negates; `and`/`or` take the minimum/maximum; `always`/`eventually` the
//! minimum/maximum over the samples of their window; `a until [s, e] b` the best over the
//! window of `min(b at t', a at every sample up to t')`. Each value carries the time of the
//! sample that decides it.
//!
//! The sign alone cannot decide: `x < 2` and `x <= 2` at x = 2 both have robustness 0, and
//! only the second holds. Each value therefore carries its [`Truth`] as well, and `and`,
//! `or` and the windows order values by truth first, then robustness. A sample whose value
//! is not a number (a recorded NaN or infinity, `0 / 0`, `inf - inf`, the square root of a
//! negative) is [`Truth::Undefined`] and decides every window that reads it: it never
//! counts as satisfying, nor as the violation a `not` would turn into a success. A window
//! the run ended before is [`Truth::Inconclusive`] unless the samples it recorded decide it
//! (a violation of `always`, a success of `eventually`), or the run's end is not given
//! ([`Signals::ended_s`]), when it is judged over those samples.
use super::formula::{Comparison, Expr, Formula, Interval, Op};

/// Whether a formula holds at a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Truth {
    Holds,
    Violated,
    /// The run ended before the window `[from_s, to_s]` (times of the run) did, and its
    /// samples up to the end leave the result open.
    Inconclusive {
        from_s: f64,
        to_s: f64,
    },
    /// A value read there is not a number: the robustness is NaN.
    Undefined,
}

impl Truth {
    /// Kleene's order: an open result lies between a violation and a success.
    fn rank(self) -> u8 {
        match self {
            Truth::Violated => 0,
            Truth::Inconclusive { .. } => 1,
            Truth::Holds => 2,
            Truth::Undefined => 3,
        }
    }
}

/// A robustness value, the time of the sample that decides it and whether it holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Robustness {
    /// NaN where [`Truth::Undefined`]; for [`Truth::Inconclusive`], the value over the
    /// samples recorded (infinite when none fell in the window).
    pub value: f64,
    pub at_s: f64,
    pub truth: Truth,
}

/// The recorded signals a formula reads: sample times and one column per signal.
pub struct Signals<'a> {
    pub times: &'a [f64],
    /// `(name, values)`, each as long as `times`.
    pub columns: Vec<(&'a str, Vec<f64>)>,
    /// When the run ended (its last sample, possibly after the last of `times`): a window
    /// past it is inconclusive. `None` judges such a window over the samples recorded, for
    /// a scenario that accepts a run ending early.
    pub ended_s: Option<f64>,
}

impl Signals<'_> {
    fn column(&self, name: &str) -> &[f64] {
        &self
            .columns
            .iter()
            .find(|(n, _)| *n == name)
            .expect("every signal of the formula was checked to be recorded")
            .1
    }
}

impl Robustness {
    fn undefined(&self) -> bool {
        self.truth == Truth::Undefined
    }
}

/// Whether `x` decides a minimum (`minimum`) or maximum over `y` or ties with it. An
/// undefined value decides both, the earlier of two first (`y`, already in the window).
fn decides(x: &Robustness, y: &Robustness, minimum: bool) -> bool {
    match (x.undefined(), y.undefined()) {
        (_, true) => false,
        (true, false) => true,
        (false, false) => {
            let order = x
                .truth
                .rank()
                .cmp(&y.truth.rank())
                .then(x.value.total_cmp(&y.value));
            if minimum {
                order.is_le()
            } else {
                order.is_ge()
            }
        }
    }
}

/// The robustness of `formula` at every sample (as a signal); the requirement's own is the
/// first sample's.
pub fn robustness(formula: &Formula, s: &Signals) -> Vec<Robustness> {
    let n = s.times.len();
    match formula {
        Formula::Compare(a, op, b) => {
            let (a, b) = (value(a, s), value(b, s));
            (0..n)
                .map(|k| {
                    let (a, b) = (a[k], b[k]);
                    let (value, holds) = match op {
                        Comparison::Less => (b - a, a < b),
                        Comparison::LessEqual => (b - a, a <= b),
                        Comparison::Greater => (a - b, a > b),
                        Comparison::GreaterEqual => (a - b, a >= b),
                    };
                    let truth = if value.is_nan() {
                        Truth::Undefined
                    } else if holds {
                        Truth::Holds
                    } else {
                        Truth::Violated
                    };
                    Robustness {
                        value,
                        at_s: s.times[k],
                        truth,
                    }
                })
                .collect()
        }
        Formula::Not(f) => robustness(f, s)
            .into_iter()
            .map(|r| Robustness {
                value: -r.value,
                truth: match r.truth {
                    Truth::Holds => Truth::Violated,
                    Truth::Violated => Truth::Holds,
                    open => open,
                },
                ..r
            })
            .collect(),
        Formula::And(a, b) => pairwise(robustness(a, s), robustness(b, s), true),
        Formula::Or(a, b) => pairwise(robustness(a, s), robustness(b, s), false),
        Formula::Always(window, f) => windowed(&robustness(f, s), s, *window, true),
        Formula::Eventually(window, f) => windowed(&robustness(f, s), s, *window, false),
        Formula::Until(a, window, b) => until(&robustness(a, s), &robustness(b, s), s, *window),
    }
}

fn pairwise(a: Vec<Robustness>, b: Vec<Robustness>, minimum: bool) -> Vec<Robustness> {
    a.into_iter()
        .zip(b)
        .map(|(x, y)| if decides(&x, &y, minimum) { x } else { y })
        .collect()
}

fn value(e: &Expr, s: &Signals) -> Vec<f64> {
    match e {
        Expr::Number(x) => vec![*x; s.times.len()],
        // A recorded infinity is an overflow, not a value to compare: NaN, as undefined.
        Expr::Signal(name) => s
            .column(name)
            .iter()
            .map(|&x| if x.is_finite() { x } else { f64::NAN })
            .collect(),
        Expr::Neg(e) => value(e, s).into_iter().map(|x| -x).collect(),
        Expr::Abs(e) => value(e, s).into_iter().map(f64::abs).collect(),
        Expr::Sqrt(e) => value(e, s).into_iter().map(f64::sqrt).collect(),
        // `hypot` is infinite when either side is, even a NaN one.
        Expr::Hypot(a, b) => value(a, s)
            .into_iter()
            .zip(value(b, s))
            .map(|(x, y)| {
                if x.is_nan() || y.is_nan() {
                    f64::NAN
                } else {
                    // libm's, as in the models: a verdict's robustness has the same bits on
                    // every platform.
                    libm::hypot(x, y)
                }
            })
            .collect(),
        Expr::Binary(a, op, b) => value(a, s)
            .into_iter()
            .zip(value(b, s))
            .map(|(x, y)| match op {
                Op::Add => x + y,
                Op::Sub => x - y,
                Op::Mul => x * y,
                Op::Div => x / y,
            })
            .collect(),
    }
}

/// Whether the window `[t + from, t + to]` ends after the run did (by more than rounding).
fn uncovered(s: &Signals, t: f64, w: Interval) -> Option<Truth> {
    let ended = s.ended_s?;
    let end = t + w.to_s;
    (end > ended + 1e-9 * (1.0 + ended.abs())).then_some(Truth::Inconclusive {
        from_s: t + w.from_s,
        to_s: end,
    })
}

/// The samples `j` with `times[j]` in `[times[k] + from, times[k] + to]`, for every `k`, as
/// a sliding window (times increase): the minimum (`always`) or maximum (`eventually`) of
/// `r` over it, by a monotone queue. An empty window has +inf (`always`) or -inf
/// (`eventually`). A window the run ended before is inconclusive unless its samples decide
/// it: a violation for `always`, a success for `eventually`.
fn windowed(r: &[Robustness], s: &Signals, w: Interval, minimum: bool) -> Vec<Robustness> {
    let times = s.times;
    let mut out = Vec::with_capacity(r.len());
    let mut queue = std::collections::VecDeque::<usize>::new();
    let (mut start, mut end) = (0, 0);
    for &t in times {
        while end < times.len() && times[end] <= t + w.to_s {
            while queue
                .back()
                .is_some_and(|&j| decides(&r[end], &r[j], minimum))
            {
                queue.pop_back();
            }
            queue.push_back(end);
            end += 1;
        }
        while start < end && times[start] < t + w.from_s {
            start += 1;
        }
        while queue.front().is_some_and(|&j| j < start) {
            queue.pop_front();
        }
        let mut here = match queue.front() {
            Some(&j) => r[j],
            None if minimum => Robustness {
                value: f64::INFINITY,
                at_s: t,
                truth: Truth::Holds,
            },
            None => Robustness {
                value: f64::NEG_INFINITY,
                at_s: t,
                truth: Truth::Violated,
            },
        };
        let open = if minimum {
            Truth::Holds
        } else {
            Truth::Violated
        };
        if here.truth == open {
            if let Some(inconclusive) = uncovered(s, t, w) {
                here.truth = inconclusive;
            }
        }
        out.push(here);
    }
    out
}

/// `a until [from, to] b` at every sample (a direct scan: windows of until are short in
/// practice, and the cost is bounded by samples x window samples).
fn until(a: &[Robustness], b: &[Robustness], s: &Signals, w: Interval) -> Vec<Robustness> {
    let times = s.times;
    (0..times.len())
        .map(|k| {
            let mut best = Robustness {
                value: f64::NEG_INFINITY,
                at_s: times[k],
                truth: Truth::Violated,
            };
            // The weakest `a` so far, from k on.
            let mut held = Robustness {
                value: f64::INFINITY,
                at_s: times[k],
                truth: Truth::Holds,
            };
            for j in k..times.len() {
                if times[j] > times[k] + w.to_s {
                    break;
                }
                if times[j] >= times[k] + w.from_s {
                    let here = if decides(&b[j], &held, true) {
                        b[j]
                    } else {
                        held
                    };
                    if !best.undefined() && !decides(&best, &here, false) {
                        best = here;
                    }
                }
                if !held.undefined() && !decides(&held, &a[j], true) {
                    held = a[j];
                }
            }
            // Past the end of the run `b` may still come, unless `a` failed already.
            if best.truth == Truth::Violated && held.truth != Truth::Violated {
                if let Some(inconclusive) = uncovered(s, times[k], w) {
                    best.truth = inconclusive;
                }
            }
            best
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::formula::parse;
    use super::*;

    /// `p.x` over `times`, judging a window cut short over its recorded samples.
    fn signals<'a>(times: &'a [f64], x: &[f64]) -> Signals<'a> {
        Signals {
            times,
            columns: vec![("p.x", x.to_vec())],
            ended_s: None,
        }
    }

    fn at_start(text: &str, s: &Signals) -> Robustness {
        robustness(&parse(text).unwrap(), s)[0]
    }

    #[test]
    fn always_and_eventually_take_the_extremes_of_their_window_with_its_time() {
        let times: Vec<f64> = (0..=10).map(f64::from).collect();
        // x = 10 - t: falls from 10 to 0.
        let x: Vec<f64> = times.iter().map(|t| 10.0 - t).collect();
        let s = signals(&times, &x);
        // Over [2, 5]: the weakest is t = 5 (x = 5): 5 - 3 = 2.
        assert_eq!(
            at_start("always [2, 5] p.x > 3", &s),
            Robustness {
                value: 2.0,
                at_s: 5.0,
                truth: Truth::Holds
            }
        );
        // Violated over [0, 9]: x = 1 at t = 9 is 2 below 3.
        assert_eq!(
            at_start("always [0, 9] p.x > 3", &s),
            Robustness {
                value: -2.0,
                at_s: 9.0,
                truth: Truth::Violated
            }
        );
        // Eventually x < 1 within [0, 10]: at t = 10 x = 0, 1 to spare.
        assert_eq!(
            at_start("eventually [0, 10] p.x < 1", &s),
            Robustness {
                value: 1.0,
                at_s: 10.0,
                truth: Truth::Holds
            }
        );
        assert_eq!(at_start("eventually [0, 3] p.x < 1", &s).value, -6.0);
        // not, and, or.
        assert_eq!(at_start("not p.x > 3", &s).value, -7.0);
        assert_eq!(at_start("p.x > 3 and p.x < 12", &s).value, 2.0);
        assert_eq!(at_start("p.x > 30 or p.x < 12", &s).value, 2.0);
        // hypot and sqrt: hypot(x, 0) = |x|; sqrt(x * x) = x at t = 0 (x = 10).
        assert_eq!(at_start("hypot(p.x, 0) < 11", &s).value, 1.0);
        assert_eq!(at_start("sqrt(p.x * p.x) > 4", &s).value, 6.0);
        // A window beyond the run judged over its (no) samples: always holds vacuously,
        // eventually fails.
        assert_eq!(
            at_start("always [20, 30] p.x > 100", &s).value,
            f64::INFINITY
        );
        assert_eq!(
            at_start("eventually [20, 30] p.x > -100", &s).value,
            f64::NEG_INFINITY
        );
    }

    #[test]
    fn the_sliding_window_equals_a_direct_scan_at_every_sample() {
        let times: Vec<f64> = (0..200).map(|k| 0.1 * f64::from(k)).collect();
        let x: Vec<f64> = times
            .iter()
            .map(|t| libm::sin(1.7 * t) + 0.3 * libm::cos(5.1 * t))
            .collect();
        let s = signals(&times, &x);
        for (text, minimum) in [
            ("always [0.35, 2.2] p.x > 0", true),
            ("eventually [1, 1.5] p.x > 0", false),
        ] {
            let f = parse(text).unwrap();
            let (Formula::Always(w, _) | Formula::Eventually(w, _)) = &f else {
                unreachable!()
            };
            let w = *w;
            let got = robustness(&f, &s);
            for (k, r) in got.iter().enumerate() {
                let window: Vec<f64> = (0..times.len())
                    .filter(|&j| times[j] >= times[k] + w.from_s && times[j] <= times[k] + w.to_s)
                    .map(|j| x[j])
                    .collect();
                let expected = if window.is_empty() {
                    if minimum {
                        f64::INFINITY
                    } else {
                        f64::NEG_INFINITY
                    }
                } else if minimum {
                    window.iter().copied().fold(f64::INFINITY, f64::min)
                } else {
                    window.iter().copied().fold(f64::NEG_INFINITY, f64::max)
                };
                assert_eq!(r.value, expected, "{text} at sample {k}");
            }
        }
    }

    #[test]
    fn until_needs_the_first_to_hold_until_the_second_does() {
        let times: Vec<f64> = (0..=10).map(f64::from).collect();
        let x: Vec<f64> = times.iter().map(|t| 10.0 - t).collect();
        let s = signals(&times, &x);
        // x > 4 holds until t = 5, where x < 6 first holds (x = 5: 1 to spare; x > 4 there
        // by 1): robustness 1.
        assert_eq!(at_start("p.x > 4 until [0, 10] p.x < 6", &s).value, 1.0);
        // x > 8 fails at t = 2 (by 0 at t = 2 already: 8 - 8), before x < 6 ever holds.
        assert!(at_start("p.x > 8 until [0, 10] p.x < 6", &s).value <= 0.0);
    }
}
