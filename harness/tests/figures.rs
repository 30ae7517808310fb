//! The figures and reports `harness paper` and `harness monte-carlo` write: the decimation
//! the plots use keeps every column's extremes, the pages carry human headings in a
//! meaningful order and the paper run's scenario, FMUs and versions.
use crate::common;

use common::harness;
use report::plots::style::decimate;
use std::path::Path;

fn run(args: &[&str]) {
    let output = harness(args);
    assert!(
        output.status.code().is_some_and(|c| c == 0 || c == 3),
        "{args:?}: {output:?}"
    );
}

/// Every column of every law's trajectory, decimated as the figures decimate it (plots
/// 400 to 1,300 px wide: 130 to 440 buckets), keeps its global maximum and minimum: the
/// coupled law's 28.43 deg/s yaw-rate peak is drawn at 28.43.
#[test]
fn the_decimated_series_keep_the_global_max_and_min_of_each_column() {
    let dir = tempfile::tempdir().unwrap();
    run(&["paper", "paper", "--out-dir", dir.path().to_str().unwrap()]);
    let mut peak = f64::NAN;
    for law in ["coupled", "decoupled", "reduced"] {
        let mut reader =
            csv::Reader::from_path(dir.path().join(format!("paper-{law}.csv"))).unwrap();
        let header = reader.headers().unwrap().clone();
        let rows: Vec<Vec<f64>> = reader
            .records()
            .map(|r| r.unwrap().iter().map(|v| v.parse().unwrap()).collect())
            .collect();
        assert!(rows.len() > 10_000, "{}", rows.len());
        for (j, name) in header.iter().enumerate().skip(1) {
            let series: Vec<(f64, f64)> = rows.iter().map(|r| (r[0], r[j])).collect();
            let finite = || series.iter().map(|p| p.1).filter(|v| v.is_finite());
            let (max, min) = (
                finite().fold(f64::NEG_INFINITY, f64::max),
                finite().fold(f64::INFINITY, f64::min),
            );
            for buckets in [130, 333, 440] {
                let kept = decimate(&series, buckets);
                assert!(kept.len() <= 4 * buckets, "{name}: {}", kept.len());
                let has = |v: f64| kept.iter().any(|p| p.1 == v);
                assert!(
                    has(max) && has(min),
                    "{law} {name} at {buckets}: {min} .. {max}"
                );
            }
            if law == "coupled" && name == "plant.omega_body[1]" {
                peak = max.to_degrees();
            }
        }
    }
    assert!(
        (peak - 28.434).abs() < 0.01,
        "coupled yaw-rate peak {peak} deg/s"
    );
}

fn position(html: &str, needle: &str) -> usize {
    html.find(needle)
        .unwrap_or_else(|| panic!("no {needle:?} in the page"))
}

/// The paper page: the scenario, its parameters, the FMUs' GUIDs and versions, the commit
/// and the date; figures under human headings in the paper's order, numbered only for the
/// paper scenario.
#[test]
fn the_paper_report_shows_the_run_and_orders_its_figures() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("paper");
    run(&["paper", "paper", "--out-dir", out.to_str().unwrap()]);
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    let provenance = lander::provenance::Provenance::read(&out.join("provenance.toml")).unwrap();
    assert_eq!(provenance.scenario, "paper");
    // Every law the GNC FMU declares, in its order.
    let system = lander::scenarios::load("paper").unwrap();
    let laws = lander::laws::Laws::of_instance(&system, "gnc", &common::fmu_dir()).unwrap();
    let names: Vec<&str> = laws.all().iter().map(|l| l.name()).collect();
    assert_eq!(provenance.laws, names);
    assert_eq!(names[..3], ["coupled", "decoupled", "reduced"]);
    assert_eq!(provenance.instance.len(), 2);
    position(&html, "Scenario, parameters and versions");
    for instance in &provenance.instance {
        assert!(instance.guid.starts_with('{'), "{instance:?}");
        position(&html, &instance.guid);
        position(&html, &instance.model_name);
    }
    position(&html, "<code>phi_cmd</code>");
    position(&html, "2.6179938779914944");
    position(&html, "each flight sets its law");
    position(&html, report::html::COMMIT);
    position(&html, "(UTC)");
    let order = [
        "<h3>3-D trajectories, scenario 'paper' (paper Fig. 3)</h3>",
        "<h3>Ground track and altitude profile, scenario 'paper'</h3>",
        "<h3>Position components against time, scenario 'paper' (paper Fig. 4)</h3>",
        "<h3>Body angular rates against time, scenario 'paper' (paper Fig. 5)</h3>",
    ];
    let at: Vec<usize> = order.iter().map(|h| position(&html, h)).collect();
    assert!(at.windows(2).all(|w| w[0] < w[1]), "{at:?}");
    assert!(!html.contains("<h3>paper-"), "a file name as a heading");
    assert!(!html.contains("<h2>paper-summary.txt</h2>"));
    position(
        &html,
        "<h2>Scenario 'paper': metrics, verdicts and requirements per law</h2>",
    );

    let landing = dir.path().join("landing");
    run(&["paper", "landing", "--out-dir", landing.to_str().unwrap()]);
    let html = std::fs::read_to_string(landing.join("report.html")).unwrap();
    position(
        &html,
        "<h3>Position components against time, scenario 'landing'</h3>",
    );
    assert!(
        !html.contains("Fig."),
        "a landing figure with a paper figure number"
    );
}

/// The Monte Carlo page: human column names (the CSV names only in tooltips), the tables in
/// scroll containers, the statement column given a readable width.
#[test]
fn the_monte_carlo_report_has_human_headers_in_scroll_containers() {
    let dir = tempfile::tempdir().unwrap();
    run(&[
        "monte-carlo",
        "-n",
        "3",
        "--phi-cmd-deg",
        "0,150",
        "-q",
        "--out-dir",
        dir.path().to_str().unwrap(),
    ]);
    let html = std::fs::read_to_string(dir.path().join("report.html")).unwrap();
    position(&html, "<div class=\"scroll\"><table class=\"stats\">");
    position(&html, ">Requirement statement (90 % confidence)</th>");
    position(&html, ">Max horizontal deviation, descent (m): median</th>");
    position(&html, "th.statement,td.statement{min-width:26em");
    assert!(!html.contains("<th>statement</th>") && !html.contains(">phi_cmd_deg</th>"));
    assert!(!html.contains(">max_horizontal_deviation_descent_m_p50</th>"));
    position(
        &html,
        "<h3>Monte Carlo: each metric against phi_cmd, per law</h3>",
    );
    assert!(Path::new(&dir.path().join("monte-carlo.png")).is_file());
}
