//! The co-simulation master: instantiates the FMUs of a [`SystemDescription`], applies the
//! parameters, initializes, and steps them with a fixed communication step.
//!
//! - Time: `t_k = start + k h` from an integer step counter, never accumulated, so every
//!   communication point is exact to one rounding. The last step is shortened to land on the
//!   stop time when `(stop - start) / h` is not an integer.
//! - Ordering ([`Ordering`]): Gauss-Seidel (default) visits instances in declaration order at
//!   each communication point, setting each one's inputs from the freshest outputs (those an
//!   earlier instance consumes are read right after the step) and reading its outputs, before
//!   all step;
//!   with the controller declared first, the plant's command over `[t_k, t_k+1]` is computed
//!   from the plant's state at `t_k` (no added delay). Jacobi sets every input from the
//!   outputs read after the previous step, so a direct-feedthrough controller's command lags
//!   one step, as in fmpy's `simulate_ssp`.
//! - Status: `fmi2Discard` with `fmi2Terminated` (touchdown), or FMI 3.0's `terminateSimulation`,
//!   ends the run cleanly at the step's `lastSuccessfulTime`, that row recorded last;
//!   `Error`/`Fatal` ends it with the FMU's log in the error.
//! - FMI 3.0: an instance whose outputs are read right after its inputs are set (Gauss-Seidel,
//!   an output depending on a connected input) is instantiated for same-instant feedthrough
//!   (Event Mode); every other one has its outputs read before its inputs are set, as Step Mode
//!   requires (see `loader::InstanceOptions` and harness/README.md).
//! - [`Conventions`]: the initial inputs and the time arithmetic of other masters (fmpy's
//!   `simulate_ssp`, libcosim), so a run can reproduce theirs exactly; the default is the above.
mod buffer;
mod checkpoint;
mod conventions;
mod events;
mod finite;
mod linearize;
mod loops;
mod model_exchange;
mod resolve;
mod saved;
mod table;
mod terminals;
mod text;

pub use conventions::{Conventions, InitialInputs, TimeGrid};
pub use events::{outcome as event_outcome, outcomes as event_outcomes};
pub use linearize::Jacobians;
pub use model_exchange::{EventCounts, MeError, SolverSettings};
pub use resolve::Port;
pub use saved::{
    check as check_checkpoints, refusal as saved_run_refusal, Checkpoints, SaveRequest, SavedError,
    SavedInstance, SavedIo, SavedRows, SavedRun,
};

use crate::system::{Ordering, ParamValue, SystemDescription};
use buffer::{block_index, word_slots, Buffer, BOOLEAN, INTEGER, REAL};
use fmi_import::VariableKind;
use fmi_import::{CallError, Fmi3Type, FmiError, Fmu, InstanceOptions, StepStatus};
use std::path::{Path, PathBuf};

/// Why a run could not start or did not finish.
#[derive(Debug, thiserror::Error)]
pub enum MasterError {
    #[error("cannot load FMU {path} for instance '{instance}'")]
    Load {
        instance: String,
        path: PathBuf,
        #[source]
        source: Box<fmi_import::LoadError>,
    },
    #[error(
        "FMU file(s) not found:\n  {}\nRelative FMU paths are looked up beside the scenario \
         file, then in the FMU directory, {}{}: set it with --fmu-dir (repeatable) or the \
         LANDER_FMU_DIR environment variable (`cargo xtask fmus` builds ours into target/fmu).",
        missing.join("\n  "),
        fmu_dir.display(),
        more_fmu_dirs()
            .iter()
            .map(|d| format!(", then {}", d.display()))
            .collect::<String>()
    )]
    MissingFmus {
        fmu_dir: PathBuf,
        missing: Vec<String>,
    },
    #[error("system '{system}' does not match its FMUs:\n  {}", problems.join("\n  "))]
    Resolve {
        system: String,
        problems: Vec<String>,
    },
    #[error("instance '{instance}': {context}")]
    Call {
        instance: String,
        context: String,
        #[source]
        source: Box<CallError>,
    },
    #[error("instance '{instance}' failed at t = {time}: {source}")]
    Step {
        instance: String,
        time: f64,
        #[source]
        source: Box<FmiError>,
    },
    #[error("instance '{instance}' (Model Exchange) failed in the step from t = {time}: {source}")]
    ModelExchange {
        instance: String,
        time: f64,
        #[source]
        source: Box<model_exchange::MeError>,
    },
    /// A Real the master read (an output exchanged or recorded, a recorded calculated
    /// parameter, a final value) was NaN or infinite with status OK, and the system does not
    /// allow it for that variable. The row of `time` is the last recorded.
    #[error(
        "instance '{instance}' returned '{variable}' = {value} at t = {time} with status OK: a \
         value that is not a finite number ends the run (its row is the last recorded); if \
         the FMU means \"no value\" by it, list '{instance}.{variable}' in allow_non_finite"
    )]
    NonFinite {
        instance: String,
        variable: String,
        time: f64,
        value: f64,
    },
    /// The recorder could not keep a row (a full disk, a closed pipe): the run stops there
    /// rather than simulate on for nothing.
    #[error("recording the row at t = {time} failed, so the run stopped there: {reason}")]
    Record { time: f64, reason: String },
    /// A saved run could not be continued or saved (see `saved.rs`).
    #[error("{message}")]
    Checkpoint { message: String },
    /// An error the supervised worker process met, as it told it (see [`crate::supervise`]).
    #[error("{message}")]
    Worker { message: String },
    /// The supervised worker process ended without finishing: a crash, an exit, a timeout.
    #[error(transparent)]
    Abnormal(Box<crate::abnormal::Abnormal>),
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum RunEnd {
    /// Reached the stop time.
    Completed,
    /// An instance stopped the simulation (`fmi2Discard` + `fmi2Terminated`, or FMI 3.0's
    /// `terminateSimulation`), e.g. touchdown.
    Terminated { instance: String, time: f64 },
}

/// Receives the recorded columns at every communication point.
pub trait Recorder {
    fn record(&mut self, time: f64, values: &[f64]);
    /// Called once before a run with (at least, in general) the number of rows it will
    /// record and their width, so a recorder that keeps rows can allocate once.
    fn reserve(&mut self, _rows: usize, _width: usize) {}
    /// Why this recorder can keep no more rows, once that is so; the master checks after
    /// every row and stops the run with it.
    fn failure(&self) -> Option<String> {
        None
    }
    /// The value of the String or Binary column `column` (a Binary in hex), given before the
    /// `record` of the first row that has it, and again whenever it changes; the slot of
    /// such a column in `values` is 0. A recorder that keeps numbers only ignores it.
    fn record_text(&mut self, _column: usize, _text: &str) {}
}

/// The most values [`Trajectory::reserve`] sets aside ahead of a run (256 MiB of f64): a
/// longer run grows as it goes instead of claiming its whole length at the start.
const MAX_RESERVED_VALUES: usize = 1 << 25;

/// Keeps every recorded row in memory.
#[derive(Debug, Default, Clone)]
pub struct Trajectory {
    /// `instance.variable` per column.
    pub names: Vec<String>,
    pub times: Vec<f64>,
    /// Row-major: `rows[k * names.len() + j]`.
    pub values: Vec<f64>,
}

impl Recorder for Trajectory {
    fn record(&mut self, time: f64, values: &[f64]) {
        self.times.push(time);
        self.values.extend_from_slice(values);
    }

    fn reserve(&mut self, rows: usize, width: usize) {
        let rows = rows.min(MAX_RESERVED_VALUES / width.max(1));
        self.times.reserve(rows);
        self.values.reserve(rows * width);
    }
}

impl Trajectory {
    pub fn column_index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
    /// The column named `name`, or `None`.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let j = self.column_index(name)?;
        let width = self.names.len();
        Some(self.values.iter().skip(j).step_by(width).copied().collect())
    }
    pub fn row(&self, k: usize) -> &[f64] {
        let width = self.names.len();
        &self.values[k * width..(k + 1) * width]
    }
    pub fn len(&self) -> usize {
        self.times.len()
    }
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }
}

/// Values of one exchange type of one instance, with their value references, so each
/// exchange is one `fmi2Set*`/`fmi2Get*` call per type.
///
/// The slots from `feedthrough_start` on hold outputs that may depend on an input of their
/// instance; those before it do not, so after a step they stay valid when inputs are set.
#[derive(Debug, Default)]
struct Block<T> {
    vrs: Vec<u32>,
    values: Vec<T>,
    feedthrough_start: usize,
}

impl<T: Copy + Default> Block<T> {
    /// Slot of `vr`, added if new.
    fn slot(&mut self, vr: u32) -> usize {
        match self.vrs.iter().position(|&v| v == vr) {
            Some(i) => i,
            None => {
                self.vrs.push(vr);
                self.values.push(T::default());
                self.vrs.len() - 1
            }
        }
    }

    /// Moves the slots flagged in `feedthrough` after the others (each group keeping its
    /// order) and returns where each old slot went.
    fn partition(&mut self, feedthrough: &[bool]) -> Vec<usize> {
        let order: Vec<usize> = (0..self.vrs.len())
            .filter(|&i| !feedthrough[i])
            .chain((0..self.vrs.len()).filter(|&i| feedthrough[i]))
            .collect();
        let mut new_slot = vec![0; order.len()];
        for (new, &old) in order.iter().enumerate() {
            new_slot[old] = new;
        }
        self.vrs = order.iter().map(|&old| self.vrs[old]).collect();
        self.values = order.iter().map(|&old| self.values[old]).collect();
        self.feedthrough_start = feedthrough.iter().filter(|&&f| !f).count();
        new_slot
    }
}

/// The exchange buffers of one side (inputs or outputs) of one instance. Booleans are kept
/// as `fmi2Boolean` (0 or 1), the FMI representation, so they pass through without conversion.
/// The FMI 3.0 types that travel as words (`fmi_import::word`) have a buffer of their own,
/// so the Real path carries nothing more than before.
#[derive(Debug, Default)]
struct Io {
    real: Block<f64>,
    integer: Block<i32>,
    boolean: Block<i32>,
    word: Block<u64>,
    text: text::Texts,
    /// It has words or texts, which take paths of their own (set once its slots are).
    others: bool,
    /// The word slots of Float32 outputs, checked for values that are not numbers as the
    /// Real ones are.
    float32: Vec<usize>,
}

impl Io {
    /// Where the feedthrough slots of the buffer of `buffer` start.
    fn feedthrough_start(&self, buffer: Buffer) -> usize {
        match buffer {
            Buffer::Real => self.real.feedthrough_start,
            Buffer::Integer => self.integer.feedthrough_start,
            Buffer::Boolean => self.boolean.feedthrough_start,
            Buffer::Word(_) => self.word.feedthrough_start,
            // Every text output counts as depending on every input.
            Buffer::String | Buffer::Binary => 0,
        }
    }

    /// Whether an output may depend on the unit's inputs (slots partitioned, see
    /// [`feedthrough_last`]): a read of [`Part::Feedthrough`] has something to read.
    fn has_feedthrough(&self) -> bool {
        self.others
            || self.real.feedthrough_start < self.real.vrs.len()
            || self.integer.feedthrough_start < self.integer.vrs.len()
            || self.boolean.feedthrough_start < self.boolean.vrs.len()
    }

    /// Notes whether it has words or texts, once its slots are all taken.
    fn note_others(&mut self) {
        self.others = !self.word.vrs.is_empty() || !self.text.is_empty();
    }

    fn slot(&mut self, port: &Port) -> usize {
        match Buffer::of(port) {
            Buffer::Real => self.real.slot(port.value_reference),
            Buffer::Boolean => self.boolean.slot(port.value_reference),
            Buffer::Integer => self.integer.slot(port.value_reference),
            Buffer::Word(_) => self.word.slot(port.value_reference),
            Buffer::String => self.text.slot(false, port.value_reference),
            Buffer::Binary => self.text.slot(true, port.value_reference),
        }
    }
}

/// Which outputs of a unit a read covers.
#[derive(Debug, Clone, Copy)]
enum Part {
    All,
    /// Those that do not depend on the unit's inputs.
    Stable,
    /// Those that may.
    Feedthrough,
}

impl Part {
    fn of<T>(self, block: &Block<T>) -> std::ops::Range<usize> {
        match self {
            Part::All => 0..block.vrs.len(),
            Part::Stable => 0..block.feedthrough_start,
            Part::Feedthrough => block.feedthrough_start..block.vrs.len(),
        }
    }
}

/// What Gauss-Seidel reads of a unit's outputs right after its step: nothing when no
/// earlier unit consumes them (they are read at its turn), else what those consume.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum AfterStep {
    Nothing,
    /// The outputs independent of its inputs: its feedthrough outputs are read again at its
    /// turn anyway, after its inputs are set.
    Stable,
    All,
}

impl AfterStep {
    /// Per unit, from the connections (slots already partitioned, see [`feedthrough_last`]).
    fn of(links: &[Link], outputs: &[Io]) -> Vec<AfterStep> {
        let mut after = vec![AfterStep::Nothing; outputs.len()];
        for link in links.iter().filter(|l| l.to_unit < l.from_unit) {
            let feedthrough_start = outputs[link.from_unit].feedthrough_start(link.buffer);
            let needed = if link.from_slot < feedthrough_start {
                AfterStep::Stable
            } else {
                AfterStep::All
            };
            let unit = &mut after[link.from_unit];
            *unit = (*unit).max(needed);
        }
        after
    }
}

/// A scalar connection after resolution: output slot of one unit to input slot of another.
#[derive(Debug, Clone, Copy)]
struct Link {
    buffer: Buffer,
    from_unit: usize,
    from_slot: usize,
    to_unit: usize,
    to_slot: usize,
}

/// The connections from one unit into another, resolved once into runs of consecutive
/// output slots copied to consecutive input slots, per exchange buffer, so setting inputs is
/// a few slice copies with no per-link dispatch on the type.
#[derive(Debug, Default)]
struct Copies {
    from_unit: usize,
    real: Vec<SlotRun>,
    integer: Vec<SlotRun>,
    boolean: Vec<SlotRun>,
    word: Vec<SlotRun>,
    /// (binary, from, to): texts copied one by one.
    text: Vec<(bool, usize, usize)>,
    /// Words or texts to copy, on a path of their own.
    others: bool,
}

/// Output slots `from..from + len` to input slots `to..to + len`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct SlotRun {
    from: usize,
    to: usize,
    len: usize,
}

impl SlotRun {
    /// Adds the copy `from -> to` to `runs`, extending the last run when it continues it.
    fn push(runs: &mut Vec<SlotRun>, from: usize, to: usize) {
        match runs.last_mut() {
            Some(run) if run.from + run.len == from && run.to + run.len == to => run.len += 1,
            _ => runs.push(SlotRun { from, to, len: 1 }),
        }
    }
}

impl Copies {
    /// The links into `to_unit`, grouped by source unit (in order of first appearance).
    fn into_unit(links: &[Link], to_unit: usize) -> Vec<Copies> {
        let mut groups: Vec<Copies> = Vec::new();
        for link in links.iter().filter(|l| l.to_unit == to_unit) {
            let group = match groups.iter().position(|g| g.from_unit == link.from_unit) {
                Some(i) => &mut groups[i],
                None => {
                    groups.push(Copies {
                        from_unit: link.from_unit,
                        ..Default::default()
                    });
                    groups.last_mut().expect("just pushed")
                }
            };
            let runs = match link.buffer {
                Buffer::Real => &mut group.real,
                Buffer::Integer => &mut group.integer,
                Buffer::Boolean => &mut group.boolean,
                Buffer::Word(_) => &mut group.word,
                Buffer::String | Buffer::Binary => {
                    let binary = link.buffer == Buffer::Binary;
                    group.text.push((binary, link.from_slot, link.to_slot));
                    continue;
                }
            };
            SlotRun::push(runs, link.from_slot, link.to_slot);
        }
        for group in &mut groups {
            group.others = !group.word.is_empty() || !group.text.is_empty();
        }
        groups
    }

    fn apply(&self, from: &Io, to: &mut Io) {
        copy_slots(&self.real, &from.real.values, &mut to.real.values);
        copy_slots(&self.integer, &from.integer.values, &mut to.integer.values);
        copy_slots(&self.boolean, &from.boolean.values, &mut to.boolean.values);
        if self.others {
            self.apply_others(from, to);
        }
    }

    #[inline(never)]
    fn apply_others(&self, from: &Io, to: &mut Io) {
        copy_slots(&self.word, &from.word.values, &mut to.word.values);
        for &(binary, from_slot, to_slot) in &self.text {
            to.text.copy(&from.text, binary, from_slot, to_slot);
        }
    }
}

fn copy_slots<T: Copy>(runs: &[SlotRun], from: &[T], to: &mut [T]) {
    for run in runs {
        let source = &from[run.from..run.from + run.len];
        for (destination, value) in to[run.to..run.to + run.len].iter_mut().zip(source) {
            *destination = *value;
        }
    }
}

struct Unit {
    name: String,
    instance: fmi_import::Instance,
    /// The solver of a Model Exchange instance; `None` for Co-Simulation.
    model_exchange: Option<model_exchange::ModelExchangeUnit>,
}

/// A loaded, resolved system, ready to run (and to run again, via `fmi2Reset`).
pub struct Simulation {
    system: SystemDescription,
    fmus: Vec<Fmu>,
    units: Vec<Unit>,
    /// Per unit: its input and output buffers (apart from the instances, so that copying
    /// from one unit's outputs into another's inputs borrows two different vectors).
    inputs: Vec<Io>,
    outputs: Vec<Io>,
    /// Per unit: the connections into its inputs.
    copies_into: Vec<Vec<Copies>>,
    /// Inputs driven by the system's input table, with their slots.
    table_inputs: Vec<table::TableInput>,
    /// The communication point inputs are set for.
    now: f64,
    /// (unit, buffer, output slot) per recorded column.
    columns: Vec<(usize, Buffer, usize)>,
    /// The same columns as runs of consecutive slots of one unit and type, copied together;
    /// the String and Binary ones apart, in `text_runs`.
    column_runs: Vec<ColumnRun>,
    text_runs: Vec<ColumnRun>,
    /// Per column: the text last given to the recorder (String and Binary columns), `None`
    /// before a run's first row.
    last_texts: Vec<Option<String>>,
    column_names: Vec<String>,
    column_units: Vec<String>,
    connection_names: Vec<(String, String)>,
    connectors: Vec<crate::system::ssp::ConnectorDecl>,
    row: Vec<f64>,
    /// Outputs read only once, at the end of a run (see [`Simulation::set_final_columns`]),
    /// with their names and their values after the last run.
    final_ports: Vec<Port>,
    final_names: Vec<String>,
    final_row: Vec<f64>,
    /// Per unit: what of its outputs Gauss-Seidel reads right after its step.
    read_after_step: Vec<AfterStep>,
    /// Per unit: every output was read since its last step (or initialization), so setting
    /// its inputs can change only its feedthrough outputs.
    outputs_read: Vec<bool>,
    /// Per unit: a get may not follow a set at one communication point (an FMI 3.0 instance
    /// in Step Mode), so its outputs are read before its inputs are set.
    get_before_set: Vec<bool>,
    /// Per unit: it has outputs that may depend on its inputs; without any, reading them
    /// again at its turn (its other outputs read after its step) is skipped, not made empty.
    has_feedthrough: Vec<bool>,
    /// Values that are not numbers among those read.
    finite: finite::Check,
    fresh: bool,
    conventions: Conventions,
    /// Saved runs to continue or save (`saved.rs`), and where the last run saved.
    checkpoints: saved::Checkpoints,
    saved_at: Option<f64>,
    /// Where a run stops with its instances kept (`linearize.rs`), and where the last one did.
    hold_at: Option<f64>,
    held_at: Option<f64>,
    /// The scenario's events, in the order they fall due (`events.rs`).
    events: events::Schedule,
}

/// Directories a relative FMU path is looked up in after the caller's FMU directory, in
/// order (a command line's further `--fmu-dir`s): set once, at start-up, as the execution.
static MORE_FMU_DIRS: std::sync::OnceLock<Vec<PathBuf>> = std::sync::OnceLock::new();

/// Sets the further FMU directories; only the first call counts.
pub fn set_more_fmu_dirs(dirs: Vec<PathBuf>) {
    let _ = MORE_FMU_DIRS.set(dirs);
}

pub fn more_fmu_dirs() -> &'static [PathBuf] {
    MORE_FMU_DIRS.get().map_or(&[], Vec::as_slice)
}

/// The FMU file of an instance: absolute, or relative to `fmu_dir`, else to the first of the
/// further FMU directories that holds it (`fmu_dir`'s when none does).
pub fn fmu_path(fmu_dir: &Path, fmu: &Path) -> PathBuf {
    if fmu.is_absolute() {
        return fmu.to_owned();
    }
    let first = fmu_dir.join(fmu);
    if first.exists() {
        return first;
    }
    more_fmu_dirs()
        .iter()
        .map(|dir| dir.join(fmu))
        .find(|path| path.exists())
        .unwrap_or(first)
}

/// Every FMU file the system names that is not there, in one error.
pub fn check_fmus_exist(system: &SystemDescription, fmu_dir: &Path) -> Result<(), MasterError> {
    let missing: Vec<String> = system
        .instances
        .iter()
        .map(|i| (i, fmu_path(fmu_dir, &i.fmu)))
        .filter(|(_, path)| !path.exists())
        .map(|(i, path)| format!("instance '{}': {}", i.name, path.display()))
        .collect();
    if missing.is_empty() {
        Ok(())
    } else {
        Err(MasterError::MissingFmus {
            fmu_dir: fmu_dir.to_owned(),
            missing,
        })
    }
}

impl Simulation {
    /// Loads every FMU (relative paths against `fmu_dir`), instantiates, and resolves all names.
    pub fn new(system: SystemDescription, fmu_dir: &Path) -> Result<Self, MasterError> {
        check_fmus_exist(&system, fmu_dir)?;
        let mut fmus = Vec::with_capacity(system.instances.len());
        for instance in &system.instances {
            let path = fmu_path(fmu_dir, &instance.fmu);
            let fmu = Fmu::load(&path).map_err(|source| MasterError::Load {
                instance: instance.name.clone(),
                path,
                source: Box::new(source),
            })?;
            fmus.push(fmu);
        }
        Self::from_fmus(system, fmus)
    }

    /// As [`Simulation::new`], with FMUs already loaded (one per instance, in order).
    pub fn from_fmus(mut system: SystemDescription, fmus: Vec<Fmu>) -> Result<Self, MasterError> {
        choose_interfaces(&mut system, &fmus);
        let mut problems = Vec::new();
        let fmus = configure(&system, fmus, &mut problems);
        resolve::declared_connectors(&system, &fmus, &mut problems);
        let pairs = resolve::connections(&system, &fmus, &mut problems);
        let recorded = resolve::columns(&system, &fmus, &mut problems);
        let path = |p: &Port| format!("{}.{}", system.instances[p.instance].name, p.name);
        let connection_names: Vec<(String, String)> =
            pairs.iter().map(|(s, d)| (path(s), path(d))).collect();
        for (i, instance) in system.instances.iter().enumerate() {
            for (name, value) in &instance.parameters {
                problems.extend(resolve::parameter_problem(
                    &system,
                    &fmus,
                    &connection_names,
                    i,
                    name,
                    value,
                ));
            }
        }
        resolve::algebraic_loop(&system, &fmus, &pairs, &mut problems);
        let table_inputs = table::resolve(&system, &fmus, &pairs, &mut problems);
        problems.extend(events::problems(
            &system,
            &fmus,
            &connection_names,
            &table_inputs,
        ));
        let mut finite = finite::Check::new(&system, &fmus, &mut problems);
        for port in recorded
            .iter()
            .chain(pairs.iter().map(|(source, _)| source))
        {
            finite.name(port.instance, port.kind, port.value_reference, &port.name);
        }
        if !problems.is_empty() {
            return Err(MasterError::Resolve {
                system: system.name.clone(),
                problems,
            });
        }
        let mut inputs: Vec<Io> = fmus.iter().map(|_| Io::default()).collect();
        let mut table_inputs = table_inputs;
        for driven in &mut table_inputs {
            driven.slot = inputs[driven.port.instance].slot(&driven.port);
        }
        let mut outputs: Vec<Io> = fmus.iter().map(|_| Io::default()).collect();
        // Recorded outputs take their slots first, in column order, so that consecutive
        // columns of one unit and type are consecutive slots and a row is a few bulk copies.
        let mut columns = Vec::with_capacity(recorded.len());
        let mut column_names = Vec::with_capacity(recorded.len());
        let mut column_units = Vec::with_capacity(recorded.len());
        for port in &recorded {
            let slot = outputs[port.instance].slot(port);
            columns.push((port.instance, Buffer::of(port), slot));
            let description = fmus[port.instance].model_description();
            column_units.push(
                description
                    .variable(&port.name)
                    .and_then(|v| description.unit_of(v))
                    .unwrap_or_default()
                    .to_owned(),
            );
            column_names.push(format!(
                "{}.{}",
                system.instances[port.instance].name, port.name
            ));
        }
        let mut links = Vec::with_capacity(pairs.len());
        for (source, destination) in &pairs {
            let from_slot = outputs[source.instance].slot(source);
            let to_slot = inputs[destination.instance].slot(destination);
            links.push(Link {
                buffer: Buffer::of(source),
                from_unit: source.instance,
                from_slot,
                to_unit: destination.instance,
                to_slot,
            });
        }
        let mut connectors: Vec<crate::system::ssp::ConnectorDecl> = Vec::new();
        for (port, kind) in pairs
            .iter()
            .flat_map(|(s, d)| [(s, "output"), (d, "input")])
        {
            let decl = crate::system::ssp::ConnectorDecl {
                instance: system.instances[port.instance].name.clone(),
                name: port.name.clone(),
                kind,
                type_name: match Buffer::of(port) {
                    Buffer::Real => "Real",
                    Buffer::Boolean => "Boolean",
                    Buffer::Integer => "Integer",
                    // SSP 1.0 connector types: a Float32 is a Real, every integer an Integer.
                    Buffer::Word(Fmi3Type::Float32) => "Real",
                    Buffer::Word(_) => "Integer",
                    Buffer::String => "String",
                    Buffer::Binary => "Binary",
                },
            };
            if !connectors.contains(&decl) {
                connectors.push(decl);
            }
        }
        let driven: Vec<Port> = table_inputs.iter().map(|t| t.port.clone()).collect();
        feedthrough_last(
            &fmus,
            &pairs,
            &driven,
            &recorded,
            &mut outputs,
            &mut links,
            &mut columns,
        );
        for port in recorded
            .iter()
            .chain(pairs.iter().map(|(source, _)| source))
        {
            if port.word == Some(Fmi3Type::Float32) {
                let io = &mut outputs[port.instance];
                let slot = io.slot(port);
                if !io.float32.contains(&slot) {
                    io.float32.push(slot);
                }
            }
        }
        for io in inputs.iter_mut().chain(&mut outputs) {
            io.note_others();
        }
        let units = instantiate(&system, &fmus, &outputs)?;
        let get_before_set = units
            .iter()
            .map(|unit| !unit.instance.can_get_after_set())
            .collect();
        let (text_runs, column_runs): (Vec<_>, Vec<_>) = ColumnRun::of(&columns)
            .into_iter()
            .partition(|run| run.buffer.is_text());
        let copies_into = (0..units.len())
            .map(|u| Copies::into_unit(&links, u))
            .collect();
        let row = vec![0.0; columns.len()];
        let last_texts = vec![None; columns.len()];
        let read_after_step = AfterStep::of(&links, &outputs);
        let has_feedthrough = outputs.iter().map(Io::has_feedthrough).collect();
        let events = events::Schedule::new(&system);
        Ok(Self {
            system,
            fmus,
            units,
            inputs,
            outputs,
            copies_into,
            table_inputs,
            now: 0.0,
            columns,
            last_texts,
            column_runs,
            text_runs,
            column_names,
            column_units,
            connection_names,
            connectors,
            row,
            final_ports: Vec::new(),
            final_names: Vec::new(),
            final_row: Vec::new(),
            outputs_read: vec![false; read_after_step.len()],
            read_after_step,
            get_before_set,
            has_feedthrough,
            finite,
            fresh: true,
            conventions: Conventions::default(),
            checkpoints: saved::Checkpoints::default(),
            saved_at: None,
            hold_at: None,
            held_at: None,
            events,
        })
    }

    pub fn system(&self) -> &SystemDescription {
        &self.system
    }

    /// Sets (or overrides) a parameter for the following runs; name, type and that it is not
    /// a connected input are checked now.
    pub fn set_parameter(
        &mut self,
        instance: &str,
        variable: &str,
        value: ParamValue,
    ) -> Result<(), MasterError> {
        let resolve = |problem: String| MasterError::Resolve {
            system: self.system.name.clone(),
            problems: vec![problem],
        };
        let index = self
            .system
            .instances
            .iter()
            .position(|i| i.name == instance)
            .ok_or_else(|| {
                let names = self.system.instances.iter().map(|i| i.name.as_str());
                resolve(format!(
                    "no instance named '{instance}'{}",
                    crate::suggest::hint(instance, names)
                ))
            })?;
        if self.fmus[index].structural_parameters().contains(&variable) {
            return Err(resolve(format!(
                "instance '{instance}': '{variable}' is a structural parameter, which sizes \
                 the FMU's arrays: give it in the scenario or with --set, before the system is \
                 loaded, not once it is"
            )));
        }
        if let Some(problem) = resolve::parameter_problem(
            &self.system,
            &self.fmus,
            &self.connection_names,
            index,
            variable,
            &value,
        ) {
            return Err(resolve(problem));
        }
        self.system.set_parameter(instance, variable, value);
        Ok(())
    }

    /// Changes a scenario event for the following runs ([`SystemDescription::change_event`]),
    /// its place among the others' due times with it.
    pub fn change_event(
        &mut self,
        name: &str,
        change: &crate::system::event::Change,
    ) -> Result<(), MasterError> {
        self.system
            .change_event(name, change)
            .map_err(|problem| MasterError::Resolve {
                system: self.system.name.clone(),
                problems: vec![problem],
            })?;
        self.events = events::Schedule::new(&self.system);
        Ok(())
    }

    /// Sets the initial-input and time conventions of the following runs (default: the
    /// harness's own; see [`Conventions`]).
    pub fn set_conventions(&mut self, conventions: Conventions) {
        self.conventions = conventions;
    }

    pub fn fmus(&self) -> &[Fmu] {
        &self.fmus
    }

    /// `instance.variable` of each recorded column.
    pub fn column_names(&self) -> &[String] {
        &self.column_names
    }

    /// The unit of each recorded column as its FMU declares it ("" where it declares none).
    pub fn column_units(&self) -> &[String] {
        &self.column_units
    }

    /// The type of each recorded column, which says how its values sit in a row (see
    /// [`crate::results::ColumnType`]).
    pub fn column_types(&self) -> Vec<crate::results::ColumnType> {
        self.columns
            .iter()
            .map(|&(_, buffer, _)| buffer.column_type())
            .collect()
    }

    /// Outputs to read once, at the last communication point of each run (after its row is
    /// recorded, before the instances terminate), instead of at every step: what a caller
    /// needs only at the end (a touchdown state) costs nothing per step. `names` are
    /// `instance.variable` paths as in a scenario's `record` (arrays expand to elements);
    /// [`Simulation::final_values`] gives the values.
    pub fn set_final_columns(&mut self, names: &[String]) -> Result<(), MasterError> {
        let mut problems = Vec::new();
        let ports: Vec<Port> = names
            .iter()
            .flat_map(|path| resolve::ports(&self.system, &self.fmus, path, &[], &mut problems))
            .collect();
        if !problems.is_empty() {
            return Err(MasterError::Resolve {
                system: self.system.name.clone(),
                problems,
            });
        }
        self.final_names = ports
            .iter()
            .map(|p| format!("{}.{}", self.system.instances[p.instance].name, p.name))
            .collect();
        self.final_row = vec![f64::NAN; ports.len()];
        for port in &ports {
            self.finite
                .name(port.instance, port.kind, port.value_reference, &port.name);
        }
        self.final_ports = ports;
        Ok(())
    }

    /// `instance.variable` of each value of [`Simulation::final_values`].
    pub fn final_column_names(&self) -> &[String] {
        &self.final_names
    }

    /// The outputs set with [`Simulation::set_final_columns`] at the end of the last run
    /// (booleans as 0.0 or 1.0, as recorded columns); NaN before any run.
    pub fn final_values(&self) -> &[f64] {
        &self.final_row
    }

    /// Every connection as (`from`, `to`) scalar `instance.variable` paths, in order.
    pub fn scalar_connections(&self) -> &[(String, String)] {
        &self.connection_names
    }

    /// Every connected variable with its direction, for writing an SSD.
    /// Each Model Exchange instance's solver counters over the last run (steps, derivative
    /// calls, Jacobians and how many the FMU gave), in instance order.
    pub fn model_exchange_statistics(&self) -> Vec<(&str, ode_solver::Statistics)> {
        self.units
            .iter()
            .filter_map(|unit| Some((unit.name.as_str(), unit.model_exchange.as_ref()?.statistics)))
            .collect()
    }

    /// Each Model Exchange instance's events in the last run, in instance order.
    pub fn model_exchange_events(&self) -> Vec<(&str, EventCounts)> {
        self.units
            .iter()
            .filter_map(|unit| {
                let me = unit.model_exchange.as_ref()?;
                Some((unit.name.as_str(), me.events))
            })
            .collect()
    }

    pub fn connectors(&self) -> &[crate::system::ssp::ConnectorDecl] {
        &self.connectors
    }

    /// Runs from the start to the stop time (or an earlier termination), handing every
    /// communication point's recorded row to `recorder`. Can be called again: the instances
    /// are reset first.
    pub fn run(&mut self, recorder: &mut dyn Recorder) -> Result<RunEnd, MasterError> {
        if !self.fresh {
            for unit in &mut self.units {
                let name = unit.name.clone();
                let v = unit.instance.fmi_version();
                unit.instance
                    .reset()
                    .map_err(|e| call(&name, named(v, "fmi2Reset", "fmi3Reset"), e.into()))?;
            }
        }
        self.fresh = false;
        self.held_at = None;
        self.final_row.fill(f64::NAN);
        self.last_texts.fill(None);
        self.finite.reset();
        self.initialize()?;
        let SystemDescription {
            start_time,
            stop_time,
            step_size,
            ordering,
            ..
        } = self.system;
        let mut clock =
            conventions::Clock::new(self.conventions.time_grid, start_time, stop_time, step_size);
        let save_at = self.begin_checkpoints(&mut clock)?;
        recorder.reserve(clock.rows_hint(), self.columns.len());
        self.events.restart();
        let mut first_point = true;
        loop {
            if save_at == Some(clock.position().0) {
                self.save_run(&clock)?;
            }
            let Some((time, h)) = clock.next_step() else {
                break;
            };
            if first_point {
                // A continued run's FMU states hold the events due before it.
                self.events.skip_before(&self.system, time);
                first_point = false;
            }
            self.now = time;
            if ordering == Ordering::GaussSeidel {
                for u in 0..self.units.len() {
                    if self.get_before_set[u] {
                        // FMI 3.0 Step Mode: no get after a set before the step. Outputs
                        // that depend on no connected input are the same either way; the
                        // others (only of an FMU without Event Mode) come one step late.
                        self.read_for_exchange(u)?;
                        self.set_inputs(u)?;
                        continue;
                    }
                    self.set_inputs(u)?;
                    // Outputs read right after the step are still valid unless they depend
                    // on the inputs just set: read only those (the plant's state once a step).
                    self.read_for_exchange(u)?;
                }
            }
            self.record(time, recorder)?;
            if ordering == Ordering::Jacobi {
                for u in 0..self.units.len() {
                    self.set_inputs(u)?;
                }
            }
            // Events due here change the step from this point, not its row (`events.rs`).
            let applied = self
                .events
                .apply_due(&self.system, &mut self.units, time, h);
            let ended = applied.inspect_err(|_| self.terminate_all())?;
            if let Some(u) = ended {
                let instance = self.units[u].name.clone();
                self.read_final(time)?;
                self.terminate_all();
                return Ok(RunEnd::Terminated { instance, time });
            }
            // A hold: every input set for this point and its events applied (the linear model
            // is that of the step from it), nothing stepped, nothing terminated.
            if self.hold_at.is_some_and(|hold| time >= hold - 0.5 * h) {
                self.held_at = Some(time);
                return Ok(RunEnd::Completed);
            }
            for u in 0..self.units.len() {
                self.outputs_read[u] = false;
                let unit = &mut self.units[u];
                let stepped = match &mut unit.model_exchange {
                    Some(me) => match me.do_step(&mut unit.instance, time, h) {
                        Ok(status) => Ok(status),
                        Err(model_exchange::MeError::Fmi(e)) => Err(e),
                        Err(other) => {
                            let instance = unit.name.clone();
                            self.terminate_all();
                            return Err(MasterError::ModelExchange {
                                instance,
                                time,
                                source: Box::new(other),
                            });
                        }
                    },
                    None => unit.instance.do_step(time, h),
                };
                match stepped {
                    Ok(StepStatus::Complete(_)) => {}
                    Ok(status) => {
                        let name = unit.name.clone();
                        // FMI 2.0: fmi2Discard + fmi2Terminated; FMI 3.0: terminateSimulation.
                        // Either way the FMU ended the run, and its row is the last.
                        let Some(last_successful_time) = status.ended_run() else {
                            let function = unit.instance.do_step_function();
                            let stopped = match status {
                                StepStatus::Discarded {
                                    last_successful_time,
                                    ..
                                } => last_successful_time,
                                _ => time,
                            };
                            let context = match unit.instance.fmi_version() {
                                fmi_import::FmiVersion::Fmi2 => format!(
                                    "fmi2DoStep at t = {time} returned fmi2Discard without \
                                     fmi2Terminated (stopped at {stopped}); this \
                                     fixed-step master cannot retry a shorter step"
                                ),
                                fmi_import::FmiVersion::Fmi3 => format!(
                                    "fmi3DoStep at t = {time} stopped at {stopped} without \
                                     terminateSimulation; this fixed-step master cannot \
                                     retry a shorter step"
                                ),
                            };
                            return Err(MasterError::Call {
                                instance: name,
                                context,
                                source: Box::new(CallError::InvalidArgument {
                                    function,
                                    instance: unit.name.clone(),
                                    reason: "discarded step".into(),
                                }),
                            });
                        };
                        self.get_outputs(u)?;
                        self.record(last_successful_time, recorder)?;
                        self.read_final(last_successful_time)?;
                        self.terminate_all();
                        return Ok(RunEnd::Terminated {
                            instance: name,
                            time: last_successful_time,
                        });
                    }
                    Err(source) => {
                        let instance = unit.name.clone();
                        self.terminate_all();
                        return Err(MasterError::Step {
                            instance,
                            time,
                            source: Box::new(source),
                        });
                    }
                }
            }
            // Jacobi exchanges exactly the outputs read after the step. Gauss-Seidel reads each
            // instance's outputs again in its turn at the next point, so after the step it only
            // needs those an earlier instance consumes (the plant's, for a controller declared
            // first); without them that instance would see its sources as they were before
            // they stepped. Reading a direct-feedthrough controller here as well would cost a
            // whole evaluation at stale inputs for nothing. Likewise the outputs that depend
            // on the instance's own inputs are read again at its turn, after those are set:
            // unless an earlier instance consumes one, only the others are read here.
            for u in 0..self.units.len() {
                let part = match ordering {
                    Ordering::Jacobi => AfterStep::All,
                    Ordering::GaussSeidel => self.read_after_step[u],
                };
                match part {
                    AfterStep::Nothing => {}
                    AfterStep::Stable => {
                        self.read_outputs(u, Part::Stable)?;
                        self.outputs_read[u] = true;
                    }
                    AfterStep::All => self.get_outputs(u)?,
                }
            }
        }
        self.now = clock.end_time();
        // Jacobi records, at every point, the outputs read after the step that ended there,
        // before any input is set: so also at the end, as fmpy's simulate_ssp, libcosim and
        // Ecos do (a final exchange would show feedthrough outputs answering inputs that no
        // step used). Gauss-Seidel sets each instance's inputs before reading it, at every
        // point and so at the end.
        if ordering == Ordering::GaussSeidel {
            for u in 0..self.units.len() {
                // An instance that allows no get after a set (FMI 3.0 Step Mode) records the
                // outputs of its last step: its inputs at the stop time could change nothing
                // read.
                if !self.get_before_set[u] {
                    self.set_inputs(u)?;
                }
                self.get_outputs(u)?;
            }
        }
        self.record(clock.end_time(), recorder)?;
        if self
            .hold_at
            .is_some_and(|hold| clock.end_time() >= hold - 0.5 * step_size)
        {
            self.held_at = Some(clock.end_time());
            return Ok(RunEnd::Completed);
        }
        self.read_final(clock.end_time())?;
        self.terminate_all();
        Ok(RunEnd::Completed)
    }

    fn initialize(&mut self) -> Result<(), MasterError> {
        let (start, stop) = (self.system.start_time, self.system.stop_time);
        self.now = start;
        let declared_stop = self.conventions.stop_time_declared.then_some(stop);
        for (u, desc) in self.system.instances.iter().enumerate() {
            let unit = &mut self.units[u];
            let name = unit.name.clone();
            let v = unit.instance.fmi_version();
            unit.instance
                .setup_experiment(None, start, declared_stop)
                .map_err(|e| {
                    call(
                        &name,
                        named(v, "fmi2SetupExperiment", "fmi3EnterInitializationMode"),
                        e.into(),
                    )
                })?;
            let structural = self.fmus[u].structural_parameters();
            for (variable, value) in &desc.parameters {
                // Set in Configuration Mode when the instance was made (see `configure`).
                if structural.contains(&variable.as_str()) {
                    continue;
                }
                set_parameter(&mut unit.instance, variable, value)
                    .map_err(|e| call(&name, &format!("setting parameter {variable}"), e))?;
            }
            unit.instance.enter_initialization_mode().map_err(|e| {
                call(
                    &name,
                    named(
                        v,
                        "fmi2EnterInitializationMode",
                        "fmi3EnterInitializationMode",
                    ),
                    e.into(),
                )
            })?;
        }
        if self.conventions.initial_inputs == InitialInputs::Zero {
            return self.initialize_with_zero_inputs();
        }
        // Initial exchange in initialization mode, in order, so that a controller sees the
        // plant's initial state and the plant its initial command.
        for u in 0..self.units.len() {
            self.get_outputs(u)?;
        }
        for u in 0..self.units.len() {
            self.set_inputs(u)?;
            self.get_outputs(u)?;
        }
        self.exit_initialization_modes()?;
        for u in 0..self.units.len() {
            self.get_outputs(u)?;
        }
        Ok(())
    }

    /// Every unit leaves initialization mode, in unit order.
    fn exit_initialization_modes(&mut self) -> Result<(), MasterError> {
        let start = self.system.start_time;
        for unit in &mut self.units {
            let name = unit.name.clone();
            let v = unit.instance.fmi_version();
            unit.instance.exit_initialization_mode().map_err(|e| {
                call(
                    &name,
                    named(
                        v,
                        "fmi2ExitInitializationMode",
                        "fmi3ExitInitializationMode",
                    ),
                    e.into(),
                )
            })?;
            if let Some(me) = &mut unit.model_exchange {
                // A run the FMU ends at its start is reported by its first step.
                me.start(&mut unit.instance, start).map_err(|source| {
                    MasterError::ModelExchange {
                        instance: name.clone(),
                        time: start,
                        source: Box::new(source),
                    }
                })?;
            }
        }
        self.finite.armed = true;
        Ok(())
    }

    /// [`InitialInputs::Zero`]: no exchange; every buffer, so every first input, is 0.0.
    fn initialize_with_zero_inputs(&mut self) -> Result<(), MasterError> {
        for io in self.inputs.iter_mut().chain(&mut self.outputs) {
            io.real.values.fill(0.0);
            io.integer.values.fill(0);
            io.boolean.values.fill(0);
            io.word.values.fill(0);
            io.text.clear();
        }
        self.exit_initialization_modes()?;
        Ok(())
    }

    fn set_inputs(&mut self, u: usize) -> Result<(), MasterError> {
        // Outputs and inputs are separate vectors, so a source may be any unit, this one
        // included.
        let inputs = &mut self.inputs[u];
        for copies in &self.copies_into[u] {
            copies.apply(&self.outputs[copies.from_unit], inputs);
        }
        if let Some(table) = &self.system.inputs {
            for driven in self.table_inputs.iter().filter(|t| t.port.instance == u) {
                let value = table.value(driven.column, self.now, driven.interpolate);
                match driven.port.kind {
                    VariableKind::Real => inputs.real.values[driven.slot] = value,
                    VariableKind::Boolean => {
                        inputs.boolean.values[driven.slot] = (value != 0.0) as i32
                    }
                    _ => inputs.integer.values[driven.slot] = value as i32,
                }
            }
        }
        let unit = &mut self.units[u];
        let result = (|| -> Result<(), CallError> {
            if !inputs.real.vrs.is_empty() {
                unit.instance
                    .set_real(&inputs.real.vrs, &inputs.real.values)?;
            }
            if !inputs.integer.vrs.is_empty() {
                unit.instance
                    .set_integer(&inputs.integer.vrs, &inputs.integer.values)?;
            }
            if !inputs.boolean.vrs.is_empty() {
                unit.instance
                    .set_boolean_raw(&inputs.boolean.vrs, &inputs.boolean.values)?;
            }
            if inputs.others {
                set_others(&mut unit.instance, inputs)?;
            }
            Ok(())
        })();
        result.map_err(|e| call(&unit.name, "setting inputs", e))
    }

    /// Reads every output of unit `u`.
    fn get_outputs(&mut self, u: usize) -> Result<(), MasterError> {
        self.read_outputs(u, Part::All)?;
        self.outputs_read[u] = true;
        Ok(())
    }

    /// Reads the outputs of unit `u` that may depend on its inputs.
    #[inline]
    fn get_feedthrough_outputs(&mut self, u: usize) -> Result<(), MasterError> {
        if !self.has_feedthrough[u] {
            return Ok(());
        }
        self.read_outputs(u, Part::Feedthrough)
    }

    /// At a unit's turn: the outputs not read since its step, or only those that depend on its
    /// inputs when the others were.
    #[inline]
    fn read_for_exchange(&mut self, u: usize) -> Result<(), MasterError> {
        if self.outputs_read[u] {
            self.get_feedthrough_outputs(u)
        } else {
            self.get_outputs(u)
        }
    }

    fn read_outputs(&mut self, u: usize, part: Part) -> Result<(), MasterError> {
        let unit = &mut self.units[u];
        let outputs = &mut self.outputs[u];
        let result = (|| -> Result<(), CallError> {
            let real = part.of(&outputs.real);
            if !real.is_empty() {
                unit.instance.get_real(
                    &outputs.real.vrs[real.clone()],
                    &mut outputs.real.values[real],
                )?;
            }
            let integer = part.of(&outputs.integer);
            if !integer.is_empty() {
                unit.instance.get_integer(
                    &outputs.integer.vrs[integer.clone()],
                    &mut outputs.integer.values[integer],
                )?;
            }
            let boolean = part.of(&outputs.boolean);
            if !boolean.is_empty() {
                unit.instance.get_boolean_raw(
                    &outputs.boolean.vrs[boolean.clone()],
                    &mut outputs.boolean.values[boolean],
                )?;
            }
            if outputs.others {
                get_others(&mut unit.instance, outputs, part)?;
            }
            Ok(())
        })();
        result.map_err(|e| call(&unit.name, "getting outputs", e))?;
        if outputs.others && self.finite.armed {
            self.finite
                .note_float32(&outputs.float32, &outputs.word.values, &outputs.word.vrs, u);
        }
        let real = part.of(&outputs.real);
        if self.finite.armed && !finite::all_finite(&outputs.real.values[real.clone()]) {
            self.finite.note(
                u,
                &outputs.real.vrs[real.clone()],
                &outputs.real.values[real],
            );
        }
        Ok(())
    }

    fn record(&mut self, time: f64, recorder: &mut dyn Recorder) -> Result<(), MasterError> {
        for run in &self.column_runs {
            let outputs = &self.outputs[run.unit];
            let row = &mut self.row[run.column..run.column + run.len];
            let slots = run.slot..run.slot + run.len;
            match run.block {
                REAL => row.copy_from_slice(&outputs.real.values[slots]),
                BOOLEAN => {
                    for (value, &b) in row.iter_mut().zip(&outputs.boolean.values[slots]) {
                        *value = f64::from(b);
                    }
                }
                INTEGER => {
                    for (value, &i) in row.iter_mut().zip(&outputs.integer.values[slots]) {
                        *value = f64::from(i);
                    }
                }
                // Texts are in `text_runs` instead: their slots stay 0.
                _ => {
                    if let Buffer::Word(kind) = run.buffer {
                        word_slots(kind, row, &outputs.word.values[slots]);
                    }
                }
            }
        }
        if !self.text_runs.is_empty() {
            self.record_texts(recorder);
        }
        recorder.record(time, &self.row);
        if let Some(reason) = recorder.failure() {
            self.terminate_all();
            return Err(MasterError::Record { time, reason });
        }
        self.settle_non_finite(time)
    }

    /// Hands the recorder each text column whose value changed since the last row (every one
    /// at a run's first row).
    #[inline(never)]
    fn record_texts(&mut self, recorder: &mut dyn Recorder) {
        for run in &self.text_runs {
            let texts = &self.outputs[run.unit].text;
            let binary = run.buffer == Buffer::Binary;
            for j in 0..run.len {
                let (column, slot) = (run.column + j, run.slot + j);
                let last = &mut self.last_texts[column];
                if last
                    .as_deref()
                    .is_none_or(|text| texts.differs(binary, slot, text))
                {
                    let text = texts.text(binary, slot);
                    recorder.record_text(column, &text);
                    *last = Some(text);
                }
            }
        }
    }

    /// Ends the run with the first value read for the row of `time` that was not a finite
    /// number and is not allowed (warning about those allowed).
    fn settle_non_finite(&mut self, time: f64) -> Result<(), MasterError> {
        if !self.finite.pending() {
            return Ok(());
        }
        let names: Vec<String> = self.units.iter().map(|u| u.name.clone()).collect();
        let settled = self.finite.settle(time, &names);
        if settled.is_err() {
            self.terminate_all();
        }
        settled.map_err(|n| MasterError::NonFinite {
            instance: n.instance,
            variable: n.variable,
            time: n.time,
            value: n.value,
        })
    }

    /// Reads the final-only outputs, one call per value: a handful, once per run. `time` is
    /// that of the last row.
    fn read_final(&mut self, time: f64) -> Result<(), MasterError> {
        for (value, port) in self.final_row.iter_mut().zip(&self.final_ports) {
            let unit = &mut self.units[port.instance];
            let vr = [port.value_reference];
            let read = match Buffer::of(port) {
                // A final value is a number: a text has none.
                Buffer::String | Buffer::Binary => Ok(0.0),
                Buffer::Word(kind) => {
                    let mut w = [0];
                    unit.instance
                        .get_words(&vr, &mut w)
                        .map(|_| crate::results::ColumnType::of_fmi3(kind).slot_of_word(w[0]))
                }
                Buffer::Real => {
                    let mut x = [0.0];
                    unit.instance.get_real(&vr, &mut x).map(|_| x[0])
                }
                Buffer::Boolean => {
                    let mut b = [0];
                    unit.instance
                        .get_boolean_raw(&vr, &mut b)
                        .map(|_| f64::from(b[0]))
                }
                Buffer::Integer => {
                    let mut i = [0];
                    unit.instance
                        .get_integer(&vr, &mut i)
                        .map(|_| f64::from(i[0]))
                }
            };
            *value = read.map_err(|e| call(&unit.name, "getting final outputs", e))?;
            let number = matches!(port.word, None | Some(Fmi3Type::Float32));
            if number && !value.is_finite() {
                self.finite
                    .note(port.instance, &[port.value_reference], &[*value]);
            }
        }
        self.settle_non_finite(time)
    }

    fn terminate_all(&mut self) {
        for unit in &mut self.units {
            // After a terminating discard, fmi2Terminate is legal; a failure here changes
            // nothing about the run's result, and the FMU's log keeps the reason.
            let _ = unit.instance.terminate();
        }
    }
}

/// Recorded columns `column..column + len` are output slots `slot..slot + len` of one unit
/// and exchange buffer (and, for words, one type).
#[derive(Debug, Clone, Copy)]
struct ColumnRun {
    unit: usize,
    /// What `record` dispatches on: a plain tag, cheaper to match than `buffer`.
    block: u8,
    buffer: Buffer,
    slot: usize,
    column: usize,
    len: usize,
}

impl ColumnRun {
    fn of(columns: &[(usize, Buffer, usize)]) -> Vec<ColumnRun> {
        let mut runs: Vec<ColumnRun> = Vec::new();
        for (column, &(unit, buffer, slot)) in columns.iter().enumerate() {
            match runs.last_mut() {
                Some(run)
                    if run.unit == unit && run.buffer == buffer && run.slot + run.len == slot =>
                {
                    run.len += 1
                }
                _ => runs.push(ColumnRun {
                    unit,
                    block: block_index(buffer) as u8,
                    buffer,
                    slot,
                    column,
                    len: 1,
                }),
            }
        }
        runs
    }
}

/// Orders every unit's output slots so that those which may depend on one of its connected
/// or table-driven inputs (as its model description declares; an output that declares nothing may depend on
/// every input) come last, and points the links and columns at the moved slots.
fn feedthrough_last(
    fmus: &[Fmu],
    pairs: &[(Port, Port)],
    driven: &[Port],
    recorded: &[Port],
    outputs: &mut [Io],
    links: &mut [Link],
    columns: &mut [(usize, Buffer, usize)],
) {
    let ports = pairs.iter().map(|(source, _)| source).chain(recorded);
    // Per unit, per exchange type (real, integer, boolean): the feedthrough flag of each slot.
    let mut flags: Vec<[Vec<bool>; 4]> = outputs
        .iter()
        .map(|io| {
            [
                vec![false; io.real.vrs.len()],
                vec![false; io.integer.vrs.len()],
                vec![false; io.boolean.vrs.len()],
                vec![false; io.word.vrs.len()],
            ]
        })
        .collect();
    let feedthrough: Vec<loops::Feedthrough> = fmus
        .iter()
        .map(|fmu| loops::Feedthrough::from_description(fmu.model_description()))
        .collect();
    for port in ports {
        let u = port.instance;
        let depends = pairs
            .iter()
            .map(|(_, destination)| destination)
            .chain(driven)
            .filter(|input| input.instance == u)
            .any(|input| feedthrough[u].depends(&port.name, &input.name, false));
        let slot = outputs[u].slot(port);
        if Buffer::of(port).is_text() {
            // Not partitioned: every text output is read with the feedthrough outputs.
            continue;
        }
        flags[u][block_index(Buffer::of(port))][slot] |= depends;
    }
    for (u, io) in outputs.iter_mut().enumerate() {
        let moved = [
            io.real.partition(&flags[u][0]),
            io.integer.partition(&flags[u][1]),
            io.boolean.partition(&flags[u][2]),
            io.word.partition(&flags[u][3]),
        ];
        for link in links
            .iter_mut()
            .filter(|l| l.from_unit == u && !l.buffer.is_text())
        {
            link.from_slot = moved[block_index(link.buffer)][link.from_slot];
        }
        for (unit_of, buffer, slot) in columns.iter_mut().filter(|c| c.0 == u && !c.1.is_text()) {
            debug_assert_eq!(*unit_of, u);
            *slot = moved[block_index(*buffer)][*slot];
        }
    }
}

/// Each FMU whose instance gives values to its structural parameters (FMI 3.0) as the FMU
/// configured with them: its scalar view built for them, so that names resolve against the
/// arrays' extents they set, and its instances set them in Configuration Mode (see
/// `fmi_import`'s `Fmu::configured`). Every FMU is loaded once per instance, so the
/// configured one is that instance's own.
fn configure(system: &SystemDescription, fmus: Vec<Fmu>, problems: &mut Vec<String>) -> Vec<Fmu> {
    fmus.into_iter()
        .zip(&system.instances)
        .map(|(fmu, instance)| {
            let structural = fmu.structural_parameters();
            let values: Vec<(String, String)> = instance
                .parameters
                .iter()
                .filter(|(name, _)| structural.contains(&name.as_str()))
                .map(|(name, value)| (name.clone(), parameter_text(value)))
                .collect();
            if values.is_empty() {
                return fmu;
            }
            match fmu.configured(&values) {
                Ok(configured) => configured,
                Err(error) => {
                    problems.push(format!("instance '{}': {error}", instance.name));
                    fmu
                }
            }
        })
        .collect()
}

/// A scenario value as the text a model description would give it.
fn parameter_text(value: &ParamValue) -> String {
    match value {
        ParamValue::Real(x) => format!("{x:?}"),
        ParamValue::Integer(i) => i.to_string(),
        ParamValue::Boolean(b) => b.to_string(),
        ParamValue::String(s) => s.clone(),
    }
}

/// An instance whose scenario names no interface runs through Model Exchange, with the
/// default solver, when that is the only interface its FMU declares (as fmpy and fmusim
/// choose); otherwise through Co-Simulation.
fn choose_interfaces(system: &mut SystemDescription, fmus: &[Fmu]) {
    for (desc, fmu) in system.instances.iter_mut().zip(fmus) {
        let description = fmu.model_description();
        let model_exchange_only =
            description.co_simulation.is_none() && description.model_exchange.is_some();
        if !desc.interface_named && desc.model_exchange.is_none() && model_exchange_only {
            log::info!(
                "instance '{}': model '{}' declares Model Exchange only: it runs through it \
                 with the default solver",
                desc.name,
                fmu.model_name()
            );
            desc.model_exchange = Some(SolverSettings::default());
        }
    }
}

/// Instantiates every unit. An instance whose outputs the master reads after setting its
/// inputs at one communication point (Gauss-Seidel, an output that depends on a connected
/// input) asks for same-instant feedthrough, which FMI 3.0 gives in Event Mode only.
fn instantiate(
    system: &SystemDescription,
    fmus: &[Fmu],
    outputs: &[Io],
) -> Result<Vec<Unit>, MasterError> {
    let mut units = Vec::with_capacity(fmus.len());
    for ((fmu, desc), io) in fmus.iter().zip(&system.instances).zip(outputs) {
        let feedthrough = io.real.feedthrough_start < io.real.vrs.len()
            || io.integer.feedthrough_start < io.integer.vrs.len()
            || io.boolean.feedthrough_start < io.boolean.vrs.len()
            || io.word.feedthrough_start < io.word.vrs.len();
        let same_instant = system.ordering == Ordering::GaussSeidel && feedthrough;
        if same_instant && desc.model_exchange.is_none() && !fmu.supports_same_instant_feedthrough()
        {
            log::warn!(
                "instance '{}': model '{}' (FMI 3.0) has no Event Mode, so its outputs that \
                 depend on its inputs are read before its inputs are set: one step late",
                desc.name,
                fmu.model_name()
            );
        }
        let options = InstanceOptions {
            logging_on: false,
            same_instant_feedthrough: same_instant,
            interface: if desc.model_exchange.is_some() {
                fmi_import::Interface::ModelExchange
            } else {
                fmi_import::Interface::CoSimulation
            },
        };
        let instance = fmu
            .instantiate_with(&desc.name, options)
            .map_err(|source| MasterError::Call {
                instance: desc.name.clone(),
                context: match (fmu.fmi_version(), desc.model_exchange.is_some()) {
                    (fmi_import::FmiVersion::Fmi2, _) => "fmi2Instantiate",
                    (fmi_import::FmiVersion::Fmi3, false) => "fmi3InstantiateCoSimulation",
                    (fmi_import::FmiVersion::Fmi3, true) => "fmi3InstantiateModelExchange",
                }
                .into(),
                source: Box::new(source),
            })?;
        let mut instance = instance;
        let model_exchange = desc
            .model_exchange
            .map(|settings| model_exchange::ModelExchangeUnit::new(settings, &mut instance))
            .transpose()
            .map_err(|source| MasterError::Step {
                instance: desc.name.clone(),
                time: system.start_time,
                source: Box::new(source),
            })?;
        units.push(Unit {
            name: desc.name.clone(),
            instance,
            model_exchange,
        });
    }
    Ok(units)
}

/// The name of a call in the FMI version of the instance, for error contexts.
fn named(version: fmi_import::FmiVersion, fmi2: &'static str, fmi3: &'static str) -> &'static str {
    match version {
        fmi_import::FmiVersion::Fmi2 => fmi2,
        fmi_import::FmiVersion::Fmi3 => fmi3,
    }
}

fn call(instance: &str, context: &str, source: CallError) -> MasterError {
    MasterError::Call {
        instance: instance.to_owned(),
        context: context.to_owned(),
        source: Box::new(source),
    }
}

/// Sets a scenario value with the type the model description gives the variable, as the
/// master does before a run (also for masters of ours outside this module: the benches).
pub fn set_parameter(
    instance: &mut fmi_import::Instance,
    variable: &str,
    value: &ParamValue,
) -> Result<(), CallError> {
    let info = *instance.variable(variable)?;
    let kind = info.kind;
    let mismatch = |what: &str| CallError::InvalidArgument {
        function: "set parameter",
        instance: instance.name().to_owned(),
        reason: format!(
            "variable '{variable}' is {}; the scenario gives {what}",
            info.type_name()
        ),
    };
    if let Some(fmi3) = info.fmi3_type.filter(|&t| fmi_import::word::is_word(t)) {
        let word = resolve::parameter_word(fmi3, value).map_err(|reason| mismatch(&reason))?;
        instance.set_words(&[info.value_reference], &[word])?;
        return Ok(());
    }
    if info.fmi3_type == Some(Fmi3Type::Binary) {
        let ParamValue::String(text) = value else {
            return Err(mismatch(&format!("{value:?}, not hex text")));
        };
        let bytes = fmi_import::word::from_hex(text).map_err(|reason| mismatch(&reason))?;
        instance.set_binary(&[info.value_reference], &[&bytes])?;
        return Ok(());
    }
    match (kind.accessed_as(), value) {
        (VariableKind::Real, ParamValue::Real(x)) => instance.set_real_by_name(variable, *x)?,
        (VariableKind::Real, ParamValue::Integer(i)) => {
            instance.set_real_by_name(variable, *i as f64)?
        }
        (VariableKind::Integer, ParamValue::Integer(i)) => {
            let i =
                i32::try_from(*i).map_err(|_| mismatch(&format!("{i}, out of Integer range")))?;
            instance.set_integer_by_name(variable, i)?
        }
        (VariableKind::Boolean, ParamValue::Boolean(b)) => {
            instance.set_boolean_by_name(variable, *b)?
        }
        (VariableKind::String, ParamValue::String(s)) => {
            instance.set_string_by_name(variable, s)?
        }
        (_, other) => return Err(mismatch(&format!("{other:?}"))),
    };
    Ok(())
}

// The words' and texts' paths live here, not in buffer.rs, because they take the exchange
// buffers (`Io`) of this module.

/// Sets the words and texts of `inputs`; out of line, as [`buffer::word_slots`].
#[inline(never)]
fn set_others(instance: &mut fmi_import::Instance, inputs: &Io) -> Result<(), CallError> {
    if !inputs.word.vrs.is_empty() {
        instance.set_words(&inputs.word.vrs, &inputs.word.values)?;
    }
    if !inputs.text.is_empty() {
        inputs.text.set(instance)?;
    }
    Ok(())
}

/// Gets the words (of `part`) and texts (every text output counts as feedthrough) of
/// `outputs`; out of line, as [`buffer::word_slots`].
#[inline(never)]
fn get_others(
    instance: &mut fmi_import::Instance,
    outputs: &mut Io,
    part: Part,
) -> Result<(), CallError> {
    let words = part.of(&outputs.word);
    if !words.is_empty() {
        instance.get_words(
            &outputs.word.vrs[words.clone()],
            &mut outputs.word.values[words],
        )?;
    }
    if !outputs.text.is_empty() && !matches!(part, Part::Stable) {
        outputs.text.get(instance)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partition_moves_feedthrough_slots_to_the_tail_keeping_each_groups_order() {
        let mut block = Block::<f64> {
            vrs: vec![10, 11, 12, 13, 14],
            values: vec![0.0, 1.0, 2.0, 3.0, 4.0],
            feedthrough_start: 0,
        };
        let moved = block.partition(&[false, true, false, true, false]);
        assert_eq!(block.vrs, [10, 12, 14, 11, 13]);
        assert_eq!(block.values, [0.0, 2.0, 4.0, 1.0, 3.0]);
        assert_eq!(block.feedthrough_start, 3);
        // Every old slot still finds its value reference.
        for (old, &new) in moved.iter().enumerate() {
            assert_eq!(block.vrs[new], 10 + old as u32);
        }
    }

    #[test]
    fn partition_without_feedthrough_leaves_the_block_as_it_was() {
        let mut block = Block::<i32> {
            vrs: vec![3, 1, 2],
            values: vec![7, 8, 9],
            feedthrough_start: 0,
        };
        assert_eq!(block.partition(&[false; 3]), [0, 1, 2]);
        assert_eq!(block.vrs, [3, 1, 2]);
        assert_eq!(block.feedthrough_start, 3);
    }

    #[test]
    fn copies_group_links_by_source_and_buffer_and_copy_only_their_slots() {
        use Buffer::{Boolean, Integer as Enumeration, Real};
        let link = |buffer, from_unit, from_slot, to_unit, to_slot| Link {
            buffer,
            from_unit,
            from_slot,
            to_unit,
            to_slot,
        };
        let links = [
            link(Real, 1, 2, 0, 0),
            link(Real, 0, 0, 1, 0), // into another unit: not in unit 0's copies
            link(Boolean, 1, 0, 0, 1),
            link(Real, 0, 1, 0, 1), // a unit fed by itself
            link(Enumeration, 1, 1, 0, 0),
        ];
        let groups = Copies::into_unit(&links, 0);
        let run = |from, to, len| SlotRun { from, to, len };
        assert_eq!(groups.len(), 2);
        assert_eq!(groups[0].from_unit, 1);
        assert_eq!(groups[0].real, [run(2, 0, 1)]);
        assert_eq!(groups[0].integer, [run(1, 0, 1)]);
        assert_eq!(groups[0].boolean, [run(0, 1, 1)]);
        assert_eq!(groups[1].from_unit, 0);
        assert_eq!(groups[1].real, [run(1, 1, 1)]);

        let mut from = Io::default();
        from.real.values = vec![1.0, 2.0, 3.0];
        from.integer.values = vec![7, 8];
        from.boolean.values = vec![1];
        let mut to = Io::default();
        to.real.values = vec![-1.0, -2.0];
        to.integer.values = vec![0];
        to.boolean.values = vec![0, 0];
        groups[0].apply(&from, &mut to);
        assert_eq!(to.real.values, [3.0, -2.0]);
        assert_eq!(to.integer.values, [8]);
        assert_eq!(to.boolean.values, [0, 1]);
    }

    #[test]
    fn consecutive_copies_join_into_one_run_and_a_gap_starts_another() {
        let mut runs = Vec::new();
        for (from, to) in [(4, 0), (5, 1), (6, 2), (8, 3), (9, 5)] {
            SlotRun::push(&mut runs, from, to);
        }
        let run = |from, to, len| SlotRun { from, to, len };
        assert_eq!(runs, [run(4, 0, 3), run(8, 3, 1), run(9, 5, 1)]);
        let from = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];
        let mut to = [-1.0; 6];
        copy_slots(&runs, &from, &mut to);
        assert_eq!(to, [4.0, 5.0, 6.0, 8.0, -1.0, 9.0]);
    }

    #[test]
    fn after_the_step_only_what_an_earlier_unit_consumes_is_read() {
        use Buffer::{Boolean, Real};
        let link = |buffer, from_unit, from_slot, to_unit| Link {
            buffer,
            from_unit,
            from_slot,
            to_unit,
            to_slot: 0,
        };
        let io = |real_feedthrough_start, boolean_feedthrough_start| {
            let mut io = Io::default();
            io.real.vrs = vec![0; 4];
            io.real.feedthrough_start = real_feedthrough_start;
            io.boolean.vrs = vec![0; 2];
            io.boolean.feedthrough_start = boolean_feedthrough_start;
            io
        };
        let outputs = [io(4, 2), io(2, 2), io(2, 1), io(4, 2)];
        let links = [
            // unit 1: an earlier unit takes a stable output
            link(Real, 1, 1, 0),
            // unit 2: one stable, one feedthrough output (a Boolean) to earlier units
            link(Real, 2, 0, 0),
            link(Boolean, 2, 1, 1),
            // unit 3: only later units and itself consume it
            link(Real, 3, 3, 3),
            // unit 0 feeds a later unit: its outputs are read at its turn
            link(Real, 0, 0, 3),
        ];
        assert_eq!(
            AfterStep::of(&links, &outputs),
            [
                AfterStep::Nothing,
                AfterStep::Stable,
                AfterStep::All,
                AfterStep::Nothing
            ]
        );
    }

    #[test]
    fn parts_split_a_block_at_its_first_feedthrough_slot() {
        let block = Block::<f64> {
            vrs: vec![1, 2, 3, 4],
            values: vec![0.0; 4],
            feedthrough_start: 3,
        };
        assert_eq!(Part::All.of(&block), 0..4);
        assert_eq!(Part::Stable.of(&block), 0..3);
        assert_eq!(Part::Feedthrough.of(&block), 3..4);
    }

    #[test]
    fn column_runs_join_consecutive_slots_of_one_unit_and_buffer_only() {
        use Buffer::{Boolean, Integer, Real};
        let enumeration = Integer;
        let columns = [
            (0, Real, 0),
            (0, Real, 1),
            (0, Real, 3), // a gap in the slots
            (1, Real, 4), // another unit
            (1, Boolean, 5),
            (1, Integer, 0),
            (1, enumeration, 1), // enumerations share the integer buffer
            (1, Buffer::Word(Fmi3Type::UInt8), 2),
            (1, Buffer::Word(Fmi3Type::UInt8), 3),
            (1, Buffer::Word(Fmi3Type::Int8), 4), // another word type: a run of its own
        ];
        let runs: Vec<_> = ColumnRun::of(&columns)
            .iter()
            .map(|r| (r.unit, block_index(r.buffer), r.slot, r.column, r.len))
            .collect();
        assert_eq!(
            runs,
            [
                (0, 0, 0, 0, 2),
                (0, 0, 3, 2, 1),
                (1, 0, 4, 3, 1),
                (1, 2, 5, 4, 1),
                (1, 1, 0, 5, 2),
                (1, 3, 2, 7, 2),
                (1, 3, 4, 9, 1),
            ]
        );
    }
}
