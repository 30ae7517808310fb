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

/// What a `harness paper` directory keeps of the run for its report (and for `harness report
/// DIR` later): the scenario, its parameters and the FMUs flown.
pub const PROVENANCE_FILE: &str = "provenance.toml";

/// The scenario a paper-style run flew and the FMUs it loaded.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Provenance {
    /// The scenario's name (its `name`).
    pub scenario: String,
    pub start_time_s: f64,
    pub stop_time_s: f64,
    pub step_size_s: f64,
    /// How the master exchanges values (`gauss-seidel`, `jacobi`).
    pub ordering: String,
    /// The laws flown, each overriding `gnc.control_law`, in the order of the table.
    #[serde(default)]
    pub laws: Vec<String>,
    #[serde(default)]
    pub instance: Vec<InstanceProvenance>,
}

/// One FMU instance: what it is and the values the scenario gives it.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct InstanceProvenance {
    pub name: String,
    /// The `.fmu` as the scenario names it.
    pub fmu: String,
    pub model_name: String,
    pub guid: String,
    pub fmi_version: String,
    /// The model's own version (`version` in modelDescription.xml), when it gives one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub version: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generation_tool: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generation_date: Option<String>,
    /// The values the scenario sets, in its order.
    #[serde(default)]
    pub parameter: Vec<Parameter>,
}

/// A parameter or start value a scenario sets, as text.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Parameter {
    pub name: String,
    pub value: String,
}

impl Provenance {
    /// The scenario and FMUs of a loaded simulation (its parameters as they stand now).
    pub fn of(simulation: &cosim::supervise::Runner) -> Self {
        let system = simulation.system();
        let value = |v: &cosim::system::ParamValue| match v {
            cosim::system::ParamValue::Real(x) => format!("{x}"),
            cosim::system::ParamValue::Integer(i) => format!("{i}"),
            cosim::system::ParamValue::Boolean(b) => format!("{b}"),
            cosim::system::ParamValue::String(t) => format!("{t:?}"),
        };
        Self {
            scenario: system.name.clone(),
            start_time_s: system.start_time,
            stop_time_s: system.stop_time,
            step_size_s: system.step_size,
            ordering: match system.ordering {
                cosim::system::Ordering::GaussSeidel => "gauss-seidel".into(),
                cosim::system::Ordering::Jacobi => "jacobi".into(),
            },
            laws: Vec::new(),
            instance: system
                .instances
                .iter()
                .enumerate()
                .map(|(index, instance)| {
                    let (_, md) = simulation.description(index);
                    InstanceProvenance {
                        name: instance.name.clone(),
                        fmu: instance.fmu.display().to_string(),
                        model_name: md.model_name.clone(),
                        guid: md.guid.clone(),
                        fmi_version: md.fmi_version.clone(),
                        version: md.version.clone(),
                        generation_tool: md.generation_tool.clone(),
                        generation_date: md.generation_date_and_time.clone(),
                        parameter: instance
                            .parameters
                            .iter()
                            .map(|(n, v)| Parameter {
                                name: n.clone(),
                                value: value(v),
                            })
                            .collect(),
                    }
                })
                .collect(),
        }
    }

    /// Writes `provenance.toml` into `dir`.
    pub fn write(&self, dir: &Path) -> anyhow::Result<PathBuf> {
        let path = dir.join(PROVENANCE_FILE);
        let text = format!(
            "# The scenario and FMUs `harness paper` flew (shown by report.html).\n{}",
            toml::to_string_pretty(self)?
        );
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
        Ok(path)
    }

    pub fn read(path: &Path) -> anyhow::Result<Self> {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        toml::from_str(&text).with_context(|| format!("parsing {}", path.display()))
    }
}

/// The page's section for a run's provenance: scenario, timing, laws, FMUs (model, GUID, FMI
/// and model versions, generator) and every parameter the scenario sets.
fn provenance_section(p: &Provenance, html: &mut String) {
    let _ = writeln!(
        html,
        "<h2>Scenario, parameters and versions</h2>\n<table class=\"facts\">\n\
         <tr><th>Scenario</th><td>{}</td></tr>\n\
         <tr><th>Simulated time</th><td>{} to {} s, communication step {} s, {} exchange</td></tr>",
        escape(&p.scenario),
        p.start_time_s,
        p.stop_time_s,
        p.step_size_s,
        escape(&p.ordering)
    );
    if !p.laws.is_empty() {
        let _ = writeln!(
            html,
            "<tr><th>Laws flown</th><td>{} (each flight sets <code>gnc.control_law</code>)</td></tr>",
            escape(&p.laws.join(", "))
        );
    }
    let _ = writeln!(
        html,
        "<tr><th>Harness</th><td>lander-fmi harness {}, commit <code>{}</code></td></tr>\n\
         <tr><th>Report written</th><td>{} (UTC)</td></tr>\n</table>",
        env!("CARGO_PKG_VERSION"),
        env!("LANDER_COMMIT"),
        utc_now()
    );
    let _ = writeln!(
        html,
        "<h3>FMUs</h3>\n<div class=\"scroll\"><table>\n<tr><th>Instance</th><th>FMU file</th>\
         <th>Model</th><th>GUID</th><th>FMI version</th><th>Model version</th>\
         <th>Generated by</th><th>Generated at</th></tr>"
    );
    for i in &p.instance {
        let _ = writeln!(
            html,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td><code>{}</code></td><td>{}</td><td>{}</td>\
             <td>{}</td><td>{}</td></tr>",
            escape(&i.name),
            escape(&i.fmu),
            escape(&i.model_name),
            escape(&i.guid),
            escape(&i.fmi_version),
            escape(i.version.as_deref().unwrap_or("not given")),
            escape(i.generation_tool.as_deref().unwrap_or("not given")),
            escape(i.generation_date.as_deref().unwrap_or("not given")),
        );
    }
    let _ = writeln!(html, "</table></div>");
    let _ = writeln!(
        html,
        "<h3>Parameters the scenario sets</h3>\n<div class=\"scroll\"><table>\n\
         <tr><th>Instance</th><th>Parameter</th><th>Value</th></tr>"
    );
    for i in &p.instance {
        for Parameter { name, value } in &i.parameter {
            let shown = if i.name == "gnc" && name == "control_law" && !p.laws.is_empty() {
                format!("{value} in the scenario; each flight sets its law (1 coupled, 2 decoupled, 3 reduced)")
            } else {
                value.clone()
            };
            let _ = writeln!(
                html,
                "<tr><td>{}</td><td><code>{}</code></td><td>{}</td></tr>",
                escape(&i.name),
                escape(name),
                escape(&shown)
            );
        }
    }
    let _ = writeln!(html, "</table></div>");
}

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

/// The human name of a `summary.csv` column (the raw name stays in the header's tooltip).
pub fn column_title(name: &str) -> String {
    let fixed = match name {
        "law" => Some("Law"),
        "phi_cmd_deg" => Some("phi_cmd (deg)"),
        "runs" => Some("Runs"),
        "errors" => Some("Errors"),
        "failed_verdicts" => Some("Failed verdicts"),
        "statement" => Some("Requirement statement (90 % confidence)"),
        "ellipse_of" => Some("Ellipse of"),
        "ellipse_semi_major_m" => Some("Ellipse semi-major axis (m)"),
        "ellipse_semi_minor_m" => Some("Ellipse semi-minor axis (m)"),
        "paired_against" => Some("Against"),
        _ => None,
    };
    if let Some(title) = fixed {
        return title.to_owned();
    }
    for (suffix, what) in [
        ("_p95_ub90", "p95 upper bound (90 %)"),
        ("_p9973_ub90", "p99.73 upper bound (90 %)"),
        ("_p50", "median"),
        ("_max", "maximum"),
        ("_influential_inputs", "drivers"),
        ("_paired_median_diff", "minus reference"),
    ] {
        if let Some(metric) = name.strip_suffix(suffix) {
            return format!("{}: {what}", metric_title(metric));
        }
    }
    metric_title(name)
}

/// A metric's name in words, with its unit.
fn metric_title(metric: &str) -> String {
    let known = match metric {
        "max_horizontal_deviation_descent_m" => "Max horizontal deviation, descent (m)",
        "max_horizontal_deviation_m" => "Max horizontal deviation (m)",
        "max_lateral_speed_manoeuvre_mps" => "Max lateral speed, manoeuvre (m/s)",
        "handover_horizontal_speed_mps" => "Horizontal speed at hand-over (m/s)",
        "max_tilt_error_rad" => "Max tilt error (rad)",
        "propellant_used_kg" => "Propellant used (kg)",
        "descent_end_position_error_m" => "Position error, end of descent (m)",
        _ => "",
    };
    if !known.is_empty() {
        return known.to_owned();
    }
    let (stem, unit) = [
        ("_m", "m"),
        ("_mps", "m/s"),
        ("_rad", "rad"),
        ("_kg", "kg"),
        ("_deg", "deg"),
        ("_s", "s"),
    ]
    .into_iter()
    .find_map(|(suffix, unit)| metric.strip_suffix(suffix).map(|stem| (stem, Some(unit))))
    .unwrap_or((metric, None));
    let mut words = stem.replace('_', " ");
    if let Some(first) = words.get(..1) {
        words = first.to_uppercase() + &words[1..];
    }
    match unit {
        Some(unit) => format!("{words} ({unit})"),
        None => words,
    }
}

fn summary_table(path: &Path, html: &mut String) -> anyhow::Result<()> {
    let mut reader = csv::Reader::from_path(path)?;
    let header = reader.headers()?.clone();
    let index: Vec<usize> = SUMMARY_COLUMNS
        .iter()
        .filter_map(|c| header.iter().position(|h| h == *c))
        .collect();
    let _ = writeln!(
        html,
        "<h2 id=\"statistics\">Monte Carlo statistics</h2>\n<p>Per law and phi_cmd; every metric's median, \
         maximum and the 90 %-confidence upper bounds of its p95 and p99.73 (<code>_ub90</code>, \
         empty where the runs cannot support them: 45 and 852 runs are needed) are in \
         <code>summary.csv</code>. The statement is the binomial \
         (Clopper-Pearson) lower bound on the share of runs meeting the scenario's \
         requirement, at 90 % confidence; the ellipse holds 99.73 % of a fitted normal.</p>\
         \n<div class=\"scroll\"><table class=\"stats\">\n<tr>"
    );
    for &i in &index {
        let _ = write!(
            html,
            "<th title=\"{}\"{}>{}</th>",
            escape(&header[i]),
            if &header[i] == "statement" {
                " class=\"statement\""
            } else {
                ""
            },
            escape(&column_title(&header[i]))
        );
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
                // The grid point is an input, shown as the user wrote it (15, not 15.0000);
                // measured values get four decimals so the column lines up.
                Ok(x) if cell.contains('.') && &header[i] != "phi_cmd_deg" => format!("{x:.4}"),
                _ => cell.to_owned(),
            };
            let class = if &header[i] == "statement" {
                " class=\"statement\""
            } else {
                ""
            };
            let _ = write!(html, "<td{class}>{}</td>", escape(&shown));
        }
        let _ = writeln!(html, "</tr>");
    }
    let _ = writeln!(html, "</table></div>");
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
        "<h2 id=\"drivers\">What drives the metrics, and each law against the reference</h2>\n<p>Per cell \
         and metric: the dispersed inputs whose partial rank correlation with the metric \
         differs from zero at the 5 % level, strongest first (PRCC, -1 to 1), and the median \
         of the run-by-run difference from the reference law on the same draws with its \
         distribution-free 90 % interval. Every metric is in <code>summary.csv</code>.</p>\
         \n<div class=\"scroll\"><table class=\"analysis\">\n<tr><th>Law</th>\
         <th>phi_cmd (deg)</th><th>Against</th>"
    );
    for m in ANALYSED_METRICS {
        let _ = write!(
            html,
            "<th title=\"{m}_influential_inputs\">{t}: drivers</th>\
             <th title=\"{m}_paired_median_diff\">{t}: minus reference</th>",
            m = escape(m),
            t = escape(&metric_title(m))
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
    let _ = writeln!(html, "</table></div>");
    Ok(())
}

/// A figure's heading and its place on the page, from its file name: the paper figures in
/// the paper's order (3-D trajectories, ground track, position, body rates), the retarget and
/// Monte Carlo figures after them, any other PNG last, by name. Only the paper scenario's
/// figures name the paper figure they reproduce.
/// `others`: the names of the directory's other PNGs (`X.png` beside `X-replanned.png` is a
/// retarget figure).
pub fn figure_heading(file_name: &str, others: &[String]) -> (u32, String) {
    let stem = file_name.strip_suffix(".png").unwrap_or(file_name);
    let paper = |scenario: &str, n: u32| {
        if scenario == crate::plots::paper::PAPER_SCENARIO {
            format!(" (paper Fig. {n})")
        } else {
            String::new()
        }
    };
    let kinds: [(&str, u32, &str, Option<u32>); 4] = [
        ("-trajectory-3d", 0, "3-D trajectories", Some(3)),
        ("-trajectory", 1, "Ground track and altitude profile", None),
        ("-position", 2, "Position components against time", Some(4)),
        ("-body-rates", 3, "Body angular rates against time", Some(5)),
    ];
    for (suffix, rank, what, fig) in kinds {
        if let Some(scenario) = stem.strip_suffix(suffix) {
            let fig = fig.map(|n| paper(scenario, n)).unwrap_or_default();
            return (rank, format!("{what}, scenario '{scenario}'{fig}"));
        }
    }
    if stem == "monte-carlo" {
        return (
            6,
            "Monte Carlo: each metric against phi_cmd, per law".to_owned(),
        );
    }
    if let Some(scenario) = stem.strip_suffix("-replanned") {
        return (
            5,
            format!("Retarget, scenario '{scenario}': re-planned flights at their own scale"),
        );
    }
    if others.iter().any(|o| *o == format!("{stem}-replanned.png")) {
        return (
            4,
            format!("Retarget, scenario '{stem}': re-planned and target-only-moved flights"),
        );
    }
    let mut words = stem.replace(['-', '_'], " ");
    if let Some(first) = words.get(..1) {
        words = first.to_uppercase() + &words[1..];
    }
    (10, words)
}

/// The heading of a `<scenario>-summary.txt`.
fn summary_heading(file_name: &str) -> String {
    match file_name.strip_suffix("-summary.txt") {
        Some(scenario) => {
            format!("Scenario '{scenario}': metrics, verdicts and requirements per law")
        }
        None => file_name.to_owned(),
    }
}

/// The page's style: the text column at most 1,500 px; a wide table scrolls inside its own
/// container instead of widening the page; the requirement statement keeps a readable width.
const STYLE: &str = "body{font-family:sans-serif;max-width:1500px;margin:auto;padding:1em;\
    box-sizing:border-box} pre{background:#f4f4f4;padding:.8em;overflow-x:auto} \
    .scroll{overflow-x:auto;max-width:100%;margin:.5em 0} \
    table{border-collapse:collapse;font-size:90%;table-layout:auto} \
    td,th{border:1px solid #bbb;padding:.25em .5em;text-align:right;vertical-align:top} \
    th{background:#f0f0f0;min-width:6.5em} td{white-space:nowrap} \
    th.statement,td.statement{min-width:26em;max-width:40em;white-space:normal;text-align:left} \
    table.analysis td{white-space:normal;min-width:9em;text-align:left} \
    table.facts th{text-align:left} table.facts td{text-align:left;white-space:normal} \
    tr.fail{background:#fde2e2} details{margin:.5em 0} \
    img{max-width:100%;height:auto;border:1px solid #ddd;margin:.5em 0}";

/// Under `report.html?check` the page writes whether it overflows the window sideways (for
/// the headless-browser test); otherwise it does nothing.
const CHECK_SCRIPT: &str = "<script>if(location.search.indexOf('check')>=0){\
    window.addEventListener('load',function(){var d=document.documentElement;\
    var p=document.createElement('p');p.id='overflow-check';p.textContent='scrollWidth='+\
    d.scrollWidth+' innerWidth='+window.innerWidth+' fits='+(d.scrollWidth<=window.innerWidth);\
    document.body.appendChild(p);});}</script>";

/// Writes `report.html` into `dir` from the files there; `failed` lists failed flights.
pub fn write(dir: &Path, title: &str, failed: &[String]) -> anyhow::Result<PathBuf> {
    let mut html = format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"viewport\" content=\"width=device-width\">\
         <title>{t}</title>\n<style>{STYLE}</style>{CHECK_SCRIPT}</head><body>\n\
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
    let provenance = dir.join(PROVENANCE_FILE);
    if provenance.is_file() {
        provenance_section(&Provenance::read(&provenance)?, &mut html);
    }
    // A campaign's definition holds what reproduces it: scenario, seed, grid, dispersions,
    // and the FMUs' model names, GUIDs and generation tools.
    let campaign = dir.join("campaign.toml");
    if campaign.is_file() {
        let text = std::fs::read_to_string(&campaign)
            .with_context(|| format!("reading {}", campaign.display()))?;
        let _ = writeln!(
            html,
            "<h2>Campaign definition and versions</h2>\n<details><summary>\
             <code>campaign.toml</code>: scenario, seed, grid, dispersions, FMU GUIDs</summary>\
             <pre>{}</pre></details>",
            escape(&text)
        );
    }
    for path in files(dir, "-summary.txt")? {
        let text = std::fs::read_to_string(&path)?;
        let _ = writeln!(
            html,
            "<h2>{}</h2>\n<pre>{}</pre>",
            escape(&summary_heading(
                &path.file_name().unwrap_or_default().to_string_lossy()
            )),
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
    let pngs = files(dir, ".png")?;
    let names: Vec<String> = pngs
        .iter()
        .map(|p| {
            p.file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    let mut figures: Vec<(u32, String, PathBuf)> = pngs
        .into_iter()
        .map(|path| {
            let name = path
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned();
            let (rank, heading) = figure_heading(&name, &names);
            (rank, heading, path)
        })
        .collect();
    figures.sort_by(|a, b| (a.0, &a.2).cmp(&(b.0, &b.2)));
    if !figures.is_empty() {
        let _ = writeln!(html, "<h2 id=\"figures\">Figures</h2>");
    }
    for (_, heading, path) in figures {
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let data = base64::engine::general_purpose::STANDARD.encode(std::fs::read(&path)?);
        let _ = writeln!(
            html,
            "<h3>{h}</h3>\n<img alt=\"{h} ({n})\" src=\"data:image/png;base64,{data}\">",
            h = escape(&heading),
            n = escape(&name)
        );
    }
    let _ = writeln!(html, "</body></html>");
    let out = dir.join(FILE_NAME);
    std::fs::write(&out, html).with_context(|| format!("writing {}", out.display()))?;
    Ok(out)
}

/// The current time, UTC, as xs:dateTime (`YYYY-MM-DDThh:mm:ssZ`).
fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    model_description::iso8601_utc(i64::try_from(secs).unwrap_or(i64::MAX))
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

    #[test]
    fn figures_get_human_headings_in_the_paper_order() {
        let names: Vec<String> = ["retarget.png", "retarget-replanned.png"]
            .map(String::from)
            .to_vec();
        let mut shown: Vec<(u32, String)> = [
            "paper-body-rates.png",
            "paper-position.png",
            "paper-trajectory.png",
            "paper-trajectory-3d.png",
            "monte-carlo.png",
            "retarget.png",
            "retarget-replanned.png",
            "extra_plot.png",
        ]
        .iter()
        .map(|n| figure_heading(n, &names))
        .collect();
        shown.sort();
        let headings: Vec<&str> = shown.iter().map(|(_, h)| h.as_str()).collect();
        assert_eq!(
            headings,
            [
                "3-D trajectories, scenario 'paper' (paper Fig. 3)",
                "Ground track and altitude profile, scenario 'paper'",
                "Position components against time, scenario 'paper' (paper Fig. 4)",
                "Body angular rates against time, scenario 'paper' (paper Fig. 5)",
                "Retarget, scenario 'retarget': re-planned and target-only-moved flights",
                "Retarget, scenario 'retarget': re-planned flights at their own scale",
                "Monte Carlo: each metric against phi_cmd, per law",
                "Extra plot",
            ]
        );
        let (_, landing) = figure_heading("landing-position.png", &[]);
        assert_eq!(
            landing,
            "Position components against time, scenario 'landing'"
        );
    }

    #[test]
    fn the_grid_point_is_shown_as_written_and_metrics_with_four_decimals() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("summary.csv");
        std::fs::write(
            &path,
            "law,phi_cmd_deg,runs,failed_verdicts,max_lateral_speed_manoeuvre_mps_p50\ndecoupled,15.0,10,0,0.123456\n",
        )
        .unwrap();
        let mut html = String::new();
        summary_table(&path, &mut html).unwrap();
        assert!(html.contains("<td>15.0</td>"), "{html}");
        assert!(html.contains("<td>0.1235</td>"), "{html}");
    }

    #[test]
    fn summary_columns_get_human_names() {
        assert_eq!(column_title("phi_cmd_deg"), "phi_cmd (deg)");
        assert_eq!(
            column_title("max_horizontal_deviation_descent_m_p95_ub90"),
            "Max horizontal deviation, descent (m): p95 upper bound (90 %)"
        );
        assert_eq!(
            column_title("final_altitude_m_p50"),
            "Final altitude (m): median"
        );
    }
}
