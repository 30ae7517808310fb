//! The signals a requirement reads, against time, from a run's result file: what a reviewer
//! looks at beside a VIOLATED line. One panel per signal (their units differ), the
//! requirement's time windows shaded.
use super::style::tick;
use cosim::master::Trajectory;
use cosim::requirements::formula::Formula;
use plotters::prelude::*;
use std::path::Path;

const WIDTH: u32 = 1000;
const PANEL_HEIGHT: u32 = 180;
/// More points than pixels only hide each other: a curve keeps every n-th point and each
/// bucket's extremes.
const MAX_POINTS: usize = 4000;

/// Draws the signals of `formula` from `trajectory` to `path` (PNG) under `title`, in
/// red when the requirement failed. `Err` names a signal the file does not hold.
pub fn figure(
    trajectory: &Trajectory,
    formula: &Formula,
    title: &str,
    failed: bool,
    path: &Path,
) -> anyhow::Result<()> {
    let signals = formula.signals();
    let columns: Vec<usize> = signals
        .iter()
        .map(|s| {
            trajectory
                .column_index(s)
                .ok_or_else(|| anyhow::anyhow!("the results hold no column {s}"))
        })
        .collect::<anyhow::Result<_>>()?;
    let height = 50 + PANEL_HEIGHT * signals.len().max(1) as u32;
    let root = super::canvas::bitmap(path, (WIDTH, height));
    root.fill(&WHITE)?;
    let colour = if failed {
        RGBColor(214, 39, 40)
    } else {
        RGBColor(31, 119, 180)
    };
    let root = root.titled(title, ("sans-serif", 22).into_font().color(&colour))?;
    let panels = root.split_evenly((signals.len().max(1), 1));
    let times = &trajectory.times;
    let (t0, t1) = match (times.first(), times.last()) {
        (Some(&a), Some(&b)) if b > a => (a, b),
        (Some(&a), _) => (a, a + 1.0),
        _ => (0.0, 1.0),
    };
    let spans = windows(formula);
    // The vertical scale is the windows' (what is judged), not a transient before them.
    let judged = |t: f64| spans.is_empty() || spans.iter().any(|&(a, b)| t >= a && t <= b);
    for ((panel, name), &column) in panels.iter().zip(&signals).zip(&columns) {
        let points = decimated(times, |k| trajectory.row(k)[column]);
        let finite = points
            .iter()
            .filter(|p| judged(p.0))
            .map(|p| p.1)
            .filter(|y| y.is_finite());
        let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| {
            (lo.min(y), hi.max(y))
        });
        let (lo, hi) = if lo.is_finite() && hi > lo {
            let pad = 0.05 * (hi - lo);
            (lo - pad, hi + pad)
        } else if lo.is_finite() {
            (lo - 1.0, lo + 1.0)
        } else {
            (-1.0, 1.0)
        };
        let mut chart = ChartBuilder::on(panel)
            .margin(8)
            .x_label_area_size(30)
            .y_label_area_size(70)
            .caption(*name, ("sans-serif", 16))
            .build_cartesian_2d(t0..t1, lo..hi)?;
        chart
            .configure_mesh()
            .x_desc("t (s)")
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .light_line_style(WHITE)
            .draw()?;
        for &window in &spans {
            let (a, b) = (window.0.max(t0), window.1.min(t1));
            if b > a {
                chart.draw_series(std::iter::once(Rectangle::new(
                    [(a, lo), (b, hi)],
                    RGBColor(255, 240, 200).filled(),
                )))?;
            }
        }
        let inside = |p: &&(f64, f64)| p.1 >= lo && p.1 <= hi;
        for segment in points.split(|p| !p.1.is_finite()) {
            // Points off the scale are left out, not drawn across the frame.
            for run in segment.split(|p| !inside(&p)) {
                chart.draw_series(LineSeries::new(run.iter().copied(), colour.stroke_width(2)))?;
            }
        }
    }
    root.present()?;
    Ok(())
}

/// The outermost time windows of the formula (`always [a, b]`, `eventually [a, b]`,
/// `until [a, b]`), which are times of the run: the spans a reader checks the curve in. A
/// window nested in another is relative to its instant and is not shaded.
fn windows(formula: &Formula) -> Vec<(f64, f64)> {
    match formula {
        Formula::Compare(..) => Vec::new(),
        Formula::Not(f) => windows(f),
        Formula::And(a, b) | Formula::Or(a, b) => {
            let mut out = windows(a);
            out.extend(windows(b));
            out
        }
        Formula::Always(w, _) | Formula::Eventually(w, _) | Formula::Until(_, w, _) => {
            vec![(w.from_s, w.to_s)]
        }
    }
}

fn decimated(times: &[f64], value: impl Fn(usize) -> f64) -> Vec<(f64, f64)> {
    let n = times.len();
    let stride = n.div_ceil(MAX_POINTS / 2).max(1);
    let mut out = Vec::with_capacity(n.min(MAX_POINTS + 2));
    let mut k = 0;
    while k < n {
        let end = (k + stride).min(n);
        if stride == 1 {
            out.push((times[k], value(k)));
        } else {
            // Each bucket's lowest and highest value, in time order, so peaks survive.
            let (mut lo, mut hi) = (k, k);
            for j in k..end {
                if value(j) < value(lo) {
                    lo = j;
                }
                if value(j) > value(hi) {
                    hi = j;
                }
            }
            let (first, second) = if lo <= hi { (lo, hi) } else { (hi, lo) };
            out.push((times[first], value(first)));
            if second != first {
                out.push((times[second], value(second)));
            }
        }
        k = end;
    }
    out
}
