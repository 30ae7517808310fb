//! A scenario campaign loaded and checked: the scenario, its requirements, the plan of its
//! runs and the manifest's columns; and one run flown on a loaded simulation.
use crate::generic::manifest::{Layout, Row, ERROR, FAIL, PASS};
use crate::generic::plan::{Plan, RunId};
use crate::generic::target::{Setting, Target};
use cosim::master::{RunEnd, Trajectory};
use cosim::requirements::Requirement;
use cosim::supervise::Runner;
use cosim::system::campaign_table::{self as declaration, Declaration};
use cosim::system::SystemDescription;
use std::path::Path;

/// The command line's changes to the scenario's `[campaign]` table.
#[derive(Debug, Clone, Copy, Default)]
pub struct Overrides {
    pub seed: Option<u64>,
    pub runs: Option<u64>,
}

#[derive(Debug, Clone)]
pub struct Campaign {
    /// The scenario file, absolute.
    pub scenario: String,
    pub declaration: Declaration,
    pub plan: Plan,
    pub requirements: Vec<Requirement>,
    pub layout: Layout,
    /// The system as each run records it: the requirements' signals only.
    pub system: SystemDescription,
    /// How each input (in the plan's order: swept, then dispersed) is set.
    pub settings: Vec<Setting>,
}

/// The TOML file that declares the campaign of `scenario`: the scenario itself, or for an
/// SSP scenario (`.ssd`, `.ssp`) or one FMU alone its sidecar `NAME.campaign.toml` beside it,
/// which holds the
/// `[campaign]` table and the `[[requirement]]`s an SSD has no place for.
pub fn declared_in(scenario: &Path) -> std::path::PathBuf {
    match scenario.extension().and_then(|e| e.to_str()) {
        Some("ssd" | "ssp" | "fmu") => {
            let stem = scenario.file_stem().unwrap_or_default().to_string_lossy();
            scenario.with_file_name(format!("{stem}.campaign.toml"))
        }
        _ => scenario.to_owned(),
    }
}

impl Campaign {
    /// Reads the campaign of the scenario file `scenario` ([`declared_in`]) and checks it whole, the FMUs'
    /// declarations included (loaded from `fmu_dir`): every problem in one error. Returns the
    /// loaded simulation too, which the first worker takes over.
    pub fn load(
        scenario: &str,
        overrides: Overrides,
        fmu_dir: &Path,
    ) -> anyhow::Result<(Self, Runner)> {
        let path = Path::new(scenario);
        let declared = declared_in(path);
        let text = std::fs::read_to_string(&declared)
            .map_err(|e| anyhow::anyhow!("{}: cannot read it: {e}", declared.display()))?;
        let at = declared.display();
        let mut declaration = declaration::from_toml(&text)
            .map_err(|e| anyhow::anyhow!("{at}: {e}"))?
            .ok_or_else(|| {
                anyhow::anyhow!(
                    "{at} has no [campaign] table (docs/campaigns.md says how to declare one)"
                )
            })?;
        declaration.seed = overrides.seed.unwrap_or(declaration.seed);
        declaration.runs = overrides.runs.unwrap_or(declaration.runs);
        let mut problems = Vec::new();
        let plan = Plan::new(&declaration).map_err(|p| problems.extend(p)).ok();
        let (mut system, _) = lander::scenarios::spec::load(scenario)?;
        let requirements =
            cosim::requirements::from_toml(&text).map_err(|e| anyhow::anyhow!("{at}: {e}"))?;
        if requirements.is_empty() {
            // Without a requirement every run that ends would count as a pass: a pass rate
            // of runs nobody judged.
            problems.push(format!(
                "{at} declares no [[requirement]]: a campaign judges each run by at least one \
                 (docs/campaigns.md says how to declare them)"
            ));
        }
        let mut record = Vec::new();
        cosim::requirements::record_signals(&mut record, &requirements);
        system.record = Some(record);
        // The targets are checked against the FMUs even when the table has other problems,
        // so that every problem is named at once.
        let swept = declaration.sweep.iter().map(|s| (&s.parameter, true));
        let dispersed = declaration.dispersion.iter().map(|d| (&d.parameter, false));
        let targets: Vec<_> = swept
            .chain(dispersed)
            .filter_map(|(text, swept)| Some((Target::parse(text).ok()?, swept)))
            .collect();
        let mut settings = Vec::new();
        let runner = match Runner::new(system.clone(), fmu_dir) {
            Ok(runner) => {
                for (target, swept) in &targets {
                    let values = plan.as_ref().and_then(|plan| {
                        let at = plan.sweeps.iter().find(|(t, _)| t == target);
                        at.map(|(_, values)| values.as_slice())
                    });
                    let found = check(target, *swept, values.unwrap_or_default(), &runner);
                    match found {
                        Ok(setting) => settings.push(setting),
                        Err(found) => problems.extend(found),
                    }
                }
                Some(runner)
            }
            Err(error) => {
                problems.push(error.to_string());
                None
            }
        };
        let (Some(runner), Some(plan), true) = (runner, plan, problems.is_empty()) else {
            anyhow::bail!(
                "{scenario}: {} problem{} in its campaign:\n  {}",
                problems.len(),
                if problems.len() == 1 { "" } else { "s" },
                problems.join("\n  ")
            );
        };
        let layout = Layout {
            inputs: plan.input_names(),
            requirements: requirements.iter().map(|r| r.name.clone()).collect(),
        };
        let scenario = std::path::absolute(path)?.display().to_string();
        Ok((
            Self {
                scenario,
                declaration,
                plan,
                requirements,
                layout,
                system,
                settings,
            },
            runner,
        ))
    }

    /// Flies run `id` on `runner` (this campaign's system, loaded), recording into
    /// `trajectory`. A failure is the run's result ("error"), not an error here.
    pub fn fly(&self, runner: &mut Runner, id: RunId, trajectory: &mut Trajectory) -> Row {
        let inputs: Vec<(&Target, f64)> = self.plan.inputs(&id);
        let values = inputs.iter().map(|(_, v)| *v).collect();
        let mut row = Row {
            id,
            inputs: values,
            end: ERROR.into(),
            verdict: ERROR.into(),
            robustness: vec![f64::NAN; self.requirements.len()],
            error: String::new(),
        };
        trajectory.names = runner.column_names().to_vec();
        trajectory.times.clear();
        trajectory.values.clear();
        let mut attempt = || -> anyhow::Result<RunEnd> {
            for ((target, value), setting) in inputs.iter().zip(&self.settings) {
                match target {
                    Target::Parameter { instance, variable } => {
                        runner.set_parameter(instance, variable, setting.value(*value))?
                    }
                    Target::EventTime { event } | Target::EventValue { event } => {
                        if let Some(change) = target.change(*setting, *value) {
                            runner.change_event(event, &change)?
                        }
                    }
                }
            }
            Ok(runner.run(trajectory)?)
        };
        match attempt() {
            Err(error) => row.error = format!("{error:#}"),
            Ok(end) => {
                row.end = match end {
                    RunEnd::Completed => "completed".into(),
                    RunEnd::Terminated { instance, .. } => format!("terminated:{instance}"),
                };
                let judged = cosim::requirements::judge(&self.requirements, trajectory);
                row.robustness = judged.iter().map(|j| j.robustness.value).collect();
                row.verdict = if judged.iter().all(|j| j.holds()) {
                    PASS
                } else {
                    FAIL
                }
                .into();
            }
        }
        row
    }
}

/// How `runner`'s system takes `target`'s numbers, or every problem of it: a target it cannot
/// set, an integer drawn rather than swept, a swept value it cannot take.
fn check(
    target: &Target,
    swept: bool,
    values: &[f64],
    runner: &Runner,
) -> Result<Setting, Vec<String>> {
    let setting = target
        .check(runner.system(), |i| runner.description(i).1)
        .map_err(|problem| vec![problem])?;
    let problems: Vec<String> = match (swept, setting) {
        (false, Setting::Integer { .. }) => vec![format!(
            "[[campaign.dispersion]] {target}: an integer is swept over its values, not drawn"
        )],
        (false, Setting::Real) => Vec::new(),
        (true, _) => values
            .iter()
            .filter_map(|&v| target.value_problem(setting, runner.system(), v))
            .map(|problem| format!("[[campaign.sweep]] {problem}"))
            .collect(),
    };
    match problems.is_empty() {
        true => Ok(setting),
        false => Err(problems),
    }
}
