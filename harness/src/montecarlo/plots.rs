//! The paper's Monte Carlo figure: terminal position error and maximum horizontal deviation
//! against phi_cmd, one colour per law, a point per flight, a thick line through the means and
//! a thin one through the medians (a few runs that go far off pull the mean away from the
//! typical run; the median shows the typical run, the points show the outliers).
//! Both axes of error are logarithmic: the laws differ by two orders of magnitude.
use super::manifest::Row;
use super::summary::{summarise, Moments, Statistic};
use crate::scenarios::Law;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

fn colour(law: Law) -> RGBColor {
    // The same colours as the `harness paper` figures.
    match law {
        Law::Coupled => RGBColor(214, 39, 40),
        Law::Decoupled => RGBColor(31, 119, 180),
        Law::Reduced => RGBColor(44, 160, 44),
    }
}

/// Points of one law drawn this far from the phi_cmd they belong to (deg), so the laws'
/// clouds sit side by side instead of on top of each other.
fn offset_deg(law: Law) -> f64 {
    match law {
        Law::Coupled => -2.0,
        Law::Decoupled => 0.0,
        Law::Reduced => 2.0,
    }
}

struct Panel {
    title: &'static str,
    y_label: &'static str,
    value: fn(&Row) -> f64,
    statistic: Statistic,
}

/// Writes `monte-carlo.png` into `dir`; failed flights (NaN metrics) are left out.
pub fn figure(rows: &[Row], dir: &Path, title: &str) -> anyhow::Result<PathBuf> {
    let path = dir.join("monte-carlo.png");
    let panels = [
        Panel {
            title: "position error at the end of the descent",
            y_label: "|r - target| at the end of the descent (m)",
            value: |r| r.metrics.descent_end_position_error_m,
            statistic: Statistic::DescentEndPositionError,
        },
        Panel {
            title: "maximum horizontal deviation over the flight",
            y_label: "max horizontal deviation (m)",
            value: |r| r.metrics.max_horizontal_deviation_m,
            statistic: Statistic::MaxHorizontalDeviation,
        },
    ];
    draw(rows, &path, title, &panels)?;
    Ok(path)
}

fn draw(rows: &[Row], path: &Path, title: &str, panels: &[Panel]) -> anyhow::Result<()> {
    let summary = summarise(rows);
    let mut laws: Vec<Law> = Vec::new();
    for row in rows {
        if !laws.contains(&row.flight.law) {
            laws.push(row.flight.law);
        }
    }
    laws.sort_by_key(|l| *l as i32);
    let root = BitMapBackend::new(path, (1400, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 24))?;
    for (area, panel) in root.split_evenly((1, 2)).iter().zip(panels) {
        let positive = |v: &f64| v.is_finite() && *v > 0.0;
        let values: Vec<f64> = rows.iter().map(panel.value).filter(positive).collect();
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(0.0, f64::max);
        let (lo, hi) = if lo.is_finite() {
            (lo / 2.0, hi * 2.0)
        } else {
            (1e-3, 1.0)
        };
        let phis = rows.iter().map(|r| r.flight.phi_cmd_deg);
        let x_lo = phis.clone().fold(f64::INFINITY, f64::min).min(0.0) - 10.0;
        let x_hi = phis.fold(f64::NEG_INFINITY, f64::max).max(0.0) + 10.0;
        let mut chart = ChartBuilder::on(area)
            .caption(panel.title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(80)
            .build_cartesian_2d(x_lo..x_hi, (lo..hi).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("phi_cmd (deg)")
            .y_desc(panel.y_label)
            .draw()?;
        for &law in &laws {
            let c = colour(law);
            let points = rows
                .iter()
                .filter(|r| r.flight.law == law)
                .map(|r| (r.flight.phi_cmd_deg + offset_deg(law), (panel.value)(r)))
                .filter(|(_, v)| positive(v));
            chart.draw_series(points.map(|p| Circle::new(p, 3, c.mix(0.45).filled())))?;
            let line = |pick: fn(&Moments) -> f64| -> Vec<(f64, f64)> {
                summary
                    .iter()
                    .filter(|s| s.law == law)
                    .map(|s| (s.phi_cmd_deg, pick(&s.get(panel.statistic))))
                    .filter(|(_, v)| positive(v))
                    .collect()
            };
            let mean = c.stroke_width(3);
            chart
                .draw_series(LineSeries::new(line(|m| m.mean), mean))?
                .label(format!("{} mean", law.name()))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], mean));
            let median = c.stroke_width(1);
            chart
                .draw_series(LineSeries::new(line(|m| m.median), median).point_size(4))?
                .label(format!("{} median", law.name()))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], median));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()?;
    }
    root.present()?;
    Ok(())
}
