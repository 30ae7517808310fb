//! `harness run X.fmu --check-reference`, and every FMU of `harness test` that carries
//! references: the FMU flown over each experiment of its FMI-LS-REF files (its times, its
//! stimuli as `--input`), each reference signal judged in its tube, a line and a JUnit test
//! case per signal.
use super::{Flown, RunRequest};
use anyhow::Context;
use cosim::reference::{Checked, References, ToleranceOverrides, Tolerances};
use cosim::requirements::junit::{Case, Outcome};
use std::path::{Path, PathBuf};

/// The tolerances of the reference check, over the ones an FMU's references carry.
#[derive(clap::Args, Clone, Default)]
pub struct ToleranceArgs {
    /// Half-width of a reference's tube as a fraction of the reference's range over the
    /// run (of its value when it is constant); default 0.1, fmpy's `dy`, unless the
    /// reference carries its own.
    #[arg(long, value_name = "FRACTION")]
    pub reference_rel_tol: Option<f64>,
    /// The least half-width of a reference's tube, in the signal's unit; default 0.
    #[arg(long, value_name = "VALUE")]
    pub reference_abs_tol: Option<f64>,
    /// How far in time the tube reaches either side, as a fraction of the run; default
    /// 0.01 (fmpy's 21 of 1000 points).
    #[arg(long, value_name = "FRACTION")]
    pub reference_time_tol: Option<f64>,
}

impl ToleranceArgs {
    fn overrides(&self) -> anyhow::Result<ToleranceOverrides> {
        let given = ToleranceOverrides {
            relative: self.reference_rel_tol,
            absolute: self.reference_abs_tol,
            time: self.reference_time_tol,
        };
        let problems = given.problems([
            "--reference-rel-tol",
            "--reference-abs-tol",
            "--reference-time-tol",
        ]);
        if !problems.is_empty() {
            anyhow::bail!("{}", problems.join("\n"));
        }
        Ok(given)
    }
}

/// The references of the FMU `request` runs: an error naming every problem of them, `None`
/// when it carries none.
fn references(request: &RunRequest) -> anyhow::Result<Option<References>> {
    let path = Path::new(&request.scenario);
    cosim::reference::read(path).map_err(|problems| {
        anyhow::anyhow!(
            "{}: its FMI-LS-REF references cannot be used:\n  {}",
            path.display(),
            problems.join("\n  ")
        )
    })
}

/// `request` flown by `fly` over each experiment of its FMU's references and judged
/// against them. An FMU without references is flown as it is when `required` is false, and
/// refused when it is true (`--check-reference`).
pub fn run_checked(
    request: &RunRequest,
    tolerances: &ToleranceArgs,
    required: bool,
    fly: impl Fn(&RunRequest) -> anyhow::Result<Flown>,
) -> anyhow::Result<Flown> {
    let is_fmu = Path::new(&request.scenario)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("fmu"));
    if !is_fmu {
        anyhow::ensure!(
            !required,
            "--check-reference: '{}' is no .fmu; references are carried by an FMU, run alone",
            request.scenario
        );
        return fly(request);
    }
    // Every problem of the command line and of the FMU's files at once.
    let (given, found) = match (tolerances.overrides(), references(request)) {
        (Ok(given), Ok(found)) => (given, found),
        (given, found) => {
            let errors: Vec<String> = [given.err(), found.err()]
                .into_iter()
                .flatten()
                .map(|e| format!("{e:#}"))
                .collect();
            anyhow::bail!("{}", errors.join("\n"));
        }
    };
    let Some(references) = found else {
        anyhow::ensure!(
            !required,
            "--check-reference: {} carries no FMI-LS-REF references (no {}/{} or {})",
            request.scenario,
            cosim::reference::archive::DIR,
            cosim::reference::archive::MANIFEST,
            cosim::reference::archive::EXPERIMENTS
        );
        return fly(request);
    };
    let system = cosim::system::single::of_fmu(Path::new(&request.scenario))?;
    let instance = system.instances[0].name.clone();
    let (_, description) = fmi_import::read_description(Path::new(&request.scenario))?;
    let is_variable = |name: &str| description.variable(name).is_some();
    let several = references.experiments.len() > 1;
    let mut flown_all: Option<Flown> = None;
    for experiment in &references.experiments {
        // The stimuli go to the run as any `--input` table does: from a file.
        let scratch = tempfile::tempdir().context("creating a folder for the stimuli")?;
        let run = experiment_request(request, experiment, several, scratch.path())?;
        let mut flown = fly(&run)?;
        if flown.exit_code != lander::verdict::EXIT_ERROR {
            let result = cosim::results::read(&run.out)
                .with_context(|| format!("reading back {}", run.out.display()))?;
            let window = (
                run.start_time.unwrap_or(system.start_time),
                run.stop_time.unwrap_or(system.stop_time),
            );
            let checked = cosim::reference::compare(
                &result,
                Some(&instance),
                experiment,
                window,
                &Tolerances::default(),
                &given,
                &is_variable,
            );
            print!("{}", report(&checked));
            flown.suite.cases.extend(checked.cases());
            let step = run.step_size.unwrap_or(system.step_size);
            judge_end(&mut flown, experiment, &result, window.1, step);
        }
        flown_all = Some(match flown_all {
            None => flown,
            Some(mut all) => {
                all.exit_code = all.exit_code.max(flown.exit_code);
                all.suite.time_s += flown.suite.time_s;
                for mut case in flown.suite.cases {
                    if !case.name.starts_with("reference ") {
                        case.name = format!("{} ({})", case.name, experiment.name);
                    }
                    all.suite.cases.push(case);
                }
                all
            }
        });
    }
    Ok(flown_all.expect("an FMU's references hold an experiment"))
}

/// Whether the run ended where its references do, in `flown`'s verdict case or a case of
/// its own; then its exit code from all its cases (a run of one FMU has no requirements:
/// its cases are the whole verdict).
fn judge_end(
    flown: &mut Flown,
    experiment: &cosim::reference::Experiment,
    result: &cosim::master::Trajectory,
    stop: f64,
    step: f64,
) {
    match cosim::reference::early_end(experiment, result, stop, step) {
        None => {}
        // The FMU stopped the run where its references say it does: the verdict's
        // expected completion is not this experiment's.
        Some(Ok(end)) => {
            for case in flown.suite.cases.iter_mut().filter(|c| c.name == "verdict") {
                case.outcome = Outcome::Passed;
                case.detail = format!(
                    "{} (stopped at t = {end} s, where its references end)",
                    case.detail
                );
            }
            println!(
                "reference {}: the run stopped at t = {end} s, where its references end",
                experiment.name
            );
        }
        Some(Err(why)) => {
            println!("reference {}: FAIL: {why}", experiment.name);
            flown.suite.cases.push(Case {
                name: format!("reference {}: end", experiment.name),
                time_s: 0.0,
                outcome: Outcome::Failed(why.clone()),
                detail: why,
            });
        }
    }
    let failed = flown
        .suite
        .cases
        .iter()
        .any(|c| !matches!(c.outcome, Outcome::Passed));
    flown.exit_code = if failed {
        lander::verdict::EXIT_FAILED_VERDICT
    } else {
        lander::verdict::EXIT_OK
    };
}

/// The run of one experiment: its times and stimuli where the command line set none; its
/// own results file when the FMU has several experiments.
fn experiment_request(
    request: &RunRequest,
    experiment: &cosim::reference::Experiment,
    several: bool,
    scratch: &Path,
) -> anyhow::Result<RunRequest> {
    let mut run = request.clone();
    run.start_time = run.start_time.or(experiment.start_time);
    run.stop_time = run.stop_time.or(experiment.stop_time);
    run.step_size = run.step_size.or(experiment.step_size);
    if let (None, Some(stimuli)) = (&run.input, &experiment.stimuli) {
        let file = scratch.join(
            Path::new(&stimuli.source)
                .file_name()
                .unwrap_or("stimuli.csv".as_ref()),
        );
        std::fs::write(&file, &stimuli.text)
            .with_context(|| format!("writing {}", file.display()))?;
        run.input = Some(file);
    }
    if several {
        run.out = suffixed(&run.out, &experiment.name);
    }
    Ok(run)
}

/// `dir/run.csv` as `dir/run-<name>.csv`, the name reduced to what a file name carries.
fn suffixed(out: &Path, name: &str) -> PathBuf {
    let name: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let stem = out
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let file = match out.extension() {
        Some(ext) => format!("{stem}-{name}.{}", ext.to_string_lossy()),
        None => format!("{stem}-{name}"),
    };
    out.with_file_name(file)
}

/// The verdict of an experiment, then a line per signal and per note.
fn report(checked: &Checked) -> String {
    let failed = checked.signals.iter().filter(|s| !s.passes()).count();
    let mut text = format!(
        "reference {}: {} ({} signals, {failed} failed)\n",
        checked.experiment,
        if failed == 0 { "pass" } else { "FAIL" },
        checked.signals.len()
    );
    for signal in &checked.signals {
        text.push_str(&format!("  {}\n", signal.describe()));
    }
    for note in &checked.notes {
        text.push_str(&format!("  note: {note}\n"));
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_experiments_results_file_carries_its_name() {
        assert_eq!(
            suffixed(Path::new("out/run.csv"), "step 2"),
            Path::new("out/run-step_2.csv")
        );
        assert_eq!(suffixed(Path::new("run"), "a"), Path::new("run-a"));
    }
}
