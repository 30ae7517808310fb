//! The paper's figures for one scenario flown with each law: Fig. 3 the 3-D trajectories
//! (with the ground track at equal scales and the altitude profile), Fig. 4 the position
//! components against time, Fig. 5 the body rates against time (the transient and the rest
//! of the flight on axes of their own). Only the paper scenario's figures carry the paper's
//! figure numbers and its phase boundaries; every figure has one legend, above its plots, in
//! the order of the comparison table.
use super::style::{self, tick, Key, Legend};
use lander::laws::Law;
use lander::paper::Flight;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The built-in scenario whose figures reproduce the paper's (Figs. 3 to 5): no other
/// scenario's figures carry a paper figure number.
pub const PAPER_SCENARIO: &str = "paper";

/// The paper scenario's phase boundaries (s): the hover at 800 m ends and the descent
/// begins, the descent ends and the hover at 150 m begins, the run ends.
pub const PAPER_PHASES: [(f64, &str); 3] = [
    (12.0, "12 s: descent"),
    (142.0, "142 s: hover at 150 m"),
    (172.0, "172 s: end"),
];

/// A figure's title: the scenario and what it shows, with the paper figure it reproduces
/// for the paper scenario only.
pub fn figure_title(name: &str, what: &str, paper_figure: Option<u32>) -> String {
    match paper_figure {
        Some(n) if name == PAPER_SCENARIO => format!("{name}: {what} (paper Fig. {n})"),
        _ => format!("{name}: {what}"),
    }
}

/// The phase markers of a scenario's time plots: the paper's boundaries, for the paper
/// scenario, those inside the flown time span (`t_end` the longest flight's last time).
pub fn phase_markers(name: &str, t_start: f64, t_end: f64) -> Vec<(f64, &'static str)> {
    if name != PAPER_SCENARIO {
        return Vec::new();
    }
    PAPER_PHASES
        .into_iter()
        .filter(|&(t, _)| t >= t_start && t <= t_end + 1e-6)
        .collect()
}

/// The legend of the paper figures: each law's curve, in the order of the flights (the order
/// of the comparison table and of the report).
pub fn legend(flights: &[Flight]) -> Legend {
    flights
        .iter()
        .map(|f| (Key::Curve(f.law), f.law.name().to_owned()))
        .collect()
}

/// A panel: each law's (x, y) points, with its axis quantities and units.
struct Panel<'a> {
    title: String,
    x_label: &'a str,
    y_label: &'a str,
    series: Vec<(Law, Vec<(f64, f64)>)>,
    /// Same metres per pixel on both axes (a ground track).
    equal_scales: bool,
    /// A time series (sorted in x): decimated per pixel column, broken at gaps, and with
    /// the phase markers; otherwise a path.
    time: bool,
    /// The x range shown (default: all the data); the y range fits the data inside it.
    x_range: Option<Range<f64>>,
    /// The least span of the y axis (so that the rest of a flight after its transient is not
    /// magnified down to the noise of the integration).
    min_y_span: Option<f64>,
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

type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// The figure's drawing area: white, titled, the legend strip under the title.
fn figure_area<'a>(
    path: &'a Path,
    size: (u32, u32),
    title: &str,
    legend: &Legend,
) -> anyhow::Result<Area<'a>> {
    let root = super::canvas::bitmap(path, size);
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 26))?;
    style::legend_strip(&root, legend)
}

fn draw_panel(area: &Area<'_>, panel: &Panel<'_>, markers: &[(f64, &str)]) -> anyhow::Result<()> {
    let points = || panel.series.iter().flat_map(|(_, p)| p.iter());
    let mut x = match &panel.x_range {
        Some(r) => r.clone(),
        None => padded(extent(points().map(|p| p.0))),
    };
    let inside = |p: &&(f64, f64)| panel.x_range.as_ref().is_none_or(|r| r.contains(&p.0));
    let mut y = padded(extent(points().filter(inside).map(|p| p.1)));
    if panel.equal_scales {
        // The plot area: the panel less margins, label areas and the caption (its text
        // height plus plotters' spacing below it).
        let (w, h) = area.dim_in_pixel();
        let width = f64::from(w - 2 * MARGIN - Y_LABELS);
        let height = f64::from(h - 2 * MARGIN - X_LABELS - CAPTION - 10);
        (x, y) = equalise(x, y, width, height);
    }
    if let Some(min_span) = panel.min_y_span {
        let span = y.end - y.start;
        if span < min_span {
            let mid = 0.5 * (y.start + y.end);
            y = (mid - 0.5 * min_span)..(mid + 0.5 * min_span);
        }
    }
    let (x_tick, y_tick) = (style::tick_on(&x), style::tick_on(&y));
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
        .x_label_formatter(&x_tick)
        .y_label_formatter(&y_tick)
        .light_line_style(TRANSPARENT)
        .bold_line_style(BLACK.mix(0.12))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 16))
        .draw()?;
    if panel.time {
        style::phase_markers(&mut chart, markers)?;
    }
    for law in style::draw_order(panel.series.iter().map(|(law, _)| *law)) {
        if let Some((_, points)) = panel.series.iter().find(|(l, _)| *l == law) {
            if panel.time {
                style::draw_law_curve(&mut chart, law, points)?;
            } else {
                style::draw_law_path(&mut chart, law, points)?;
            }
        }
    }
    Ok(())
}

fn draw_panels(
    path: &Path,
    title: &str,
    legend: &Legend,
    panels: &[Panel<'_>],
    layout: (usize, usize),
    size: (u32, u32),
    markers: &[(f64, &str)],
) -> anyhow::Result<()> {
    let root = figure_area(path, size, title, legend)?;
    for (area, panel) in root.split_evenly(layout).iter().zip(panels) {
        draw_panel(area, panel, markers)?;
    }
    root.present()?;
    Ok(())
}

/// Where a time plot of `panels` splits into the transient and the rest: a round number of
/// seconds (multiple of 5) past the last time any series exceeds 5 % of the largest
/// magnitude, when that leaves the transient less than half of the flight; `None` otherwise
/// (one axis shows it well).
pub fn transient_end(series: &[&[(f64, f64)]]) -> Option<f64> {
    let all = || {
        series
            .iter()
            .flat_map(|s| s.iter())
            .filter(|p| p.0.is_finite() && p.1.is_finite())
    };
    let peak = all().fold(0.0f64, |m, p| m.max(p.1.abs()));
    let (t0, t1) = extent(all().map(|p| p.0));
    if !(peak > 0.0 && t1 > t0) {
        return None;
    }
    let settled = all()
        .filter(|p| p.1.abs() > 0.05 * peak)
        .fold(t0, |t, p| t.max(p.0));
    let split = t0 + (5.0 * ((settled - t0 + 2.0) / 5.0).ceil()).max(5.0);
    (split - t0 < 0.5 * (t1 - t0)).then_some(split)
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
        time: true,
        x_range: None,
        min_y_span: None,
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
fn trajectory_3d(
    path: &Path,
    title: &str,
    legend: &Legend,
    tracks: &[(Law, Vec<[f64; 3]>)],
) -> anyhow::Result<()> {
    let all = || tracks.iter().flat_map(|(_, p)| p.iter());
    let n = padded(extent(all().map(|p| p[0])));
    let u = padded(extent(all().map(|p| p[1])));
    let e = padded(extent(all().map(|p| p[2])));
    // The 3-D lines are solid: the legend shows them so.
    let legend: Legend = legend
        .iter()
        .map(|(key, text)| match key {
            Key::Curve(law) => (Key::Solid(*law), text.clone()),
            other => (*other, text.clone()),
        })
        .collect();
    let root = figure_area(path, (1100, 900), title, &legend)?;
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
    for law in style::draw_order(tracks.iter().map(|(law, _)| *law)) {
        let Some((_, points)) = tracks.iter().find(|(l, _)| *l == law) else {
            continue;
        };
        let style = style::line(law, 2);
        let finite: Vec<[f64; 3]> = points
            .iter()
            .copied()
            .filter(|p| p.iter().all(|v| v.is_finite()))
            .collect();
        let points = style::decimate_path(
            &finite,
            300,
            &[
                |p: &[f64; 3]| p[0],
                |p: &[f64; 3]| p[1],
                |p: &[f64; 3]| p[2],
            ],
        );
        let line = points.iter().map(|p| (p[2], p[1], p[0]));
        chart.draw_series(LineSeries::new(line, style))?;
        // Ground shadow: where each law flew over the ground, in a light tint.
        let shadow = style::colour(law).mix(0.35).filled().stroke_width(1);
        chart.draw_series(LineSeries::new(
            points.iter().map(|p| (p[2], u.start, p[0])),
            shadow,
        ))?;
    }
    root.present()?;
    Ok(())
}

/// The body-rate figure: per rate, the transient on its own axes and the rest of the flight
/// on axes of its own scale (the rates there are a few hundredths of the peak), so neither
/// is a flat line at the edge of one long axis; one axis when the transient is no short
/// part of the flight.
fn body_rates(
    path: &Path,
    title: &str,
    legend: &Legend,
    panels: &[Panel<'_>],
    markers: &[(f64, &str)],
) -> anyhow::Result<()> {
    let series: Vec<&[(f64, f64)]> = panels
        .iter()
        .flat_map(|p| p.series.iter().map(|(_, s)| s.as_slice()))
        .collect();
    let split = transient_end(&series);
    let (t0, t1) = extent(series.iter().flat_map(|s| s.iter().map(|p| p.0)));
    let root = figure_area(path, (1400, 1260), title, legend)?;
    for (row, panel) in root.split_evenly((3, 1)).iter().zip(panels) {
        let Some(split) = split else {
            draw_panel(row, panel, markers)?;
            continue;
        };
        let (w, _) = row.dim_in_pixel();
        let (left, right) = row.split_horizontally(w * 9 / 20);
        // The rest of the flight on a scale of its own, but no finer than a hundredth of the
        // transient's: what is smaller than that is the integration's noise.
        let peak = extent(
            panel
                .series
                .iter()
                .flat_map(|(_, s)| s.iter().filter(|p| p.0 <= split).map(|p| p.1)),
        );
        let floor = 0.01 * (peak.1 - peak.0);
        let part = |title: String, range: Range<f64>, min_y_span: Option<f64>| Panel {
            title,
            x_label: panel.x_label,
            y_label: panel.y_label,
            series: panel.series.clone(),
            equal_scales: false,
            time: true,
            x_range: Some(range),
            min_y_span,
        };
        draw_panel(
            &left,
            &part(
                format!(
                    "{}: transient, {} to {} s",
                    panel.title,
                    tick(&t0),
                    tick(&split)
                ),
                t0..split,
                None,
            ),
            markers,
        )?;
        draw_panel(
            &right,
            &part(
                format!(
                    "{}: {} to {} s, own scale",
                    panel.title,
                    tick(&split),
                    tick(&t1)
                ),
                split..t1,
                floor.is_finite().then_some(floor),
            ),
            markers,
        )?;
    }
    root.present()?;
    Ok(())
}

/// Writes the figures for `flights` into `dir`; returns their paths.
pub fn paper_figures(flights: &[Flight], dir: &Path, name: &str) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut written = Vec::new();
    let tracks = positions(flights)?;
    let legend = legend(flights);
    let times = || {
        flights
            .iter()
            .flat_map(|f| f.trajectory.times.iter().copied())
    };
    let (t0, t1) = extent(times());
    let markers = phase_markers(name, t0, t1);

    let path = dir.join(format!("{name}-trajectory-3d.png"));
    trajectory_3d(
        &path,
        &figure_title(name, "3-D trajectories", Some(3)),
        &legend,
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
        &figure_title(name, "ground track and altitude profile", None),
        &legend,
        &[
            Panel {
                title: "ground track (equal scales)".into(),
                x_label: "East (m)",
                y_label: "North (m)",
                series: track,
                equal_scales: true,
                time: false,
                x_range: None,
                min_y_span: None,
            },
            Panel {
                title: "altitude against horizontal distance".into(),
                x_label: "horizontal distance from the target vertical (m)",
                y_label: "altitude Up (m)",
                series: profile,
                equal_scales: false,
                time: false,
                x_range: None,
                min_y_span: None,
            },
        ],
        (1, 2),
        (1400, 600),
        &[],
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
        &figure_title(name, "position components", Some(4)),
        &legend,
        &panels,
        (3, 1),
        (1200, 1290),
        &markers,
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
            "roll rate (body y, thrust axis)",
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
    body_rates(
        &path,
        &figure_title(name, "body angular rates", Some(5)),
        &legend,
        &panels,
        &markers,
    )?;
    written.push(path);
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_paper_scenario_carries_paper_figure_numbers() {
        assert_eq!(
            figure_title("paper", "body angular rates", Some(5)),
            "paper: body angular rates (paper Fig. 5)"
        );
        for name in ["landing", "upright", "paper-nav", "paper-thrusters"] {
            let title = figure_title(name, "position components", Some(4));
            assert!(!title.contains("Fig"), "{title}");
        }
    }

    #[test]
    fn phase_markers_only_where_the_run_covers_them() {
        let all: Vec<f64> = phase_markers("paper", 0.0, 172.0)
            .iter()
            .map(|m| m.0)
            .collect();
        assert_eq!(all, vec![12.0, 142.0, 172.0]);
        let short: Vec<f64> = phase_markers("paper", 0.0, 100.0)
            .iter()
            .map(|m| m.0)
            .collect();
        assert_eq!(short, vec![12.0]);
        assert!(phase_markers("landing", 0.0, 323.6).is_empty());
    }

    #[test]
    fn the_transient_gets_its_own_axis_only_when_short() {
        let decay: Vec<(f64, f64)> = (0..17_201)
            .map(|k| {
                let t = k as f64 * 0.01;
                (t, 60.0 * (-t / 2.0).exp() * (3.0 * t).sin())
            })
            .collect();
        // 5 % of the ~45 deg/s peak is last exceeded before 10 s: split at a multiple of 5.
        let split = transient_end(&[&decay]).unwrap();
        assert!(
            split > 5.0 && split <= 15.0 && split % 5.0 == 0.0,
            "{split}"
        );
        let steady: Vec<(f64, f64)> = (0..1_000).map(|k| (k as f64, (k as f64).sin())).collect();
        assert_eq!(transient_end(&[&steady]), None);
    }
}
