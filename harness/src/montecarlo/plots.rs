//! The paper's Monte Carlo figure (its Fig. 6), one panel per metric that isolates the
//! controller's effect, against phi_cmd: per law, the median (line, law's pattern and
//! marker), the range of all runs (shaded, minimum to maximum) and, where the runs support it
//! (45 or more), the 90 %-confidence upper bound of the 95th percentile (thin line): no
//! percentile is drawn that the run count cannot support. The error after the final hover is
//! not shown: the hover removes what the controller did.
use super::manifest::Row;
use super::stats::{percentile_of_sorted, quantile_upper_bound};
use super::summary_csv::CONFIDENCE;
use crate::plots::style::{self, tick, DRAW_ORDER};
use crate::scenarios::Law;
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

/// Per law and phi_cmd: (phi, minimum, median, maximum, p95 upper bound or NaN) of one
/// metric, NaN values left out.
fn bands(rows: &[Row], law: Law, value: fn(&Row) -> f64) -> Vec<[f64; 5]> {
    let mut phis: Vec<f64> = rows
        .iter()
        .filter(|r| r.flight.law == law)
        .map(|r| r.flight.phi_cmd_deg)
        .collect();
    phis.sort_by(f64::total_cmp);
    phis.dedup();
    phis.into_iter()
        .filter_map(|phi| {
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
                ]
            })
        })
        .collect()
}

/// Writes `monte-carlo.png` into `dir`; failed flights (NaN metrics) are left out.
pub fn figure(rows: &[Row], dir: &Path, title: &str) -> anyhow::Result<PathBuf> {
    let path = dir.join("monte-carlo.png");
    draw(rows, &path, title)?;
    Ok(path)
}

fn draw(rows: &[Row], path: &Path, title: &str) -> anyhow::Result<()> {
    let root = BitMapBackend::new(path, (1500, 1060)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(
        &format!(
            "{title}: median, range of all runs, p95 upper bound at 90 % confidence (thin, \
             from 45 runs per point)"
        ),
        ("sans-serif", 22),
    )?;
    let laws: Vec<Law> = DRAW_ORDER
        .into_iter()
        .filter(|l| rows.iter().any(|r| r.flight.law == *l))
        .collect();
    for (area, panel) in root.split_evenly((2, 2)).iter().zip(&PANELS) {
        let per_law: Vec<(Law, Vec<[f64; 5]>)> = laws
            .iter()
            .map(|&law| (law, bands(rows, law, panel.value)))
            .collect();
        let values = || {
            per_law
                .iter()
                .flat_map(|(_, b)| b.iter().flat_map(|p| p[1..].iter().copied()))
        };
        let lo = values().fold(f64::INFINITY, f64::min);
        let hi = values().fold(f64::NEG_INFINITY, f64::max);
        let phis = || per_law.iter().flat_map(|(_, b)| b.iter().map(|p| p[0]));
        let x_lo = phis().fold(0.0, f64::min) - 8.0;
        let x_hi = phis().fold(0.0, f64::max) + 8.0;
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
            for (law, b) in &per_law {
                draw_law(&mut chart, *law, b)?;
            }
            legend(&mut chart)?;
        } else {
            let (lo, hi) = if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) };
            let pad = 0.08 * (hi - lo).max(1e-9);
            let mut chart = chart.build_cartesian_2d(x_lo..x_hi, (lo - pad)..(hi + pad))?;
            mesh(&mut chart, panel)?;
            for (law, b) in &per_law {
                draw_law(&mut chart, *law, b)?;
            }
            legend(&mut chart)?;
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

fn draw_law<Y>(chart: &mut Chart<'_, Y>, law: Law, b: &[[f64; 5]]) -> anyhow::Result<()>
where
    Y: Ranged<ValueType = f64>,
{
    let c = style::colour(law);
    // The range of all runs: a polygon along the maximum out and back along the minimum.
    let outline: Vec<(f64, f64)> = b
        .iter()
        .map(|p| (p[0], p[3]))
        .chain(b.iter().rev().map(|p| (p[0], p[1])))
        .collect();
    chart.draw_series(std::iter::once(Polygon::new(outline, c.mix(0.12).filled())))?;
    chart.draw_series(LineSeries::new(
        b.iter().filter(|p| p[4].is_finite()).map(|p| (p[0], p[4])),
        c.mix(0.8).stroke_width(1),
    ))?;
    let median: Vec<(f64, f64)> = b.iter().map(|p| (p[0], p[2])).collect();
    let line = style::line(law, style::width(law));
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
    chart
        .draw_series(median.iter().map(|&p| {
            EmptyElement::at(p)
                + Circle::new((0, 0), 5, show(law == Law::Coupled))
                + TriangleMarker::new((0, 0), 7, show(law == Law::Decoupled))
                + Rectangle::new([(-4, -4), (4, 4)], show(law == Law::Reduced))
        }))?
        .label(format!("{} median", law.name()))
        .legend(move |(x, y)| {
            EmptyElement::at((x, y))
                + PathElement::new(vec![(-8, 0), (16, 0)], line)
                + Circle::new((4, 0), 5, show(law == Law::Coupled))
                + TriangleMarker::new((4, 0), 7, show(law == Law::Decoupled))
                + Rectangle::new([(0, -4), (8, 4)], show(law == Law::Reduced))
        });
    Ok(())
}

fn legend<Y>(chart: &mut Chart<'_, Y>) -> anyhow::Result<()>
where
    Y: Ranged<ValueType = f64>,
{
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 15))
        .position(SeriesLabelPosition::UpperLeft)
        .draw()?;
    Ok(())
}
