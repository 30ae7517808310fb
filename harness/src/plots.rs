//! PNG figures mirroring the paper's: trajectory (ground track and altitude), position
//! components vs time, body rates vs time, one line per control law.
use crate::paper::Flight;
use crate::scenarios::Law;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

fn colour(law: Law) -> RGBColor {
    match law {
        Law::Coupled => RGBColor(214, 39, 40),
        Law::Decoupled => RGBColor(31, 119, 180),
        Law::Reduced => RGBColor(44, 160, 44),
    }
}

/// A named series: (x, y) points per law.
struct Panel<'a> {
    title: String,
    x_label: &'a str,
    y_label: &'a str,
    series: Vec<(Law, Vec<(f64, f64)>)>,
}

fn bounds(series: &[(Law, Vec<(f64, f64)>)]) -> (std::ops::Range<f64>, std::ops::Range<f64>) {
    let mut x = (f64::INFINITY, f64::NEG_INFINITY);
    let mut y = (f64::INFINITY, f64::NEG_INFINITY);
    for (_, points) in series {
        for &(a, b) in points
            .iter()
            .filter(|(a, b)| a.is_finite() && b.is_finite())
        {
            x = (x.0.min(a), x.1.max(a));
            y = (y.0.min(b), y.1.max(b));
        }
    }
    let pad = |(lo, hi): (f64, f64)| {
        if !lo.is_finite() {
            return 0.0..1.0;
        }
        let span = (hi - lo).max(1e-6);
        (lo - 0.05 * span)..(hi + 0.05 * span)
    };
    (pad(x), pad(y))
}

fn draw_panels(
    path: &Path,
    title: &str,
    panels: &[Panel<'_>],
    layout: (usize, usize),
) -> anyhow::Result<()> {
    let root = BitMapBackend::new(path, (1200, 420 * layout.0 as u32)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 26))?;
    for (area, panel) in root.split_evenly(layout).iter().zip(panels) {
        let (xr, yr) = bounds(&panel.series);
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(xr, yr)?;
        chart
            .configure_mesh()
            .x_desc(panel.x_label)
            .y_desc(panel.y_label)
            .light_line_style(WHITE.mix(0.0))
            .draw()?;
        for (law, points) in &panel.series {
            let style = colour(*law).stroke_width(2);
            chart
                .draw_series(LineSeries::new(points.iter().copied(), style))?
                .label(law.name())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()?;
    }
    root.present()?;
    Ok(())
}

fn column(flight: &Flight, name: &str) -> anyhow::Result<Vec<f64>> {
    flight
        .trajectory
        .column(name)
        .ok_or_else(|| anyhow::anyhow!("no column {name} to plot"))
}

fn time_panel<'a>(
    flights: &[Flight],
    name: &str,
    title: &str,
    y_label: &'a str,
    scale: f64,
) -> anyhow::Result<Panel<'a>> {
    let mut series = Vec::new();
    for f in flights {
        let values = column(f, name)?;
        series.push((
            f.law,
            f.trajectory
                .times
                .iter()
                .zip(values)
                .map(|(&t, v)| (t, v * scale))
                .collect(),
        ));
    }
    Ok(Panel {
        title: title.to_owned(),
        x_label: "time (s)",
        y_label,
        series,
    })
}

/// Writes the three figures for `flights` into `dir`; returns their paths.
pub fn paper_figures(flights: &[Flight], dir: &Path, name: &str) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut written = Vec::new();

    let mut track = Vec::new();
    let mut profile = Vec::new();
    for f in flights {
        let north = column(f, "plant.r_nue[1]")?;
        let up = column(f, "plant.r_nue[2]")?;
        let east = column(f, "plant.r_nue[3]")?;
        track.push((
            f.law,
            east.iter().zip(&north).map(|(&e, &n)| (e, n)).collect(),
        ));
        profile.push((
            f.law,
            north
                .iter()
                .zip(&east)
                .zip(&up)
                .map(|((&n, &e), &u)| (n.hypot(e), u))
                .collect(),
        ));
    }
    let path = dir.join(format!("{name}-trajectory.png"));
    draw_panels(
        &path,
        &format!("{name}: descent trajectory"),
        &[
            Panel {
                title: "ground track".into(),
                x_label: "East (m)",
                y_label: "North (m)",
                series: track,
            },
            Panel {
                title: "altitude vs horizontal deviation".into(),
                x_label: "horizontal distance from target vertical (m)",
                y_label: "altitude (m)",
                series: profile,
            },
        ],
        (1, 2),
    )?;
    written.push(path);

    let path = dir.join(format!("{name}-position.png"));
    let panels = [
        time_panel(flights, "plant.r_nue[1]", "North", "m", 1.0)?,
        time_panel(flights, "plant.r_nue[2]", "Up (altitude)", "m", 1.0)?,
        time_panel(flights, "plant.r_nue[3]", "East", "m", 1.0)?,
    ];
    draw_panels(&path, &format!("{name}: position (NUE)"), &panels, (3, 1))?;
    written.push(path);

    let path = dir.join(format!("{name}-body-rates.png"));
    let panels = [
        time_panel(
            flights,
            "plant.omega_body[1]",
            "yaw rate (body x)",
            "deg/s",
            1f64.to_degrees(),
        )?,
        time_panel(
            flights,
            "plant.omega_body[2]",
            "roll rate (body y, thrust axis)",
            "deg/s",
            1f64.to_degrees(),
        )?,
        time_panel(
            flights,
            "plant.omega_body[3]",
            "pitch rate (body z)",
            "deg/s",
            1f64.to_degrees(),
        )?,
    ];
    draw_panels(
        &path,
        &format!("{name}: body angular rates"),
        &panels,
        (3, 1),
    )?;
    written.push(path);
    Ok(written)
}
