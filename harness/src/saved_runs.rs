//! `harness run --save-state FILE [--save-at T]` and `--from-state FILE`: the options, the
//! file read before anything is loaded, and what is said about a run saved or continued.
//! The saved run itself is the master's (`cosim/src/master/saved.rs`, docs/saved-runs.md).
use cosim::master::{Checkpoints, RunEnd, SaveRequest, SavedRun};
use cosim::requirements::Kept;
use cosim::supervise::Runner;
use std::path::PathBuf;

#[derive(clap::Args, Clone, Default)]
pub struct StateArgs {
    /// Save the run to FILE at its end (the stop time), or at --save-at: every FMU's state
    /// and the master's, to continue it with --from-state. Refused before the run when an
    /// FMU does not declare it can serialize its state, or an instance is Model Exchange.
    #[arg(long, value_name = "FILE")]
    pub save_state: Option<PathBuf>,
    /// The communication point to save at, in s (one of start + k * step).
    #[arg(long, value_name = "S", requires = "save_state")]
    pub save_at: Option<f64>,
    /// Continue the run saved in FILE (same scenario, FMUs, start time, step and ordering)
    /// to the stop time: the results hold its rows from the saved time on, bit for bit those
    /// of the uninterrupted run; the verdict and the requirements are the uninterrupted
    /// run's (the requirements read the rows before the saved time from FILE).
    #[arg(long, value_name = "FILE")]
    pub from_state: Option<PathBuf>,
}

impl StateArgs {
    /// What the run does about saved runs; the file of --from-state read and checked whole
    /// (its errors name it).
    pub fn checkpoints(&self) -> anyhow::Result<Checkpoints> {
        let resume = match &self.from_state {
            None => None,
            Some(path) => {
                Some(SavedRun::read(path).map_err(|e| anyhow::anyhow!("--from-state: {e}"))?)
            }
        };
        Ok(Checkpoints {
            resume,
            save: self.save_state.clone().map(|path| SaveRequest {
                path,
                at: self.save_at,
            }),
        })
    }

    /// Hands the checkpoints to the run, refused before its first step with the option and
    /// file they come from.
    pub fn set_checkpoints(
        &self,
        simulation: &mut Runner,
        checkpoints: &Checkpoints,
    ) -> anyhow::Result<()> {
        let option = match (&self.from_state, &self.save_state) {
            (Some(path), _) => format!("--from-state {}", path.display()),
            (None, Some(path)) => format!("--save-state {}", path.display()),
            (None, None) => return Ok(()),
        };
        simulation
            .set_checkpoints(checkpoints.clone())
            .map_err(|error| anyhow::anyhow!("{option}: {error}"))
    }

    /// The requirements' rows before the saved point, from the saved run, so that they are
    /// judged over the whole flight.
    pub fn continue_requirements(
        &self,
        mut kept: Kept,
        checkpoints: &Checkpoints,
    ) -> anyhow::Result<Kept> {
        if let (Some(path), Some(saved)) = (&self.from_state, &checkpoints.resume) {
            if let Some(rows) = &saved.rows_before {
                kept.continue_from(rows)
                    .map_err(|e| anyhow::anyhow!("--from-state {}: {e}", path.display()))?;
            }
        }
        Ok(kept)
    }

    /// What a continued run says before its requirements: where it continued from, and
    /// what its requirements were judged over.
    pub fn continued_note(&self, checkpoints: &Checkpoints) -> Option<String> {
        let saved = checkpoints.resume.as_ref()?;
        let path = self.from_state.as_ref()?.display();
        let t = saved.time;
        Some(match saved.rows_before {
            Some(_) => format!(
                "continued from {path} at t = {t} s: the results hold the rows from t = {t} s \
                 on; the requirements are judged over the whole flight, its rows before t = \
                 {t} s read from {path}"
            ),
            None => format!(
                "continued from {path} at t = {t} s: the results and the requirements below \
                 cover t >= {t} s only ({path} holds no rows before it)"
            ),
        })
    }

    /// After the run: the requirements' rows before the saved point added to the saved run
    /// (the worker saved it without them); and where it was saved, or why it was not (a
    /// run that ended before its save point), the second an error.
    pub fn saved_note(
        &self,
        saved_at: Option<f64>,
        end: &RunEnd,
        kept: &Kept,
    ) -> Option<Result<String, String>> {
        let path = self.save_state.as_ref()?;
        let ended = match end {
            RunEnd::Completed => "reached its stop time".to_owned(),
            RunEnd::Terminated { instance, time } => {
                format!("ended at t = {time} s ('{instance}' terminated it)")
            }
        };
        Some(match saved_at {
            Some(time) => {
                let amended =
                    SavedRun::read(path)
                        .map_err(|e| e.to_string())
                        .and_then(|mut saved| {
                            saved.rows_before = Some(kept.rows_before(time));
                            saved.write(path).map_err(|e| e.to_string())
                        });
                match amended {
                    Ok(()) => Ok(format!(
                        "saved the run at t = {time} s to {} (continue it with --from-state)",
                        path.display()
                    )),
                    Err(e) => Err(format!(
                        "--save-state {}: adding the requirements' rows: {e}",
                        path.display()
                    )),
                }
            }
            None => Err(format!(
                "--save-state {}: nothing saved: the run {ended} before its save point{}",
                path.display(),
                self.save_at
                    .map_or_else(String::new, |t| format!(" t = {t} s"))
            )),
        })
    }
}
