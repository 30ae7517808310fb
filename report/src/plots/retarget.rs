//! The retarget figure: North, East, altitude, distance from the new site, thrust-axis tilt
//! and tilt error against time from shortly before the command, each law re-planned (solid)
//! and with the target only moved (dashed), the new site marked.
use super::style::{self, colour, tick, Key};
use lander::retarget::{DivertFlight, RetargetCommand};
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Seconds shown before the command.
const BEFORE_S: f64 = 5.0;

struct Panel {
    title: &'static str,
    y_label: &'static str,
    /// Each flight's (t, y) points.
    series: Vec<Vec<(f64, f64)>>,
    /// A horizontal reference line (the site's North or altitude).
    reference: Option<f64>,
}

fn series(
    flights: &[&DivertFlight],
    command: &RetargetCommand,
    value: impl Fn(&[f64], &[usize]) -> f64,
    names: &[&str],
) -> anyhow::Result<Vec<Vec<(f64, f64)>>> {
    flights
        .iter()
        .map(|f| {
            let t = &f.flight.trajectory;
            let idx: Vec<usize> = names
                .iter()
                .map(|n| {
                    t.column_index(n)
                        .ok_or_else(|| anyhow::anyhow!("no column {n} to plot"))
                })
                .collect::<anyhow::Result<_>>()?;
            Ok((0..t.len())
                .filter(|&k| t.times[k] >= command.time_s - BEFORE_S)
                .map(|k| (t.times[k], value(t.row(k), &idx)))
                .collect())
        })
        .collect()
}

/// Draws the figure of `flights` to `path` (PNG), titled `name`.
pub fn figure(
    flights: &[&DivertFlight],
    command: &RetargetCommand,
    path: &Path,
    name: &str,
) -> anyhow::Result<()> {
    let tilt = |row: &[f64], i: &[usize]| {
        let (x, z) = (row[i[0]], row[i[1]]);
        (1.0 - 2.0 * (x * x + z * z))
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees()
    };
    let panels = [
        Panel {
            title: "North position",
            y_label: "North (m)",
            series: series(flights, command, |r, i| r[i[0]], &["plant.r_nue[1]"])?,
            reference: Some(command.site_nue[0]),
        },
        Panel {
            title: "East position",
            y_label: "East (m)",
            series: series(flights, command, |r, i| r[i[0]], &["plant.r_nue[3]"])?,
            reference: Some(command.site_nue[2]),
        },
        Panel {
            title: "Altitude",
            y_label: "Up (m)",
            series: series(flights, command, |r, i| r[i[0]], &["plant.r_nue[2]"])?,
            reference: Some(command.site_nue[1]),
        },
        Panel {
            title: "Distance from the new site",
            y_label: "distance (m)",
            series: series(
                flights,
                command,
                |r, i| {
                    let [n, u, e] = command.site_nue;
                    let (dn, du, de) = (r[i[0]] - n, r[i[1]] - u, r[i[2]] - e);
                    (dn * dn + du * du + de * de).sqrt()
                },
                &["plant.r_nue[1]", "plant.r_nue[2]", "plant.r_nue[3]"],
            )?,
            reference: Some(lander::retarget::SETTLE_RADIUS_M),
        },
        Panel {
            title: "Thrust-axis tilt from vertical",
            y_label: "tilt (deg)",
            series: series(
                flights,
                command,
                tilt,
                &["plant.q_body_to_nue[2]", "plant.q_body_to_nue[4]"],
            )?,
            reference: None,
        },
        Panel {
            title: "Tilt error (thrust axis vs commanded direction)",
            y_label: "tilt error (deg)",
            series: series(
                flights,
                command,
                |r, i| r[i[0]].to_degrees(),
                &["gnc.tilt_error"],
            )?,
            reference: None,
        },
    ];
    let root = super::canvas::bitmap(path, (1500, 1440));
    root.fill(&WHITE)?;
    let [n, u, e] = command.site_nue;
    let root = root.titled(
        &format!(
            "{name}: retarget at {} s to ({n}, {u}, {e}) m",
            command.time_s
        ),
        ("sans-serif", 24),
    )?;
    let root = style::legend_strip(&root, &legend(flights))?;
    for (area, panel) in root.split_evenly((3, 2)).iter().zip(&panels) {
        let points = || panel.series.iter().flat_map(|s| s.iter());
        let (x0, x1) = points().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
        let (mut y0, mut y1) = points()
            .filter(|p| p.1.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p.1), b.max(p.1))
            });
        if let Some(r) = panel.reference {
            (y0, y1) = (y0.min(r), y1.max(r));
        }
        if !(x0.is_finite() && y0.is_finite()) {
            continue;
        }
        let pad = 0.05 * (y1 - y0).max(1e-3);
        // Enough decimals to tell the ticks of a narrow range apart (150.1 from 150.2 m).
        let decimals = (1 - span_magnitude(y1 - y0 + 2.0 * pad)).clamp(0, 4) as usize;
        let y_tick = move |v: &f64| {
            if decimals == 0 {
                tick(v)
            } else {
                format!("{v:.decimals$}")
            }
        };
        let mut chart = ChartBuilder::on(area)
            .caption(panel.title, ("sans-serif", 20))
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(80)
            .build_cartesian_2d(x0..x1, (y0 - pad)..(y1 + pad))?;
        chart
            .configure_mesh()
            .x_desc("time (s)")
            .y_desc(panel.y_label)
            .x_label_formatter(&tick)
            .y_label_formatter(&y_tick)
            .light_line_style(TRANSPARENT)
            .bold_line_style(BLACK.mix(0.12))
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 16))
            .draw()?;
        if let Some(r) = panel.reference {
            chart.draw_series(LineSeries::new(
                [(x0, r), (x1, r)],
                BLACK.mix(0.5).stroke_width(1),
            ))?;
        }
        // The command's time.
        chart.draw_series(DashedLineSeries::new(
            [(command.time_s, y0 - pad), (command.time_s, y1 + pad)],
            4,
            4,
            BLACK.mix(0.4).stroke_width(1),
        ))?;
        for (flight, points) in flights.iter().zip(&panel.series) {
            let law = flight.flight.law;
            let style = colour(law)
                .filled()
                .stroke_width(if flight.replan { 3 } else { 2 });
            let buckets = style::plot_buckets(&chart);
            for piece in style::segments(points) {
                let piece = style::decimate(&piece, buckets);
                if flight.replan {
                    chart.draw_series(LineSeries::new(piece, style))?;
                } else {
                    chart.draw_series(DashedLineSeries::new(piece, 8, 6, style))?;
                }
            }
        }
    }
    root.present()?;
    Ok(())
}

/// Writes the figures `<name>.png` (every flight) and `<name>-replanned.png` into `dir`;
/// returns their paths.
pub fn figures(
    flights: &[DivertFlight],
    command: &RetargetCommand,
    dir: &Path,
    name: &str,
) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut written = Vec::new();
    let path = dir.join(format!("{name}.png"));
    let title = format!("scenario '{name}'");
    let all: Vec<&DivertFlight> = flights.iter().collect();
    figure(&all, command, &path, &title)?;
    written.push(path);
    // The re-planned flights alone, at their own scale.
    let replanned: Vec<&DivertFlight> = flights.iter().filter(|f| f.replan).collect();
    let path = dir.join(format!("{name}-replanned.png"));
    let title = format!("scenario '{name}', re-planned");
    figure(&replanned, command, &path, &title)?;
    written.push(path);
    Ok(written)
}

/// `floor(log10(x))` for a positive span (1 for anything not positive).
fn span_magnitude(x: f64) -> i32 {
    if x > 0.0 && x.is_finite() {
        x.log10().floor() as i32
    } else {
        1
    }
}

/// The figure's legend: each flight's line (solid re-planned, dashed target only moved), in
/// the order of the flights (the order of the summary table).
fn legend(flights: &[&DivertFlight]) -> style::Legend {
    flights
        .iter()
        .map(|f| {
            let law = f.flight.law;
            let key = if f.replan {
                Key::Solid(law)
            } else {
                Key::Dashed(law)
            };
            (key, f.label())
        })
        .collect()
}
