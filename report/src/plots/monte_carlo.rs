//! The paper's Monte Carlo figure (its Fig. 6), one panel per metric that isolates the
//! controller's effect, against phi_cmd: per law, the median (line, law's pattern and
//! marker), the middle half of the runs (25th to 75th percentile, shaded in the law's
//! colour: three laws' full ranges overlap so much that their shades mix to grey), the range
//! of all runs (short dashes at the minimum and maximum) and, where the runs support it (45
//! or more), the 90 %-confidence upper bound of the 95th percentile (thin line): no tail
//! percentile is drawn, nor named in the legend, that the run count cannot support. One
//! legend above the panels names each law's median, band, range and (when drawn) bound, laws
//! in the order of `summary.csv`; no line crosses a phi_cmd where a law has no value. The error after the final hover is
//! not shown: the hover removes what the controller did.
use super::style::{self, tick, Key, Legend, Marker};
use campaign::manifest::Row;
use campaign::stats::{percentile_of_sorted, quantile_upper_bound, runs_for_quantile_bound};
use campaign::summary_csv::CONFIDENCE;
use lander::laws::Law;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

struct Panel {
    title: &'static str,
    y_label: &'static str,
    value: fn(&Row) -> f64,
}

const PANELS: [Panel; 4] = [
    Panel {
        title: "largest horizontal deviation during the descent",
        y_label: "max horizontal deviation (m)",
        value: |r| r.metrics.max_horizontal_deviation_descent_m,
    },
    Panel {
        title: "lateral speed during the thrust-axis manoeuvre",
        y_label: "max horizontal speed (m/s)",
        value: |r| r.metrics.max_lateral_speed_manoeuvre_mps,
    },
    Panel {
        title: "thrust-axis pointing error, time integral",
        y_label: "integral of the pointing error (deg s)",
        value: |r| r.metrics.tilt_error_integral_rad_s.to_degrees(),
    },
    Panel {
        title: "position error at the end of the descent",
        y_label: "|r - target| (m)",
        value: |r| r.metrics.descent_end_position_error_m,
    },
];

/// One law at one phi_cmd: (phi, minimum, median, maximum, p95 upper bound or NaN, 25th
/// percentile, 75th percentile) of one metric.
type Point = [f64; 7];

/// Per law, at every phi_cmd of the campaign's grid (`grid`): its [`Point`], NaN values
/// left out; `None` where the law has no finite value at that phi_cmd (no line is drawn
/// across it).
fn bands(rows: &[Row], grid: &[f64], law: Law, value: fn(&Row) -> f64) -> Vec<Option<Point>> {
    grid.iter()
        .map(|&phi| {
            let mut v: Vec<f64> = rows
                .iter()
                .filter(|r| r.flight.law == law && r.flight.phi_cmd_deg == phi)
                .map(value)
                .filter(|x| x.is_finite())
                .collect();
            v.sort_by(f64::total_cmp);
            (!v.is_empty()).then(|| {
                [
                    phi,
                    v[0],
                    percentile_of_sorted(&v, 0.5),
                    v[v.len() - 1],
                    quantile_upper_bound(&v, 0.95, CONFIDENCE).unwrap_or(f64::NAN),
                    percentile_of_sorted(&v, 0.25),
                    percentile_of_sorted(&v, 0.75),
                ]
            })
        })
        .collect()
}

/// The runs of contiguous grid points where a law has values.
fn pieces(b: &[Option<Point>]) -> Vec<Vec<Point>> {
    b.split(Option::is_none)
        .filter(|run| !run.is_empty())
        .map(|run| run.iter().flatten().copied().collect())
        .collect()
}

/// The phi_cmd grid of `rows`, sorted.
fn grid(rows: &[Row]) -> Vec<f64> {
    let mut phis: Vec<f64> = rows.iter().map(|r| r.flight.phi_cmd_deg).collect();
    phis.sort_by(f64::total_cmp);
    phis.dedup();
    phis
}

/// The laws of `rows`, in the order of `summary.csv` and the report's tables.
fn laws(rows: &[Row]) -> Vec<Law> {
    let mut laws: Vec<Law> = Vec::new();
    for row in rows {
        if !laws.contains(&row.flight.law) {
            laws.push(row.flight.law);
        }
    }
    laws.sort();
    laws
}

/// Whether any point of `law` has the runs for the p95 upper bound.
fn has_p95_bound(rows: &[Row], law: Law) -> bool {
    let grid = grid(rows);
    PANELS.iter().any(|panel| {
        bands(rows, &grid, law, panel.value)
            .iter()
            .flatten()
            .any(|p| p[4].is_finite())
    })
}

/// The figure's legend, per law in the order of the tables: its median, its band and, only
/// where the runs support it, its p95 upper bound.
pub fn legend(rows: &[Row]) -> Legend {
    let mut out = Legend::new();
    for law in laws(rows) {
        let name = law.name();
        out.push((Key::Curve(law), format!("{name} median")));
        out.push((Key::Band(law), format!("{name} middle 50 % of runs")));
        out.push((Key::Range(law), format!("{name} range of all runs")));
        if has_p95_bound(rows, law) {
            out.push((Key::Thin(law), format!("{name} p95 upper bound (90 %)")));
        }
    }
    out
}

/// Writes `monte-carlo.png` into `dir`; failed flights (NaN metrics) are left out.
pub fn figure(rows: &[Row], dir: &Path, title: &str) -> anyhow::Result<PathBuf> {
    let path = dir.join("monte-carlo.png");
    draw(rows, &path, title)?;
    Ok(path)
}

fn draw(rows: &[Row], path: &Path, title: &str) -> anyhow::Result<()> {
    let root = super::canvas::bitmap(path, (1500, 1100));
    root.fill(&WHITE)?;
    let laws = laws(rows);
    let bound = laws.iter().any(|&l| has_p95_bound(rows, l));
    let needed = runs_for_quantile_bound(0.95, CONFIDENCE);
    let root = root.titled(
        &if bound {
            format!(
                "{title}: median, middle 50 % (shaded), range of all runs (dashed), p95 \
                 upper bound at 90 % confidence (thin)"
            )
        } else {
            format!(
                "{title}: median, middle 50 % (shaded), range of all runs (dashed; a p95 \
                 bound needs {needed} runs per point)"
            )
        },
        ("sans-serif", 22),
    )?;
    let root = style::legend_strip(&root, &legend(rows))?;
    let grid = grid(rows);
    for (area, panel) in root.split_evenly((2, 2)).iter().zip(&PANELS) {
        let per_law: Vec<(Law, Vec<Option<Point>>)> = laws
            .iter()
            .map(|&law| (law, bands(rows, &grid, law, panel.value)))
            .collect();
        let values = || {
            per_law
                .iter()
                .flat_map(|(_, b)| b.iter().flatten().flat_map(|p| p[1..].iter().copied()))
                .filter(|v| v.is_finite())
        };
        let lo = values().fold(f64::INFINITY, f64::min);
        let hi = values().fold(f64::NEG_INFINITY, f64::max);
        let x_lo = grid.iter().copied().fold(0.0, f64::min) - 8.0;
        let x_hi = grid.iter().copied().fold(0.0, f64::max) + 8.0;
        let mut builder = ChartBuilder::on(area);
        let chart = builder
            .caption(panel.title, ("sans-serif", 19))
            .margin(14)
            .x_label_area_size(46)
            .y_label_area_size(80);
        // Logarithmic when the values are positive and span more than a factor 30 (the laws
        // can differ by orders of magnitude), linear otherwise.
        if lo.is_finite() && lo > 0.0 && hi / lo > 30.0 {
            let mut chart =
                chart.build_cartesian_2d(x_lo..x_hi, (lo / 1.5..hi * 1.5).log_scale())?;
            mesh(&mut chart, panel)?;
            draw_laws(&mut chart, &per_law)?;
        } else {
            let (lo, hi) = if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) };
            let pad = 0.08 * (hi - lo).max(1e-9);
            let mut chart = chart.build_cartesian_2d(x_lo..x_hi, (lo - pad)..(hi + pad))?;
            mesh(&mut chart, panel)?;
            draw_laws(&mut chart, &per_law)?;
        }
    }
    root.present()?;
    Ok(())
}

type Chart<'a, Y> = ChartContext<'a, BitMapBackend<'a>, Cartesian2d<RangedCoordf64, Y>>;

fn mesh<Y>(chart: &mut Chart<'_, Y>, panel: &Panel) -> anyhow::Result<()>
where
    Y: Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_desc("commanded rotation about the thrust axis phi_cmd (deg)")
        .y_desc(panel.y_label)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .light_line_style(TRANSPARENT)
        .bold_line_style(BLACK.mix(0.12))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 16))
        .draw()?;
    Ok(())
}

/// Every law's middle-half band first (so no band covers a median), then each law's minimum
/// and maximum in short dashes, then the p95 bounds, then the medians.
fn draw_laws<Y>(
    chart: &mut Chart<'_, Y>,
    per_law: &[(Law, Vec<Option<Point>>)],
) -> anyhow::Result<()>
where
    Y: Ranged<ValueType = f64>,
{
    let order = style::draw_order(per_law.iter().map(|(law, _)| *law));
    let in_order = || {
        order
            .iter()
            .filter_map(|law| per_law.iter().find(|(l, _)| l == law))
    };
    for (law, b) in in_order() {
        let c = style::colour(*law);
        for piece in pieces(b) {
            // The middle half: a polygon along the 75th percentile out and back along the
            // 25th.
            let outline: Vec<(f64, f64)> = piece
                .iter()
                .map(|p| (p[0], p[6]))
                .chain(piece.iter().rev().map(|p| (p[0], p[5])))
                .collect();
            chart.draw_series(std::iter::once(Polygon::new(
                outline,
                c.mix(style::BAND_ALPHA).filled(),
            )))?;
        }
    }
    for (law, b) in in_order() {
        let c = style::colour(*law);
        let edge = c.mix(0.7).stroke_width(1);
        for piece in pieces(b) {
            for k in [1, 3] {
                let line: Vec<(f64, f64)> = piece.iter().map(|p| (p[0], p[k])).collect();
                chart.draw_series(DashedLineSeries::new(line, 3, 3, edge))?;
            }
            if piece.len() == 1 {
                let p = piece[0];
                chart.draw_series(LineSeries::new(
                    [(p[0], p[1]), (p[0], p[3])],
                    c.mix(0.7).stroke_width(6),
                ))?;
            }
        }
    }
    for (law, b) in in_order() {
        let c = style::colour(*law);
        for piece in b.split(|p| !p.is_some_and(|p| p[4].is_finite())) {
            let line: Vec<(f64, f64)> = piece.iter().flatten().map(|p| (p[0], p[4])).collect();
            chart.draw_series(LineSeries::new(line, c.mix(0.9).stroke_width(1)))?;
        }
    }
    for (law, b) in in_order() {
        draw_median(chart, *law, b)?;
    }
    Ok(())
}

fn draw_median<Y>(chart: &mut Chart<'_, Y>, law: Law, b: &[Option<Point>]) -> anyhow::Result<()>
where
    Y: Ranged<ValueType = f64>,
{
    let c = style::colour(law);
    let line = style::line(law, style::width(law));
    for piece in pieces(b) {
        let median: Vec<(f64, f64)> = piece.iter().map(|p| (p[0], p[2])).collect();
        match style::dashes(law) {
            None => chart.draw_series(LineSeries::new(median.iter().copied(), line))?,
            Some((dash, gap)) => chart.draw_series(DashedLineSeries::new(
                median.iter().copied(),
                dash,
                gap,
                line,
            ))?,
        };
        let show = move |on: bool| if on { c.filled() } else { TRANSPARENT.filled() };
        let line = move |on: bool| show(on).stroke_width(2);
        let marker = style::look(law).marker;
        chart.draw_series(median.iter().map(|&p| {
            EmptyElement::at(p)
                + Circle::new((0, 0), 5, show(marker == Marker::Circle))
                + TriangleMarker::new((0, 0), 7, show(marker == Marker::Triangle))
                + Rectangle::new([(-4, -4), (4, 4)], show(marker == Marker::Square))
                + Cross::new((0, 0), 5, line(marker == Marker::Cross))
        }))?;
    }
    Ok(())
}
