//! One self-contained HTML page for a results directory: every PNG embedded (base64), the
//! text tables and verdicts the commands wrote (`*-summary.txt`), and `summary.csv`'s
//! per-cell statistics with the failed flights of a campaign. Written by `harness paper` and
//! `harness monte-carlo` into their directory, and by `harness report DIR` for any directory
//! (a merged or Dask campaign, say).
use anyhow::Context;
use base64::Engine;
use std::fmt::Write;
use std::path::{Path, PathBuf};

pub const FILE_NAME: &str = "report.html";

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn files(dir: &Path, suffix: &str) -> anyhow::Result<Vec<PathBuf>> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("reading {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.to_string_lossy().ends_with(suffix) && p.is_file())
        .collect();
    out.sort();
    Ok(out)
}

/// The columns of `summary.csv` the page shows (all are in the file).
const SUMMARY_COLUMNS: [&str; 13] = [
    "law",
    "phi_cmd_deg",
    "runs",
    "errors",
    "failed_verdicts",
    "statement",
    "ellipse_of",
    "ellipse_semi_major_m",
    "ellipse_semi_minor_m",
    "max_horizontal_deviation_descent_m_p50",
    "max_horizontal_deviation_descent_m_p95_ub90",
    "max_horizontal_deviation_descent_m_max",
    "max_lateral_speed_manoeuvre_mps_p50",
];

fn summary_table(path: &Path, html: &mut String) -> anyhow::Result<()> {
    let mut reader = csv::Reader::from_path(path)?;
    let header = reader.headers()?.clone();
    let index: Vec<usize> = SUMMARY_COLUMNS
        .iter()
        .filter_map(|c| header.iter().position(|h| h == *c))
        .collect();
    let _ = writeln!(
        html,
        "<h2>Monte Carlo statistics</h2>\n<p>Per law and phi_cmd; every metric's median, \
         maximum and the 90 %-confidence upper bounds of its p95 and p99.73 (<code>_ub90</code>, \
         empty where the runs cannot support them: 45 and 852 runs are needed) are in \
         <code>summary.csv</code>. The statement is the binomial \
         (Clopper-Pearson) lower bound on the share of runs meeting the scenario's \
         requirement, at 90 % confidence; the ellipse holds 99.73 % of a fitted normal.</p>\
         \n<table>\n<tr>"
    );
    for &i in &index {
        let _ = write!(html, "<th>{}</th>", escape(&header[i]));
    }
    let _ = writeln!(html, "</tr>");
    for record in reader.records() {
        let record = record?;
        let failed = record
            .get(
                header
                    .iter()
                    .position(|h| h == "failed_verdicts")
                    .unwrap_or(0),
            )
            .is_some_and(|f| f != "0");
        let _ = write!(html, "<tr{}>", if failed { " class=\"fail\"" } else { "" });
        for &i in &index {
            let cell = record.get(i).unwrap_or_default();
            let shown = match cell.parse::<f64>() {
                Ok(x) if cell.contains('.') => format!("{x:.4}"),
                _ => cell.to_owned(),
            };
            let _ = write!(html, "<td>{}</td>", escape(&shown));
        }
        let _ = writeln!(html, "</tr>");
    }
    let _ = writeln!(html, "</table>");
    Ok(())
}

/// The metrics whose drivers and paired differences the page shows (all are in
/// `summary.csv`).
const ANALYSED_METRICS: [&str; 4] = [
    "max_horizontal_deviation_descent_m",
    "handover_horizontal_speed_mps",
    "max_tilt_error_rad",
    "propellant_used_kg",
];

/// What drives each shown metric in each cell, and the cell's law against the reference law
/// on the same runs, from `summary.csv`.
fn analysis_table(path: &Path, html: &mut String) -> anyhow::Result<()> {
    let mut reader = csv::Reader::from_path(path)?;
    let header = reader.headers()?.clone();
    let column = |name: &str| header.iter().position(|h| h == name);
    if column("paired_against").is_none() {
        return Ok(());
    }
    let _ = writeln!(
        html,
        "<h2>What drives the metrics, and each law against the reference</h2>\n<p>Per cell \
         and metric: the dispersed inputs whose partial rank correlation with the metric \
         differs from zero at the 5 % level, strongest first (PRCC, -1 to 1), and the median \
         of the run-by-run difference from the reference law on the same draws with its \
         distribution-free 90 % interval. Every metric is in <code>summary.csv</code>.</p>\
         \n<table>\n<tr><th>law</th><th>phi_cmd_deg</th><th>against</th>"
    );
    for m in ANALYSED_METRICS {
        let _ = write!(
            html,
            "<th>{} drivers</th><th>{} minus reference</th>",
            escape(m),
            escape(m)
        );
    }
    let _ = writeln!(html, "</tr>");
    for record in reader.records() {
        let record = record?;
        let get = |name: &str| {
            column(name)
                .and_then(|i| record.get(i))
                .unwrap_or_default()
                .to_owned()
        };
        let _ = write!(
            html,
            "<tr><td>{}</td><td>{}</td><td>{}</td>",
            escape(&get("law")),
            escape(&get("phi_cmd_deg")),
            escape(&get("paired_against"))
        );
        for m in ANALYSED_METRICS {
            let number = |suffix: &str| get(&format!("{m}_{suffix}")).parse::<f64>().ok();
            let paired = match (
                number("paired_median_diff"),
                number("paired_ci90_low"),
                number("paired_ci90_high"),
            ) {
                (Some(d), Some(lo), Some(hi)) if lo.is_finite() => {
                    format!("{d:.4} [{lo:.4}, {hi:.4}]")
                }
                (Some(d), _, _) => format!("{d:.4} (too few runs for an interval)"),
                _ => String::new(),
            };
            let _ = write!(
                html,
                "<td>{}</td><td>{}</td>",
                escape(&get(&format!("{m}_influential_inputs"))),
                escape(&paired)
            );
        }
        let _ = writeln!(html, "</tr>");
    }
    let _ = writeln!(html, "</table>");
    Ok(())
}

/// Writes `report.html` into `dir` from the files there; `failed` lists failed flights.
pub fn write(dir: &Path, title: &str, failed: &[String]) -> anyhow::Result<PathBuf> {
    let mut html = format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>{t}</title>\n<style>body{{font-family:sans-serif;max-width:1500px;\
         margin:auto;padding:1em}} pre{{background:#f4f4f4;padding:.8em;overflow-x:auto}} \
         table{{border-collapse:collapse;font-size:90%}} td,th{{border:1px solid #bbb;\
         padding:.25em .5em;text-align:right}} tr.fail{{background:#fde2e2}} \
         img{{max-width:100%;border:1px solid #ddd;margin:.5em 0}}</style></head><body>\n\
         <h1>{t}</h1>\n",
        t = escape(title)
    );
    let _ = writeln!(
        html,
        "<p>Written by lander-fmi harness {} (commit {}) at {} (UTC).</p>",
        env!("CARGO_PKG_VERSION"),
        env!("LANDER_COMMIT"),
        utc_now()
    );
    // A campaign's definition holds what reproduces it: scenario, seed, grid, dispersions,
    // and the FMUs' model names, GUIDs and generation tools.
    let campaign = dir.join("campaign.toml");
    if campaign.is_file() {
        let text = std::fs::read_to_string(&campaign)
            .with_context(|| format!("reading {}", campaign.display()))?;
        let _ = writeln!(
            html,
            "<h2>Campaign definition and versions (campaign.toml)</h2>\n<pre>{}</pre>",
            escape(&text)
        );
    }
    for path in files(dir, "-summary.txt")? {
        let text = std::fs::read_to_string(&path)?;
        let _ = writeln!(
            html,
            "<h2>{}</h2>\n<pre>{}</pre>",
            escape(&path.file_name().unwrap_or_default().to_string_lossy()),
            escape(&text)
        );
    }
    let summary = dir.join(crate::montecarlo::summary_csv::FILE_NAME);
    if summary.is_file() {
        summary_table(&summary, &mut html)?;
        analysis_table(&summary, &mut html)?;
        let _ = writeln!(
            html,
            "<h2>Flights that did not end as the scenario expects: {}</h2>",
            failed.len()
        );
        if !failed.is_empty() {
            let _ = writeln!(html, "<pre>{}</pre>", escape(&failed.join("\n")));
        }
    }
    let _ = writeln!(html, "<h2>Figures</h2>");
    for path in files(dir, ".png")? {
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let data = base64::engine::general_purpose::STANDARD.encode(std::fs::read(&path)?);
        let _ = writeln!(
            html,
            "<h3>{n}</h3>\n<img alt=\"{n}\" src=\"data:image/png;base64,{data}\">",
            n = escape(&name)
        );
    }
    let _ = writeln!(html, "</body></html>");
    let out = dir.join(FILE_NAME);
    std::fs::write(&out, html).with_context(|| format!("writing {}", out.display()))?;
    Ok(out)
}

/// The current time as `YYYY-MM-DD HH:MM:SS`, UTC (the civil calendar from the days since
/// 1970, Howard Hinnant's algorithm).
fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    civil(secs)
}

fn civil(secs: u64) -> String {
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1_460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02}",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

/// `harness report DIR`: a campaign directory gets its summary and failed flights from its
/// manifest; any other directory the files it holds.
pub fn for_directory(dir: &Path) -> anyhow::Result<PathBuf> {
    let manifest = dir.join(crate::montecarlo::manifest::FILE_NAME);
    let failed = if manifest.is_file() {
        let rows = crate::montecarlo::manifest::read(&manifest)?;
        crate::montecarlo::summary_csv::failed_lines(&rows)
    } else {
        Vec::new()
    };
    let found = !files(dir, "-summary.txt")?.is_empty()
        || !files(dir, ".png")?.is_empty()
        || dir
            .join(crate::montecarlo::summary_csv::FILE_NAME)
            .is_file()
        || manifest.is_file();
    if !found {
        anyhow::bail!(
            "{} holds no results to report (no *-summary.txt, summary.csv, {} or *.png): \
             write them first with `harness paper` or `harness monte-carlo --out-dir {0}`",
            dir.display(),
            crate::montecarlo::manifest::FILE_NAME
        );
    }
    let title = format!("lander-fmi results: {}", dir.display());
    write(dir, &title, &failed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_directory_without_results_is_refused_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let message = for_directory(dir.path()).unwrap_err().to_string();
        assert!(message.contains("holds no results"), "{message}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        let missing = dir.path().join("nonexistent");
        assert!(for_directory(&missing).is_err());
    }

    #[test]
    fn the_calendar_date_of_known_instants() {
        assert_eq!(civil(0), "1970-01-01 00:00:00");
        assert_eq!(civil(951_782_400), "2000-02-29 00:00:00");
        assert_eq!(civil(1_796_083_199), "2026-11-30 23:59:59");
    }

    #[test]
    fn a_campaign_page_carries_its_definition_and_versions() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("campaign.toml"),
            "[campaign]\nseed = 7\n[[versions.fmu]]\nguid = \"{g}\"\n",
        )
        .unwrap();
        let html = std::fs::read_to_string(write(dir.path(), "t", &[]).unwrap()).unwrap();
        assert!(html.contains("Campaign definition and versions"), "{html}");
        assert!(
            html.contains("seed = 7") && html.contains("guid = &quot;{g}&quot;"),
            "{html}"
        );
        assert!(html.contains(concat!(
            "harness ",
            env!("CARGO_PKG_VERSION"),
            " (commit ",
            env!("LANDER_COMMIT"),
            ") at "
        )));
        // In a git checkout the page names the commit checked out (the build script reruns
        // when HEAD moves).
        let head = std::process::Command::new("git")
            .args(["rev-parse", "HEAD"])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_owned());
        match head {
            Some(head) => assert_eq!(env!("LANDER_COMMIT"), head),
            None => assert_eq!(env!("LANDER_COMMIT"), "unknown"),
        }
    }

    #[test]
    fn the_page_embeds_images_and_escapes_text() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a.png"), [0x89, b'P', b'N', b'G']).unwrap();
        std::fs::write(dir.path().join("paper-summary.txt"), "verdict <hard> & x").unwrap();
        let path = write(dir.path(), "t", &[]).unwrap();
        let html = std::fs::read_to_string(path).unwrap();
        assert!(html.contains("data:image/png;base64,iVBORw=="), "{html}");
        assert!(html.contains("verdict &lt;hard&gt; &amp; x"));
        assert!(!html.contains("src=\"a.png\""), "self-contained");
    }
}
