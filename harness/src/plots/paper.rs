//! The paper's figures for one scenario flown with each law: Fig. 3 the 3-D trajectories
//! (with the ground track at equal scales and the altitude profile), Fig. 4 the position
//! components against time, Fig. 5 the body rates against time.
use super::style::{self, draw_law_curve, tick, DRAW_ORDER};
use crate::paper::Flight;
use crate::scenarios::Law;
use plotters::prelude::*;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// A panel: each law's (x, y) points, with its axis quantities and units.
struct Panel<'a> {
    title: String,
    x_label: &'a str,
    y_label: &'a str,
    series: Vec<(Law, Vec<(f64, f64)>)>,
    /// Same metres per pixel on both axes (a ground track).
    equal_scales: bool,
}

fn extent(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

fn padded((lo, hi): (f64, f64)) -> Range<f64> {
    if !lo.is_finite() {
        return 0.0..1.0;
    }
    let span = (hi - lo).max(1e-6);
    (lo - 0.05 * span)..(hi + 0.05 * span)
}

/// Widens the shorter range so that both axes have the same scale on a plot area of
/// `width` x `height` pixels.
fn equalise(x: Range<f64>, y: Range<f64>, width: f64, height: f64) -> (Range<f64>, Range<f64>) {
    let per_px = ((x.end - x.start) / width).max((y.end - y.start) / height);
    let around = |r: Range<f64>, px: f64| {
        let mid = 0.5 * (r.start + r.end);
        (mid - 0.5 * per_px * px)..(mid + 0.5 * per_px * px)
    };
    (around(x, width), around(y, height))
}

const MARGIN: u32 = 14;
const X_LABELS: u32 = 48;
const Y_LABELS: u32 = 80;
const CAPTION: u32 = 20;

fn draw_panels(
    path: &Path,
    title: &str,
    panels: &[Panel<'_>],
    layout: (usize, usize),
    size: (u32, u32),
) -> anyhow::Result<()> {
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 26))?;
    for (area, panel) in root.split_evenly(layout).iter().zip(panels) {
        let points = || panel.series.iter().flat_map(|(_, p)| p.iter());
        let mut x = padded(extent(points().map(|p| p.0)));
        let mut y = padded(extent(points().map(|p| p.1)));
        if panel.equal_scales {
            // The plot area: the panel less margins, label areas and the caption (its text
            // height plus plotters' spacing below it).
            let (w, h) = area.dim_in_pixel();
            let width = f64::from(w - 2 * MARGIN - Y_LABELS);
            let height = f64::from(h - 2 * MARGIN - X_LABELS - CAPTION - 10);
            (x, y) = equalise(x, y, width, height);
        }
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.title, ("sans-serif", CAPTION))
            .margin(MARGIN)
            .x_label_area_size(X_LABELS)
            .y_label_area_size(Y_LABELS)
            .build_cartesian_2d(x, y)?;
        chart
            .configure_mesh()
            .x_desc(panel.x_label)
            .y_desc(panel.y_label)
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .light_line_style(TRANSPARENT)
            .bold_line_style(BLACK.mix(0.12))
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 16))
            .draw()?;
        for law in DRAW_ORDER {
            if let Some((_, points)) = panel.series.iter().find(|(l, _)| *l == law) {
                draw_law_curve(&mut chart, law, points, law.name())?;
            }
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 15))
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
        x_label: "time t (s)",
        y_label,
        series,
        equal_scales: false,
    })
}

/// North, Up, East of each flight.
fn positions(flights: &[Flight]) -> anyhow::Result<Vec<(Law, Vec<[f64; 3]>)>> {
    flights
        .iter()
        .map(|f| {
            let n = column(f, "plant.r_nue[1]")?;
            let u = column(f, "plant.r_nue[2]")?;
            let e = column(f, "plant.r_nue[3]")?;
            Ok((f.law, (0..n.len()).map(|k| [n[k], u[k], e[k]]).collect()))
        })
        .collect()
}

/// Fig. 3: the trajectories in 3-D (East, Up, North), every axis named with its unit.
fn trajectory_3d(path: &Path, title: &str, tracks: &[(Law, Vec<[f64; 3]>)]) -> anyhow::Result<()> {
    let all = || tracks.iter().flat_map(|(_, p)| p.iter());
    let n = padded(extent(all().map(|p| p[0])));
    let u = padded(extent(all().map(|p| p[1])));
    let e = padded(extent(all().map(|p| p[2])));
    let root = BitMapBackend::new(path, (1100, 900)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 26))?;
    let mut chart =
        ChartBuilder::on(&root)
            .margin(20)
            .build_cartesian_3d(e.clone(), u.clone(), n.clone())?;
    chart.with_projection(|mut p| {
        p.pitch = 0.35;
        p.yaw = 0.7;
        p.scale = 0.85;
        p.into_matrix()
    });
    chart
        .configure_axes()
        .x_formatter(&tick)
        .y_formatter(&tick)
        .z_formatter(&tick)
        .label_style(("sans-serif", 15))
        .light_grid_style(TRANSPARENT)
        .bold_grid_style(BLACK.mix(0.12))
        .max_light_lines(0)
        .draw()?;
    // Each axis's name at the middle of the edge that carries its tick labels (the East
    // ticks run along North = max, the North ticks along East = max, the altitude ticks up
    // the corner East = min, North = max).
    let label = ("sans-serif", 18).into_font().color(&BLACK);
    let mid = |r: &Range<f64>| 0.5 * (r.start + r.end);
    let outside = |r: &Range<f64>| r.end + 0.3 * (r.end - r.start);
    for (text, at) in [
        ("East (m)", (mid(&e), u.start, outside(&n))),
        (
            "altitude Up (m)",
            (e.start, u.end + 0.06 * (u.end - u.start), n.end),
        ),
        ("North (m)", (outside(&e), u.start, mid(&n))),
    ] {
        chart.draw_series(std::iter::once(Text::new(text, at, label.clone())))?;
    }
    for law in DRAW_ORDER {
        let Some((_, points)) = tracks.iter().find(|(l, _)| *l == law) else {
            continue;
        };
        let style = style::line(law, 2);
        let points = style::thin(points);
        let line = points.iter().map(|p| (p[2], p[1], p[0]));
        chart
            .draw_series(LineSeries::new(line, style))?
            .label(law.name())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
        // Ground shadow: where each law flew over the ground, in a light tint.
        let shadow = style::colour(law).mix(0.35).filled().stroke_width(1);
        chart.draw_series(LineSeries::new(
            points.iter().map(|p| (p[2], u.start, p[0])),
            shadow,
        ))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 16))
        .position(SeriesLabelPosition::UpperRight)
        .draw()?;
    root.present()?;
    Ok(())
}

/// Writes the figures for `flights` into `dir`; returns their paths.
pub fn paper_figures(flights: &[Flight], dir: &Path, name: &str) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut written = Vec::new();
    let tracks = positions(flights)?;

    let path = dir.join(format!("{name}-trajectory-3d.png"));
    trajectory_3d(
        &path,
        &format!("{name}: 3-D trajectories (Fig. 3)"),
        &tracks,
    )?;
    written.push(path);

    let track = tracks
        .iter()
        .map(|(law, p)| (*law, p.iter().map(|r| (r[2], r[0])).collect()))
        .collect();
    let profile = tracks
        .iter()
        .map(|(law, p)| (*law, p.iter().map(|r| (r[0].hypot(r[2]), r[1])).collect()))
        .collect();
    let path = dir.join(format!("{name}-trajectory.png"));
    draw_panels(
        &path,
        &format!("{name}: ground track and altitude profile"),
        &[
            Panel {
                title: "ground track (equal scales)".into(),
                x_label: "East (m)",
                y_label: "North (m)",
                series: track,
                equal_scales: true,
            },
            Panel {
                title: "altitude against horizontal distance".into(),
                x_label: "horizontal distance from the target vertical (m)",
                y_label: "altitude Up (m)",
                series: profile,
                equal_scales: false,
            },
        ],
        (1, 2),
        (1400, 560),
    )?;
    written.push(path);

    let path = dir.join(format!("{name}-position.png"));
    let panels = [
        time_panel(flights, "plant.r_nue[1]", "North", "North (m)", 1.0)?,
        time_panel(
            flights,
            "plant.r_nue[2]",
            "Up (altitude)",
            "altitude Up (m)",
            1.0,
        )?,
        time_panel(flights, "plant.r_nue[3]", "East", "East (m)", 1.0)?,
    ];
    draw_panels(
        &path,
        &format!("{name}: position components (Fig. 4)"),
        &panels,
        (3, 1),
        (1200, 1260),
    )?;
    written.push(path);

    let path = dir.join(format!("{name}-body-rates.png"));
    let deg = 1f64.to_degrees();
    let panels = [
        time_panel(
            flights,
            "plant.omega_body[1]",
            "yaw rate (body x)",
            "omega_x (deg/s)",
            deg,
        )?,
        time_panel(
            flights,
            "plant.omega_body[2]",
            "roll rate (body y, the thrust axis)",
            "omega_y (deg/s)",
            deg,
        )?,
        time_panel(
            flights,
            "plant.omega_body[3]",
            "pitch rate (body z)",
            "omega_z (deg/s)",
            deg,
        )?,
    ];
    draw_panels(
        &path,
        &format!("{name}: body angular rates (Fig. 5)"),
        &panels,
        (3, 1),
        (1200, 1260),
    )?;
    written.push(path);
    Ok(written)
}
