//! A 1,000-flight Monte Carlo campaign on 2 workers through the C ABI (target:
//! under 30 s), and peak memory after 100 and after 1,000 flights: the campaign streams its
//! rows to disk, so the high-water mark must not grow with the number of flights.
//!
//! `cargo bench -p harness --bench montecarlo` (FMUs from `cargo xtask fmus`). Prints
//! figures; there is no statistical repetition, a campaign is long enough on its own.
use campaign::dispersion::DispersionRanges;
use campaign::runner;
use campaign::{CampaignSpec, Shard};
use lander::laws::Law;
use std::path::{Path, PathBuf};

/// Linux reports CPU times in /proc in USER_HZ, 100 per second on every architecture.
const USER_HZ: f64 = 100.0;

fn proc_status_kib(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(field))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// User + system CPU time of this process so far (s).
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesised command name; utime and stime are fields 14 and 15.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / USER_HZ)
}

fn fmu_dir() -> PathBuf {
    let dir = std::env::var_os("LANDER_FMU_DIR").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/fmu"),
        PathBuf::from,
    );
    assert!(
        dir.join("LanderGnc.fmu").is_file() && dir.join("LanderPlant.fmu").is_file(),
        "no FMUs in {}: run `cargo xtask fmus` first",
        dir.display()
    );
    dir
}

/// 10 phi_cmd points x coupled/decoupled x `runs`: 20 flights per run.
fn spec(runs: u64) -> CampaignSpec {
    CampaignSpec {
        scenario: "paper".into(),
        seed: 1,
        phi_cmd_deg: (0..10).map(|i| 20.0 * f64::from(i)).collect(),
        laws: vec![Law::COUPLED, Law::DECOUPLED],
        runs_per_point: runs,
        dispersions: DispersionRanges::default(),
        sets: Vec::new(),
    }
}

fn campaign(runs: u64, out: &Path) -> (runner::Outcome, f64) {
    let options = runner::RunOptions {
        fmu_dir: fmu_dir(),
        out_dir: out.to_owned(),
        workers: 2,
        shard: Shard::WHOLE,
        progress: false,
    };
    let cpu_before = cpu_seconds().unwrap_or(f64::NAN);
    let outcome = runner::run(&spec(runs), &options).expect("campaign runs");
    let cpu = cpu_seconds().unwrap_or(f64::NAN) - cpu_before;
    (outcome, cpu)
}

fn main() {
    // `cargo bench` passes `--bench`; a filter that excludes us means: do nothing.
    if std::env::args()
        .skip(1)
        .any(|a| !a.starts_with('-') && !"montecarlo".contains(a.as_str()))
    {
        return;
    }
    let dir = tempfile::tempdir().expect("temporary directory");
    println!(
        "montecarlo: 2 workers, {} cores available, paper scenario (17,200 steps of 0.01 s)",
        runner::default_workers()
    );
    let mut last_hwm = 0;
    for runs in [5, 50] {
        let (outcome, cpu) = campaign(runs, &dir.path().join(format!("runs{runs}")));
        let hwm = proc_status_kib("VmHWM:").unwrap_or(0);
        println!(
            "montecarlo/{:>4} flights: {:6.2} s wall, {:5.1} flights/s, {:5.1} ms CPU per flight, \
             {} failed; peak RSS (VmHWM) {:.1} MiB (+{:.1} MiB)",
            outcome.flights,
            outcome.elapsed.as_secs_f64(),
            outcome.flights_per_second(),
            1e3 * cpu / outcome.flights as f64,
            outcome.failed,
            hwm as f64 / 1024.0,
            hwm.saturating_sub(last_hwm) as f64 / 1024.0,
        );
        last_hwm = hwm;
    }
}
