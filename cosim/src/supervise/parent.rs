//! The parent side: a [`Simulation`](crate::master::Simulation) that lives in a worker
//! process, driven as if it were here. Rows come back through the shared ring into the
//! caller's recorder; a worker that crashes, exits or hangs becomes an [`Abnormal`] error
//! with the call it was in, after every row it recorded has been handed on.
#![allow(unsafe_code)]

use super::protocol::{receive, send, FromWorker, ToWorker};
use super::shared::{BlackBox, Ring};
use super::{BLACK_BOX, RING, WORKER_FLAG};
use crate::abnormal::{Abnormal, How};
use crate::limits::Limits;
use crate::master::{Checkpoints, Conventions, EventCounts, MasterError, Recorder, RunEnd};
use crate::system::event::Change;
use crate::system::{ParamValue, SystemDescription};
use fmi_import::FmiVersion;
use model_description::ModelDescription;
use std::io::{BufWriter, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How often the parent looks at a worker that says nothing.
const TICK: Duration = Duration::from_millis(50);
/// How long a worker told to quit may take before it is killed.
const QUIT_GRACE: Duration = Duration::from_secs(5);
/// The most of a worker's stderr kept for a report (the newest bytes).
const STDERR_KEPT: usize = 256 * 1024;

enum Incoming {
    Message(FromWorker),
    Closed,
}

struct Worker {
    child: Child,
    /// `None` once closed, which tells the worker to free its instances and exit.
    to: Option<BufWriter<ChildStdin>>,
    messages: Receiver<Incoming>,
    black_box: BlackBox,
    ring: Option<Ring>,
    /// Says when the worker's stderr has all been passed on.
    stderr_done: Receiver<()>,
    /// Calls the black box had counted when the parent last saw progress, and when.
    seen_calls: u64,
    since: Instant,
    // Last: removed after the worker has gone, with the FMUs it unpacked under it.
    dir: tempfile::TempDir,
}

/// A system that runs in a supervised worker process.
pub struct Supervised {
    program: PathBuf,
    limits: Limits,
    system: SystemDescription,
    fmu_dir: PathBuf,
    conventions: Conventions,
    descriptions: Vec<(FmiVersion, ModelDescription)>,
    column_names: Vec<String>,
    column_units: Vec<String>,
    column_types: Vec<crate::results::ColumnType>,
    final_requested: Vec<String>,
    final_names: Vec<String>,
    final_values: Vec<f64>,
    /// Parameters set since the worker last ran; a new worker gets them in its system.
    pending: Vec<(String, String, ParamValue)>,
    /// Events changed since the worker last ran; a new worker gets them in its system too.
    pending_events: Vec<(String, Change)>,
    events: Vec<(String, EventCounts)>,
    /// Sent with every run; where the last one saved.
    checkpoints: Checkpoints,
    saved_at: Option<f64>,
    worker: Option<Worker>,
    stderr: Arc<Mutex<Vec<u8>>>,
}

fn broken(reason: String) -> MasterError {
    MasterError::Abnormal(Box::new(Abnormal {
        how: How::Broken(reason),
        last_call: None,
        memory_limit_bytes: 0,
    }))
}

impl Supervised {
    pub(super) fn new(
        system: SystemDescription,
        fmu_dir: &Path,
        program: PathBuf,
        limits: Limits,
    ) -> Result<Self, MasterError> {
        crate::master::check_fmus_exist(&system, fmu_dir)?;
        let mut supervised = Self {
            program,
            limits,
            system,
            fmu_dir: fmu_dir.to_owned(),
            conventions: Conventions::default(),
            descriptions: Vec::new(),
            column_names: Vec::new(),
            column_units: Vec::new(),
            column_types: Vec::new(),
            final_requested: Vec::new(),
            final_names: Vec::new(),
            final_values: Vec::new(),
            pending: Vec::new(),
            pending_events: Vec::new(),
            events: Vec::new(),
            checkpoints: Checkpoints::default(),
            saved_at: None,
            worker: None,
            stderr: Arc::new(Mutex::new(Vec::new())),
        };
        // The worker loads the FMUs while this process reads their descriptions.
        let started = supervised.start()?;
        let mut descriptions = Vec::with_capacity(supervised.system.instances.len());
        for instance in &supervised.system.instances {
            let path = crate::master::fmu_path(fmu_dir, &instance.fmu);
            let description =
                fmi_import::peek_description(&path).map_err(|source| MasterError::Load {
                    instance: instance.name.clone(),
                    path,
                    source: Box::new(source),
                })?;
            descriptions.push(description);
        }
        supervised.descriptions = descriptions;
        supervised.finish_start(started)?;
        Ok(supervised)
    }

    pub fn system(&self) -> &SystemDescription {
        &self.system
    }

    pub fn descriptions(&self) -> &[(FmiVersion, ModelDescription)] {
        &self.descriptions
    }

    pub fn column_names(&self) -> &[String] {
        &self.column_names
    }

    pub fn column_units(&self) -> &[String] {
        &self.column_units
    }

    pub fn column_types(&self) -> Vec<crate::results::ColumnType> {
        self.column_types.clone()
    }

    pub fn final_column_names(&self) -> &[String] {
        &self.final_names
    }

    pub fn final_values(&self) -> &[f64] {
        &self.final_values
    }

    pub fn model_exchange_events(&self) -> &[(String, EventCounts)] {
        &self.events
    }

    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    /// What the workers wrote to stderr since the last call (the newest 256 KiB), which the
    /// parent also passed on to its own stderr as it came.
    pub fn take_stderr(&self) -> String {
        let mut kept = self.stderr.lock().unwrap_or_else(|e| e.into_inner());
        String::from_utf8_lossy(&std::mem::take(&mut *kept)).into_owned()
    }

    pub fn set_conventions(&mut self, conventions: Conventions) {
        self.conventions = conventions;
    }

    /// Checked here against the FMUs' descriptions, and by the worker with its FMUs (the
    /// save point, the exchange's layout) before the run's first step.
    pub fn set_checkpoints(&mut self, checkpoints: Checkpoints) -> Result<(), MasterError> {
        let describe = |i: usize| self.descriptions[i].clone();
        crate::master::check_checkpoints(
            &self.system,
            &self.conventions,
            &self.column_names,
            &checkpoints,
            &describe,
        )
        .map_err(|message| MasterError::Checkpoint { message })?;
        self.checkpoints = checkpoints;
        Ok(())
    }

    pub fn saved_at(&self) -> Option<f64> {
        self.saved_at
    }

    /// Recorded here and sent with the next run; the worker checks the name and type then.
    pub fn set_parameter(
        &mut self,
        instance: &str,
        variable: &str,
        value: ParamValue,
    ) -> Result<(), MasterError> {
        if !self.system.set_parameter(instance, variable, value.clone()) {
            let names = self.system.instances.iter().map(|i| i.name.as_str());
            return Err(MasterError::Resolve {
                system: self.system.name.clone(),
                problems: vec![format!(
                    "no instance named '{instance}'{}",
                    crate::suggest::hint(instance, names)
                )],
            });
        }
        self.pending
            .push((instance.to_owned(), variable.to_owned(), value));
        Ok(())
    }

    /// Checked and recorded here, sent with the next run.
    pub fn change_event(&mut self, name: &str, change: &Change) -> Result<(), MasterError> {
        self.system
            .change_event(name, change)
            .map_err(|problem| MasterError::Resolve {
                system: self.system.name.clone(),
                problems: vec![problem],
            })?;
        self.pending_events.push((name.to_owned(), change.clone()));
        Ok(())
    }

    pub fn set_final_columns(&mut self, names: &[String]) -> Result<(), MasterError> {
        self.final_requested = names.to_vec();
        let limits = self.limits;
        let worker = self.worker()?;
        let deadline = Instant::now() + limits.run_timeout();
        let answer = worker
            .send(&ToWorker::SetFinal {
                names: names.to_vec(),
            })
            .and_then(|()| worker.next(deadline, &limits));
        match answer {
            Ok(FromWorker::FinalSet { names }) => {
                self.final_values = vec![f64::NAN; names.len()];
                self.final_names = names;
                Ok(())
            }
            Ok(FromWorker::Failed { error, .. }) => Err(error.into()),
            Ok(other) => Err(self.lose_worker(broken(format!("answered {other:?}")))),
            Err(error) => Err(self.lose_worker(error)),
        }
    }

    /// Runs the system in the worker (a new one if the last died), handing every row to
    /// `recorder` as [`crate::master::Simulation::run`] does.
    pub fn run(&mut self, recorder: &mut dyn Recorder) -> Result<RunEnd, MasterError> {
        self.final_values.fill(f64::NAN);
        self.events.clear();
        self.saved_at = None;
        let parameters = std::mem::take(&mut self.pending);
        let events = std::mem::take(&mut self.pending_events);
        let limits = self.limits;
        let (conventions, width) = (self.conventions, self.column_names.len());
        let rows_hint = {
            let s = &self.system;
            ((s.stop_time - s.start_time) / s.step_size).ceil().max(0.0) as usize + 1
        };
        let checkpoints = Box::new(self.checkpoints.clone());
        let worker = self.worker()?;
        let deadline = Instant::now() + limits.run_timeout();
        recorder.reserve(rows_hint, width);
        // Rows handed on, and the first row the recorder could not keep (the run ends there,
        // as it does in process, though the worker has flown a little further).
        let mut hand = Hand::default();
        let mut answer = worker.send(&ToWorker::Run {
            parameters,
            events,
            conventions,
            checkpoints,
        });
        let error = loop {
            if let Err(error) = answer {
                break error;
            }
            match worker.next(deadline, &limits) {
                Ok(FromWorker::Text { row, column, text }) => {
                    hand.texts.push_back((row, column as usize, text));
                    answer = Ok(());
                }
                Ok(FromWorker::Rows { upto }) => {
                    worker.hand_on(&mut hand, upto, recorder);
                    let stop = hand.failed.as_ref().map(|(_, reason)| reason.clone());
                    // A worker that died meanwhile is noticed at the next message.
                    answer = Ok(());
                    let _ = worker.send(&ToWorker::Ack { upto, stop });
                }
                Ok(FromWorker::Done {
                    rows,
                    end,
                    final_values,
                    events,
                    saved_at,
                }) => {
                    worker.hand_on(&mut hand, rows, recorder);
                    if let Some(error) = hand.record_error() {
                        return Err(error);
                    }
                    self.final_values = final_values;
                    self.events = events;
                    self.saved_at = saved_at;
                    return Ok(end);
                }
                Ok(FromWorker::Failed { rows, error }) => {
                    worker.hand_on(&mut hand, rows, recorder);
                    return Err(hand.record_error().unwrap_or_else(|| error.into()));
                }
                Ok(other) => break broken(format!("answered {other:?} during a run")),
                Err(error) => break error,
            }
        };
        // The worker is gone: the rows it wrote before are still in the ring.
        if let Some(ring) = &worker.ring {
            let written = ring.written();
            worker.hand_on(&mut hand, written, recorder);
        }
        Err(self.lose_worker(error))
    }

    /// The live worker, started (with the system as it is now) if there is none.
    fn worker(&mut self) -> Result<&mut Worker, MasterError> {
        if self.worker.is_none() {
            let started = self.start()?;
            self.finish_start(started)?;
        }
        Ok(self.worker.as_mut().expect("started above"))
    }

    /// Starts a worker and sends it the system; it loads while the caller goes on.
    fn start(&mut self) -> Result<(Worker, Instant), MasterError> {
        let mut worker = Worker::spawn(&self.program, &self.limits, &self.stderr)?;
        let deadline = Instant::now() + self.limits.run_timeout();
        worker.send(&ToWorker::Setup {
            system: Box::new(self.system.clone()),
            fmu_dir: self.fmu_dir.clone(),
            conventions: self.conventions,
            final_columns: self.final_requested.clone(),
        })?;
        Ok((worker, deadline))
    }

    /// Waits for a started worker to be ready and makes it the live one.
    fn finish_start(
        &mut self,
        (mut worker, deadline): (Worker, Instant),
    ) -> Result<(), MasterError> {
        match worker.next(deadline, &self.limits)? {
            FromWorker::Ready {
                column_names,
                column_units,
                column_types,
                final_names,
                ring_capacity,
            } => {
                let ring = Ring::open(
                    &worker.dir.path().join(RING),
                    column_names.len(),
                    ring_capacity as usize,
                )
                .map_err(|e| broken(format!("cannot map its row ring: {e}")))?;
                worker.ring = Some(ring);
                self.column_names = column_names;
                self.column_units = column_units;
                self.column_types = column_types;
                self.final_values = vec![f64::NAN; final_names.len()];
                self.final_names = final_names;
                self.pending.clear();
                self.pending_events.clear();
                self.worker = Some(worker);
                Ok(())
            }
            FromWorker::Failed { error, .. } => Err(error.into()),
            other => Err(broken(format!("answered {other:?} to its setup"))),
        }
    }

    /// Drops the worker (killing it if it still runs, removing its directory) and returns
    /// `error`.
    fn lose_worker(&mut self, error: MasterError) -> MasterError {
        if let Some(mut worker) = self.worker.take() {
            worker.kill();
        }
        error
    }
}

/// The rows of a run handed on so far, and the first the recorder could not keep.
#[derive(Default)]
struct Hand {
    taken: u64,
    failed: Option<(f64, String)>,
    /// Text values (row, column, text) not yet handed on, in the order sent.
    texts: std::collections::VecDeque<(u64, usize, String)>,
}

impl Hand {
    /// The error of the first row the recorder could not keep, as the master gives it.
    fn record_error(&self) -> Option<MasterError> {
        let (time, reason) = self.failed.clone()?;
        Some(MasterError::Record { time, reason })
    }
}

impl Worker {
    fn spawn(
        program: &Path,
        limits: &Limits,
        stderr: &Arc<Mutex<Vec<u8>>>,
    ) -> Result<Self, MasterError> {
        let dir = tempfile::Builder::new()
            .prefix("harness-worker-")
            .tempdir()
            .map_err(|e| broken(format!("cannot create its directory: {e}")))?;
        let black_box = BlackBox::create(&dir.path().join(BLACK_BOX))
            .map_err(|e| broken(format!("cannot create its black box: {e}")))?;
        let tmp = dir.path().join("tmp");
        std::fs::create_dir(&tmp)
            .map_err(|e| broken(format!("cannot create its directory: {e}")))?;
        let mut command = Command::new(program);
        command
            .arg(WORKER_FLAG)
            .arg(dir.path())
            // FMUs unpack under the worker's directory, which the parent removes whatever
            // happens to the worker.
            .env("TMPDIR", &tmp)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        // The bound on what an archive may unpack to, as this process has it (a command-line
        // setting included), holds in the worker too.
        if let Ok(bytes) = fmi_abi::unpack::max_unpacked_bytes() {
            command.env(fmi_abi::unpack::MAX_UNPACKED_BYTES_ENV, bytes.to_string());
        }
        let memory = limits.memory_bytes();
        #[cfg(unix)]
        {
            use std::os::unix::process::CommandExt;
            // SAFETY: only async-signal-safe calls between fork and exec.
            unsafe {
                command.pre_exec(move || {
                    // A worker never outlives its parent.
                    #[cfg(target_os = "linux")]
                    libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL);
                    if memory > 0 {
                        let limit = libc::rlimit {
                            rlim_cur: memory as libc::rlim_t,
                            rlim_max: memory as libc::rlim_t,
                        };
                        libc::setrlimit(libc::RLIMIT_AS, &limit);
                    }
                    Ok(())
                });
            }
        }
        // Windows has no address-space limit to set before the worker starts (a job object
        // would be one); there the memory limit is not enforced, as docs/robustness.md says.
        #[cfg(not(unix))]
        let _ = memory;
        let mut child = command.spawn().map_err(|e| {
            broken(format!(
                "cannot start {} as a worker: {e}",
                program.display()
            ))
        })?;
        let to = Some(BufWriter::new(child.stdin.take().expect("piped")));
        let mut from = std::io::BufReader::new(child.stdout.take().expect("piped"));
        let mut err = child.stderr.take().expect("piped");
        let (sender, messages) = std::sync::mpsc::channel();
        // Neither thread is joined: a process the FMU started may hold the pipes open.
        std::thread::spawn(move || loop {
            match receive::<FromWorker>(&mut from) {
                Ok(Some(message)) => {
                    if sender.send(Incoming::Message(message)).is_err() {
                        return;
                    }
                }
                Ok(None) | Err(_) => {
                    let _ = sender.send(Incoming::Closed);
                    return;
                }
            }
        });
        let kept = Arc::clone(stderr);
        let (done, stderr_done) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut buffer = [0u8; 8192];
            loop {
                match err.read(&mut buffer) {
                    Ok(0) | Err(_) => {
                        let _ = done.send(());
                        return;
                    }
                    Ok(n) => {
                        let _ = std::io::stderr().write_all(&buffer[..n]);
                        let mut kept = kept.lock().unwrap_or_else(|e| e.into_inner());
                        kept.extend_from_slice(&buffer[..n]);
                        if kept.len() > STDERR_KEPT {
                            let excess = kept.len() - STDERR_KEPT;
                            kept.drain(..excess);
                        }
                    }
                }
            }
        });
        Ok(Self {
            child,
            to,
            messages,
            black_box,
            ring: None,
            stderr_done,
            seen_calls: 0,
            since: Instant::now(),
            dir,
        })
    }

    fn send(&mut self, message: &ToWorker) -> Result<(), MasterError> {
        // A broken pipe means the worker is gone; the next message says how.
        if let Some(to) = self.to.as_mut() {
            let _ = send(to, message);
        }
        Ok(())
    }

    /// Hands rows `hand.taken..upto` of the ring to `recorder`, up to the first it cannot
    /// keep.
    fn hand_on(&self, hand: &mut Hand, upto: u64, recorder: &mut dyn Recorder) {
        let Some(ring) = &self.ring else { return };
        // Never more than the ring holds: a worker cannot make the parent read stale slots.
        let first = hand
            .taken
            .max(upto.saturating_sub(2 * ring.capacity as u64));
        for row in first..upto {
            if hand.failed.is_some() {
                break;
            }
            while let Some((_, column, text)) = hand.texts.front().filter(|t| t.0 <= row) {
                recorder.record_text(*column, text);
                hand.texts.pop_front();
            }
            let (time, values) = ring.read(row);
            recorder.record(time, values);
            if let Some(reason) = recorder.failure() {
                hand.failed = Some((time, reason));
            }
        }
        hand.taken = hand.taken.max(upto);
    }

    /// The worker's next message, or how it ended without one.
    fn next(&mut self, deadline: Instant, limits: &Limits) -> Result<FromWorker, MasterError> {
        self.since = Instant::now();
        loop {
            let now = Instant::now();
            // Checked before every wait, not only after a quiet one: a worker that keeps
            // sending (rows ready, a fast run) would otherwise never meet its run limit.
            if now >= deadline {
                return Err(self.ended(Some(How::RunTimeout(limits.run_timeout_s())), limits));
            }
            let wait = TICK.min(deadline.saturating_duration_since(now));
            match self.messages.recv_timeout(wait) {
                Ok(Incoming::Message(message)) => return Ok(message),
                Ok(Incoming::Closed) | Err(RecvTimeoutError::Disconnected) => {
                    return Err(self.ended(None, limits))
                }
                Err(RecvTimeoutError::Timeout) => {}
            }
            if let Ok(Some(_)) = self.child.try_wait() {
                // Exited, but its stdout is still open elsewhere (a process it started):
                // what it sent before is in the channel.
                if let Ok(Incoming::Message(message)) = self.messages.try_recv() {
                    return Ok(message);
                }
                return Err(self.ended(None, limits));
            }
            let now = Instant::now();
            if let Some(call) = self.black_box.last_call() {
                if call.calls != self.seen_calls {
                    self.seen_calls = call.calls;
                    self.since = now;
                }
            }
            if now.duration_since(self.since) > limits.call_timeout() {
                return Err(self.ended(Some(How::CallTimeout(limits.call_timeout_s())), limits));
            }
            if now >= deadline {
                return Err(self.ended(Some(How::RunTimeout(limits.run_timeout_s())), limits));
            }
        }
    }

    /// Ends the worker (killing it for a timeout) and says how it ended.
    fn ended(&mut self, timeout: Option<How>, limits: &Limits) -> MasterError {
        let how = match timeout {
            Some(how) => {
                let _ = self.child.kill();
                let _ = self.child.wait();
                how
            }
            None => self.exit_status(),
        };
        MasterError::Abnormal(Box::new(Abnormal {
            how,
            last_call: self.black_box.last_call().filter(|call| call.calls > 0),
            // Named only when the user set it: the default is far from any real allocation.
            memory_limit_bytes: limits.memory_mb.map_or(0, |_| limits.memory_bytes()),
        }))
    }

    /// How the worker ended, waiting a little for it (and killing it if it does not).
    fn exit_status(&mut self) -> How {
        let started = Instant::now();
        let status = loop {
            match self.child.try_wait() {
                Ok(Some(status)) => break Some(status),
                Ok(None) if started.elapsed() < QUIT_GRACE => {
                    std::thread::sleep(Duration::from_millis(5))
                }
                _ => {
                    let _ = self.child.kill();
                    break self.child.wait().ok();
                }
            }
        };
        #[cfg(unix)]
        let signal = |status: std::process::ExitStatus| {
            use std::os::unix::process::ExitStatusExt;
            status.signal()
        };
        // Windows ends a crashed process with an exit code (an NTSTATUS), never a signal.
        #[cfg(not(unix))]
        let signal = |_: std::process::ExitStatus| None::<i32>;
        match status {
            Some(status) => match (status.code(), signal(status)) {
                (Some(code), _) => How::Exited(code),
                (None, Some(signal)) => How::Signal(signal),
                (None, None) => How::Broken("ended in an unknown way".into()),
            },
            None => How::Broken("could not be waited for".into()),
        }
    }

    fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        drop(self.to.take());
        let started = Instant::now();
        loop {
            match self.child.try_wait() {
                Ok(Some(_)) | Err(_) => break,
                Ok(None) if started.elapsed() < QUIT_GRACE => {
                    std::thread::sleep(Duration::from_millis(2))
                }
                Ok(None) => {
                    self.kill();
                    break;
                }
            }
        }
        // What it wrote last (a C library flushes its buffers at exit) reaches our stderr
        // before we go on, unless a process it started keeps the pipe open.
        let _ = self.stderr_done.recv_timeout(Duration::from_secs(1));
    }
}
