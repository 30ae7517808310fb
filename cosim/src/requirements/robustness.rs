//! Quantitative robustness of a formula over a recorded run (discrete-time signal temporal
//! logic): how far the signals are from violating it, in the compared signals' unit;
//! positive holds, negative is violated. A comparison `a < b` at a sample has robustness
//! `b - a`; `not` negates; `and`/`or` take the minimum/maximum; `always`/`eventually` the
//! minimum/maximum over the samples of their window; `a until [s, e] b` the best over the
//! window of `min(b at t', a at every sample up to t')`. Each value carries the time of the
//! sample that decides it.
use super::formula::{Comparison, Expr, Formula, Interval, Op};

/// A robustness value and the time of the sample that decides it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Robustness {
    pub value: f64,
    pub at_s: f64,
}

/// The recorded signals a formula reads: sample times and one column per signal.
pub struct Signals<'a> {
    pub times: &'a [f64],
    /// `(name, values)`, each as long as `times`.
    pub columns: Vec<(&'a str, Vec<f64>)>,
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

/// The robustness of `formula` at every sample (as a signal); the requirement's own is the
/// first sample's.
pub fn robustness(formula: &Formula, s: &Signals) -> Vec<Robustness> {
    let n = s.times.len();
    match formula {
        Formula::Compare(a, op, b) => {
            let (a, b) = (value(a, s), value(b, s));
            (0..n)
                .map(|k| Robustness {
                    value: match op {
                        Comparison::Less | Comparison::LessEqual => b[k] - a[k],
                        Comparison::Greater | Comparison::GreaterEqual => a[k] - b[k],
                    },
                    at_s: s.times[k],
                })
                .collect()
        }
        Formula::Not(f) => robustness(f, s)
            .into_iter()
            .map(|r| Robustness {
                value: -r.value,
                ..r
            })
            .collect(),
        Formula::And(a, b) => pairwise(robustness(a, s), robustness(b, s), |x, y| x <= y),
        Formula::Or(a, b) => pairwise(robustness(a, s), robustness(b, s), |x, y| x >= y),
        Formula::Always(window, f) => windowed(&robustness(f, s), s.times, *window, true),
        Formula::Eventually(window, f) => windowed(&robustness(f, s), s.times, *window, false),
        Formula::Until(a, window, b) => {
            until(&robustness(a, s), &robustness(b, s), s.times, *window)
        }
    }
}

fn pairwise(
    a: Vec<Robustness>,
    b: Vec<Robustness>,
    keep_first: impl Fn(f64, f64) -> bool,
) -> Vec<Robustness> {
    a.into_iter()
        .zip(b)
        .map(|(x, y)| if keep_first(x.value, y.value) { x } else { y })
        .collect()
}

fn value(e: &Expr, s: &Signals) -> Vec<f64> {
    match e {
        Expr::Number(x) => vec![*x; s.times.len()],
        Expr::Signal(name) => s.column(name).to_vec(),
        Expr::Neg(e) => value(e, s).into_iter().map(|x| -x).collect(),
        Expr::Abs(e) => value(e, s).into_iter().map(f64::abs).collect(),
        Expr::Sqrt(e) => value(e, s).into_iter().map(f64::sqrt).collect(),
        Expr::Hypot(a, b) => value(a, s)
            .into_iter()
            .zip(value(b, s))
            .map(|(x, y)| x.hypot(y))
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

/// The samples `j` with `times[j]` in `[times[k] + from, times[k] + to]`, for every `k`, as
/// a sliding window (times increase): the minimum (`always`) or maximum (`eventually`) of
/// `r` over it, by a monotone queue. A window past the last sample is empty: `always` holds
/// there (+inf), `eventually` does not (-inf); the report says how much of the window the
/// run covered.
fn windowed(r: &[Robustness], times: &[f64], w: Interval, minimum: bool) -> Vec<Robustness> {
    let better = |x: f64, y: f64| if minimum { x <= y } else { x >= y };
    let mut out = Vec::with_capacity(r.len());
    let mut queue = std::collections::VecDeque::<usize>::new();
    let (mut start, mut end) = (0, 0);
    for &t in times {
        while end < times.len() && times[end] <= t + w.to_s {
            while queue
                .back()
                .is_some_and(|&j| better(r[end].value, r[j].value))
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
        out.push(match queue.front() {
            Some(&j) => r[j],
            None => Robustness {
                value: if minimum {
                    f64::INFINITY
                } else {
                    f64::NEG_INFINITY
                },
                at_s: t,
            },
        });
    }
    out
}

/// `a until [from, to] b` at every sample (a direct scan: windows of until are short in
/// practice, and the cost is bounded by samples x window samples).
fn until(a: &[Robustness], b: &[Robustness], times: &[f64], w: Interval) -> Vec<Robustness> {
    (0..times.len())
        .map(|k| {
            let mut best = Robustness {
                value: f64::NEG_INFINITY,
                at_s: times[k],
            };
            // The weakest `a` so far, from k on.
            let mut held = Robustness {
                value: f64::INFINITY,
                at_s: times[k],
            };
            for j in k..times.len() {
                if times[j] > times[k] + w.to_s {
                    break;
                }
                if times[j] >= times[k] + w.from_s {
                    let here = if b[j].value <= held.value { b[j] } else { held };
                    if here.value > best.value {
                        best = here;
                    }
                }
                if a[j].value < held.value {
                    held = a[j];
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

    fn signals<'a>(times: &'a [f64], x: &[f64]) -> Signals<'a> {
        Signals {
            times,
            columns: vec![("p.x", x.to_vec())],
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
                at_s: 5.0
            }
        );
        // Violated over [0, 9]: x = 1 at t = 9 is 2 below 3.
        assert_eq!(
            at_start("always [0, 9] p.x > 3", &s),
            Robustness {
                value: -2.0,
                at_s: 9.0
            }
        );
        // Eventually x < 1 within [0, 10]: at t = 10 x = 0, 1 to spare.
        assert_eq!(
            at_start("eventually [0, 10] p.x < 1", &s),
            Robustness {
                value: 1.0,
                at_s: 10.0
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
        // A window beyond the run: always holds vacuously, eventually fails.
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
            .map(|t| (1.7 * t).sin() + 0.3 * (5.1 * t).cos())
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
