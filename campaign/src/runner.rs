//! Running a campaign (or one shard of it) in parallel ([`crate::parallel`]: one FMU
//! instance pair per worker thread, reused (reset) for every flight it takes; each finished
//! row appended to `manifest.csv` by one writer, which advances the progress bar). Rows are
//! appended in completion order (a killed campaign keeps every finished row); at the end the manifest is
//! rewritten sorted by flight index. Every result is a function of its flight alone, so the
//! finished manifest does not depend on the worker count, the scheduling, sharding (after
//! `merge-mc`) or interruptions (`resume`).
use crate::config::{self, CampaignFile, CampaignSection, Execution, ShardSection};
use crate::definition::{CampaignSpec, Shard};
use crate::flight::{campaign_system, Flyer};
use crate::manifest::{self, Row};
use anyhow::Context;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// How to run a campaign; none of this changes its results.
#[derive(Debug, Clone)]
pub struct RunOptions {
    pub fmu_dir: PathBuf,
    pub out_dir: PathBuf,
    pub workers: usize,
    pub shard: Shard,
    /// Show a progress bar (it still hides itself when stderr is not a terminal).
    pub progress: bool,
}

/// Continuing the campaign in `out_dir` ([`run_resumed`]): its finished rows are kept and
/// only the other flights flown, and `rerun` flight indices flown again (their rows replaced).
#[derive(Debug, Clone, Default)]
pub struct Resume {
    pub rerun: Vec<u64>,
}

/// What a finished campaign run did.
#[derive(Debug, Clone)]
pub struct Outcome {
    pub manifest: PathBuf,
    /// Flights flown by this invocation.
    pub flights: u64,
    /// Of those, the ones that ended in an error.
    pub failed: u64,
    /// Flights already in the manifest of a resumed campaign, kept.
    pub kept: u64,
    pub elapsed: Duration,
    /// Every row of the campaign (or shard), kept and flown, sorted by flight index: what the
    /// manifest holds, for a summary that does not read it back.
    pub rows: Vec<Row>,
}

impl Outcome {
    pub fn flights_per_second(&self) -> f64 {
        self.flights as f64 / self.elapsed.as_secs_f64()
    }
}

/// Runs `options.shard` of `spec`, writing `manifest.csv` and `campaign.toml` into
/// `options.out_dir` (figures are the caller's choice).
pub fn run(spec: &CampaignSpec, options: &RunOptions) -> anyhow::Result<Outcome> {
    run_resumed(spec, options, None)
}

/// [`run`], continuing the campaign already in `options.out_dir` when `resume` is given (a
/// fresh one when there is none there).
pub fn run_resumed(
    spec: &CampaignSpec,
    options: &RunOptions,
    resume: Option<&Resume>,
) -> anyhow::Result<Outcome> {
    spec.validate().map_err(anyhow::Error::msg)?;
    anyhow::ensure!(options.workers > 0, "--workers must be at least 1");
    let started = Instant::now();
    let (system, verdict_spec) = campaign_system(&spec.scenario, &spec.sets, false)?;
    let requirements = lander::scenarios::spec::requirements(&spec.scenario)?;
    // The first instance pair is loaded here, so a bad scenario or FMU directory fails before
    // any file is written; the first worker then takes it over.
    let first = Flyer::new(system.clone(), verdict_spec, &options.fmu_dir)?
        .with_requirements(requirements.clone())?;
    first.laws().check(&spec.laws).map_err(anyhow::Error::msg)?;
    if first.nominal().thrust_scale.is_none() && spec.dispersions.thrust_level_fraction > 0.0 {
        anyhow::bail!(
            "--disp-thrust-frac {}: the plant of scenario '{}' has no engine_thrust_scale \
             parameter to disperse",
            spec.dispersions.thrust_level_fraction,
            spec.scenario
        );
    }
    let manifest_path = options.out_dir.join(manifest::FILE_NAME);
    let total = spec.flight_count();
    let shard = options.shard;
    let previous = match resume {
        Some(resume) => finished_rows(spec, options, &resume.rerun, &manifest_path)?,
        None => None,
    };
    std::fs::create_dir_all(&options.out_dir)
        .with_context(|| format!("creating {}", options.out_dir.display()))?;
    let file = CampaignFile {
        campaign: CampaignSection::from_spec(spec),
        shard: (!options.shard.is_whole()).then_some(ShardSection {
            k: options.shard.k,
            n: options.shard.n,
        }),
        execution: Execution {
            workers: Some(options.workers),
            merged_from: Vec::new(),
        },
        versions: config::versions(first.simulation()),
    };
    file.write(&options.out_dir.join(config::FILE_NAME))?;
    let (mut writer, done, mut rows) = match previous {
        None => (
            manifest::Writer::create(&manifest_path)?,
            std::collections::BTreeSet::new(),
            Vec::new(),
        ),
        Some(mut kept) => {
            if kept.rewrite {
                manifest::write_sorted(&manifest_path, &mut kept.rows)?;
            }
            let length = std::fs::metadata(&manifest_path)?.len();
            let keep = if kept.rewrite { length } else { kept.bytes };
            let done = kept.rows.iter().map(|r| r.flight.index).collect();
            (
                manifest::Writer::append(&manifest_path, keep)?,
                done,
                kept.rows,
            )
        }
    };
    // The shard's flights are its stride, computed as they are handed out (a list of them
    // would be 8 bytes per flight before the first one flies: 6 GB for -n 100000000); a
    // resumed campaign skips the finished ones.
    let kept = done.len() as u64;
    let positions = shard.len(total);
    let count = positions.saturating_sub(kept);
    let progress = progress_bar(count, options.progress, "flights");
    let load = || -> anyhow::Result<Flyer> {
        Flyer::new(system.clone(), verdict_spec, &options.fmu_dir)?
            .with_requirements(requirements.clone())
    };
    let mut failed = 0;
    let work = crate::parallel::Work {
        workers: options.workers,
        shard,
        total,
        done: &done,
    };
    let written = crate::parallel::run(
        work,
        first,
        &load,
        &|flyer, index| {
            let row = flyer.fly(&spec.flight(index), &spec.dispersions);
            let failed = row.end.is_error();
            (row, failed)
        },
        |row| {
            failed += u64::from(row.end.is_error());
            writer
                .write(&row)
                .with_context(|| format!("writing {}", manifest_path.display()))?;
            rows.push(row);
            progress.inc(1);
            Ok(())
        },
    );
    progress.finish_and_clear();
    let flights = written?;
    anyhow::ensure!(
        flights == count,
        "wrote {flights} of {count} flights to {}",
        manifest_path.display()
    );
    drop(writer);
    anyhow::ensure!(
        rows.len() as u64 == shard.len(total),
        "{} holds {} rows, the campaign (shard {shard}) {}",
        manifest_path.display(),
        rows.len(),
        shard.len(total)
    );
    manifest::write_sorted(&manifest_path, &mut rows)?;
    Ok(Outcome {
        manifest: manifest_path,
        flights,
        failed,
        kept,
        elapsed: started.elapsed(),
        rows,
    })
}

/// The finished rows a resumed campaign keeps.
struct Kept {
    rows: Vec<Row>,
    /// Bytes of the manifest holding them (as found).
    bytes: u64,
    /// Rows were dropped for --rerun: the file is rewritten instead of cut.
    rewrite: bool,
}

/// For `resume`: the rows of the campaign in `out_dir`, checked to be this campaign's and
/// shard's; `None` when there is no campaign there yet (it starts from scratch).
fn finished_rows(
    spec: &CampaignSpec,
    options: &RunOptions,
    rerun: &[u64],
    manifest_path: &Path,
) -> anyhow::Result<Option<Kept>> {
    let config_path = options.out_dir.join(config::FILE_NAME);
    if !config_path.exists() || !manifest_path.exists() {
        anyhow::ensure!(
            rerun.is_empty(),
            "--rerun: no campaign in {} to re-fly flights of",
            options.out_dir.display()
        );
        return Ok(None);
    }
    let file = CampaignFile::read(&config_path)?;
    anyhow::ensure!(
        file.campaign == CampaignSection::from_spec(spec),
        "--resume: {} defines another campaign than these options (seed, scenario, grid, \
         laws, runs or dispersions differ)",
        config_path.display()
    );
    anyhow::ensure!(
        file.shard() == options.shard,
        "--resume: {} is shard {}, not {}",
        config_path.display(),
        file.shard(),
        options.shard
    );
    let total = spec.flight_count();
    let bad: Vec<String> = rerun
        .iter()
        .filter(|&&i| i >= total || i % options.shard.n != options.shard.k - 1)
        .map(u64::to_string)
        .collect();
    anyhow::ensure!(
        bad.is_empty(),
        "--rerun: flights {} are not in this campaign (0..{total}) and shard {}",
        bad.join(", "),
        options.shard
    );
    let (mut rows, bytes) = manifest::read_complete(manifest_path)?;
    let mut seen = std::collections::BTreeSet::new();
    for row in &rows {
        let index = row.flight.index;
        anyhow::ensure!(
            index < total && row.flight == spec.flight(index),
            "--resume: {} flight {index} is not this campaign's",
            manifest_path.display()
        );
        anyhow::ensure!(
            seen.insert(index),
            "--resume: {} holds flight {index} twice",
            manifest_path.display()
        );
    }
    let before = rows.len();
    rows.retain(|r| !rerun.contains(&r.flight.index));
    let rewrite = rows.len() != before;
    Ok(Some(Kept {
        rows,
        bytes,
        rewrite,
    }))
}

/// A progress bar of `len` runs, counted in `unit` ("flights", "runs"); hidden unless `show`.
pub(crate) fn progress_bar(len: u64, show: bool, unit: &str) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    // `stderr()` draws only when stderr is a terminal.
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(&format!(
        "{{elapsed_precise}} {{wide_bar}} {{pos}}/{{len}} {unit}, {{per_sec}}, ETA {{eta}}"
    )) {
        bar.set_style(style);
    }
    bar
}

/// The default worker count: the cores this process may use.
pub fn default_workers() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The manifest and campaign file of a directory (or of the directory of a manifest); a
/// path that does not exist is named as given, not as the campaign file it would imply.
pub fn locate(path: &Path) -> anyhow::Result<(PathBuf, PathBuf)> {
    anyhow::ensure!(
        path.exists(),
        "{}: no such file or directory (give a campaign's output directory or its {})",
        path.display(),
        manifest::FILE_NAME
    );
    let dir = if path.is_dir() {
        path.to_owned()
    } else {
        path.parent().unwrap_or(Path::new(".")).to_owned()
    };
    let manifest = if path.is_dir() {
        dir.join(manifest::FILE_NAME)
    } else {
        path.to_owned()
    };
    Ok((manifest, dir.join(config::FILE_NAME)))
}
