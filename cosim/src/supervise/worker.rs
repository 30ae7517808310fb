//! The worker side: a process that owns the FMUs of one system, runs it when told, passes
//! its rows through the ring and answers over its stdin and stdout. Whatever FMU code does to
//! this process (crash, exit, hang), the parent outlives it and tells what happened.
#![allow(unsafe_code)]

use super::protocol::{receive, send, FromWorker, ToWorker, WireError};
use super::shared::{BlackBox, Ring};
use crate::master::{MasterError, Recorder, Simulation};
use std::fs::File;
use std::io::{BufReader, BufWriter};
use std::path::Path;

type Input = BufReader<File>;
type Output = BufWriter<File>;

/// Takes stdin and stdout for the protocol and points fd 1 at stderr, so that whatever FMU
/// code prints cannot corrupt the parent's stream (and still reaches the user), and fd 0 at
/// /dev/null.
#[cfg(unix)]
fn protocol_streams() -> std::io::Result<(Input, Output)> {
    use std::os::fd::FromRawFd;
    // SAFETY: plain descriptor calls on this process's own standard descriptors; each result
    // is checked before use and owned by exactly one File.
    unsafe {
        let input = libc::dup(0);
        let output = libc::dup(1);
        if input < 0 || output < 0 || libc::dup2(2, 1) < 0 {
            return Err(std::io::Error::last_os_error());
        }
        let null = libc::open(c"/dev/null".as_ptr(), libc::O_RDONLY);
        if null >= 0 {
            libc::dup2(null, 0);
            libc::close(null);
        }
        Ok((
            BufReader::new(File::from_raw_fd(input)),
            BufWriter::new(File::from_raw_fd(output)),
        ))
    }
}

/// As on Unix: the protocol gets copies of the standard input and output handles, and
/// standard output (the C runtime's fd 1 and the process's handle, which Rust's `print!`
/// reads) is pointed at standard error.
#[cfg(windows)]
fn protocol_streams() -> std::io::Result<(Input, Output)> {
    use std::os::windows::io::AsHandle;
    use windows_sys::Win32::System::Console::{
        GetStdHandle, SetStdHandle, STD_ERROR_HANDLE, STD_OUTPUT_HANDLE,
    };
    let input = std::io::stdin().as_handle().try_clone_to_owned()?;
    let output = std::io::stdout().as_handle().try_clone_to_owned()?;
    // SAFETY: plain calls on this process's own standard handles and descriptors.
    unsafe {
        if SetStdHandle(STD_OUTPUT_HANDLE, GetStdHandle(STD_ERROR_HANDLE)) == 0 {
            return Err(std::io::Error::last_os_error());
        }
        libc::dup2(2, 1);
    }
    Ok((
        BufReader::new(File::from(input)),
        BufWriter::new(File::from(output)),
    ))
}

/// Runs the worker until the parent closes its stdin; the process's exit code.
pub(super) fn serve(dir: &Path) -> i32 {
    let (mut input, mut output) = match protocol_streams() {
        Ok(streams) => streams,
        Err(error) => {
            eprintln!("harness worker: cannot take its standard streams: {error}");
            return 70;
        }
    };
    match BlackBox::open(&dir.join(super::BLACK_BOX)) {
        Ok(black_box) => black_box.install(),
        Err(error) => {
            eprintln!("harness worker: cannot map its black box: {error}");
            return 70;
        }
    }
    let mut worker = Worker {
        simulation: None,
        ring: None,
    };
    loop {
        let message = match receive::<ToWorker>(&mut input) {
            Ok(Some(message)) => message,
            // The parent is done with us (or gone).
            Ok(None) | Err(_) => return 0,
        };
        let answered = worker.answer(message, &mut input, &mut output, dir);
        if answered.is_err() {
            return 0;
        }
    }
}

struct Worker {
    simulation: Option<Simulation>,
    ring: Option<Ring>,
}

fn failed(error: &MasterError, rows: u64) -> FromWorker {
    FromWorker::Failed {
        rows,
        error: WireError::from(error),
    }
}

impl Worker {
    fn answer(
        &mut self,
        message: ToWorker,
        input: &mut Input,
        output: &mut Output,
        dir: &Path,
    ) -> std::io::Result<()> {
        match message {
            ToWorker::Setup {
                system,
                fmu_dir,
                conventions,
                final_columns,
            } => {
                let built = Simulation::new(*system, &fmu_dir).and_then(|mut simulation| {
                    simulation.set_conventions(conventions);
                    if !final_columns.is_empty() {
                        simulation.set_final_columns(&final_columns)?;
                    }
                    Ok(simulation)
                });
                let simulation = match built {
                    Ok(simulation) => simulation,
                    Err(error) => return send(output, &failed(&error, 0)),
                };
                let width = simulation.column_names().len();
                let ring = match Ring::create(&dir.join(super::RING), width) {
                    Ok(ring) => ring,
                    Err(error) => {
                        let error = MasterError::Worker {
                            message: format!("cannot create the worker's row ring: {error}"),
                        };
                        return send(output, &failed(&error, 0));
                    }
                };
                let ready = FromWorker::Ready {
                    column_names: simulation.column_names().to_vec(),
                    column_units: simulation.column_units().to_vec(),
                    column_types: simulation.column_types(),
                    final_names: simulation.final_column_names().to_vec(),
                    ring_capacity: ring.capacity as u64,
                };
                self.simulation = Some(simulation);
                self.ring = Some(ring);
                send(output, &ready)
            }
            ToWorker::SetFinal { names } => {
                let Some(simulation) = self.simulation.as_mut() else {
                    return Ok(());
                };
                match simulation.set_final_columns(&names) {
                    Ok(()) => send(
                        output,
                        &FromWorker::FinalSet {
                            names: simulation.final_column_names().to_vec(),
                        },
                    ),
                    Err(error) => send(output, &failed(&error, 0)),
                }
            }
            ToWorker::Run {
                parameters,
                events,
                conventions,
                checkpoints,
            } => {
                let (Some(simulation), Some(ring)) = (self.simulation.as_mut(), self.ring.as_ref())
                else {
                    return Ok(());
                };
                for (instance, variable, value) in parameters {
                    if let Err(error) = simulation.set_parameter(&instance, &variable, value) {
                        return send(output, &failed(&error, 0));
                    }
                }
                for (name, change) in events {
                    if let Err(error) = simulation.change_event(&name, &change) {
                        return send(output, &failed(&error, 0));
                    }
                }
                simulation.set_conventions(conventions);
                if let Err(error) = simulation.set_checkpoints(*checkpoints) {
                    return send(output, &failed(&error, 0));
                }
                ring.set_written(0);
                let mut recorder = RingRecorder {
                    ring,
                    rows: 0,
                    taken: 0,
                    stop: None,
                    input,
                    output,
                    broken: None,
                };
                let result = simulation.run(&mut recorder);
                let rows = recorder.rows;
                if let Some(error) = recorder.broken.take() {
                    return Err(error);
                }
                let answer = match result {
                    Ok(end) => FromWorker::Done {
                        rows,
                        end,
                        final_values: simulation.final_values().to_vec(),
                        events: simulation
                            .model_exchange_events()
                            .into_iter()
                            .map(|(name, events)| (name.to_owned(), events))
                            .collect(),
                        saved_at: simulation.saved_at(),
                    },
                    Err(error) => failed(&error, rows),
                };
                send(output, &answer)
            }
            // An acknowledgement that arrives after its run ended says nothing new.
            ToWorker::Ack { .. } => Ok(()),
        }
    }
}

/// Puts each row in the ring and tells the parent whenever a half is full, waiting for it
/// only when the next row would overwrite one it has not taken.
struct RingRecorder<'a> {
    ring: &'a Ring,
    rows: u64,
    taken: u64,
    stop: Option<String>,
    input: &'a mut Input,
    output: &'a mut Output,
    /// The pipe to the parent broke: the run is abandoned.
    broken: Option<std::io::Error>,
}

impl RingRecorder<'_> {
    fn wait_for_room(&mut self) {
        let slots = 2 * self.ring.capacity as u64;
        while self.broken.is_none() && self.rows >= self.taken + slots {
            match receive::<ToWorker>(self.input) {
                Ok(Some(ToWorker::Ack { upto, stop })) => {
                    self.taken = self.taken.max(upto);
                    if stop.is_some() {
                        self.stop = stop;
                    }
                }
                Ok(Some(_)) => {}
                Ok(None) => {
                    self.broken = Some(std::io::ErrorKind::UnexpectedEof.into());
                }
                Err(error) => self.broken = Some(error),
            }
        }
    }
}

impl Recorder for RingRecorder<'_> {
    fn record(&mut self, time: f64, values: &[f64]) {
        self.wait_for_room();
        if self.broken.is_some() {
            return;
        }
        self.ring.write(self.rows, time, values);
        self.rows += 1;
        if self.rows.is_multiple_of(self.ring.capacity as u64) {
            if let Err(error) = send(self.output, &FromWorker::Rows { upto: self.rows }) {
                self.broken = Some(error);
            }
        }
    }

    fn record_text(&mut self, column: usize, text: &str) {
        if self.broken.is_some() {
            return;
        }
        let message = FromWorker::Text {
            row: self.rows,
            column: column as u64,
            text: text.to_owned(),
        };
        if let Err(error) = send(self.output, &message) {
            self.broken = Some(error);
        }
    }

    fn failure(&self) -> Option<String> {
        match (&self.broken, &self.stop) {
            (Some(error), _) => Some(format!("the parent process is gone: {error}")),
            (None, Some(stop)) => Some(stop.clone()),
            (None, None) => None,
        }
    }
}
