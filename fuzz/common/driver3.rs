//! The FMI 3.0 fuzzing bodies, shared by the per-FMU fuzz crates beside the FMI 2.0 ones
//! (`driver.rs`), on the test kit's FMI 3.0 driver ([`Fmi3Instance`]).
//!
//! A crash is a panic here: a status outside fmi3OK..fmi3Fatal, `fmi3Fatal` (no input may
//! break an instance), or a non-finite Float64 (an output, a derivative, an event
//! indicator, a continuous state) from a get that reported success.
//!
//! What does not depend on the input is made once per process (each binary fuzzes one
//! model): the table of value references, the instantiation token, the instances, and for
//! `restored_state` an initialized instance with a genuine state, put back after every
//! input; `call_sequence` starts each input with `fmi3Reset` on the instance it uses.
#![allow(dead_code)]

use fmi3_export::variables::{Type, TIME_VR};
use fmi_export::snapshot::{reseal, HEADER_LEN};
use fmi_model::{Kind, Model};
use fmi_testkit::fmi3_ffi::*;
use fmi_testkit::{CoSimulationOptions, Fmi3Functions, Fmi3Instance};
use std::cell::OnceCell;
use std::sync::OnceLock;

/// Value references of the variables a call sequence uses, by type; Float64 with their
/// element counts (an array is one reference).
struct Table {
    float64: Vec<(u32, usize)>,
    /// Every Float64 reference, `time` among them, and the number of values they hold.
    all_float64: (Vec<u32>, usize),
    int32: Vec<u32>,
    enumerations: Vec<u32>,
    booleans: Vec<u32>,
    token: String,
}

fn table<M: Model>() -> &'static Table {
    // One model per fuzz binary, so one table.
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| {
        let declarations = M::declarations();
        let of = |t: Type| -> Vec<u32> {
            declarations
                .iter()
                .filter(|d| Type::of(d) == t)
                .map(|d| d.value_reference)
                .collect()
        };
        let float64: Vec<(u32, usize)> = declarations
            .iter()
            .filter_map(|d| match d.kind {
                Kind::Real { shape, .. } => Some((d.value_reference, shape.len())),
                _ => None,
            })
            .collect();
        let mut all: Vec<u32> = float64.iter().map(|&(vr, _)| vr).collect();
        all.push(TIME_VR);
        let total = float64.iter().map(|&(_, n)| n).sum::<usize>() + 1;
        Table {
            all_float64: (all, total),
            float64,
            int32: of(Type::Int32),
            enumerations: of(Type::Enumeration),
            booleans: of(Type::Boolean),
            token: fmi3_export::instantiation_token::<M>(),
        }
    })
}

/// A status the standard defines, and not fmi3Fatal.
fn no_fatal(inst: &Fmi3Instance, status: fmi3Status, call: &str) {
    assert!(
        (0..=3).contains(&status.0),
        "{call} returned {status:?}: {:?}",
        inst.messages()
    );
}

fn succeeded(status: fmi3Status) -> bool {
    status == fmi3OK || status == fmi3Warning
}

/// All Float64 values, `time` included; finite whenever the get succeeds.
fn check_outputs(inst: &Fmi3Instance, table: &Table) {
    let (vrs, total) = &table.all_float64;
    let (status, values) = inst.get_float64(vrs, *total);
    no_fatal(inst, status, "fmi3GetFloat64");
    if succeeded(status) {
        assert!(
            values.iter().all(|v| v.is_finite()),
            "non-finite output from an accepted state: {values:?}"
        );
    }
}

/// A vector read (derivatives, indicators, states, nominals): finite when it succeeds.
fn check_vector(inst: &Fmi3Instance, (status, values): (fmi3Status, Vec<f64>), call: &str) {
    no_fatal(inst, status, call);
    if succeeded(status) {
        assert!(
            values.iter().all(|v| v.is_finite()),
            "{call}: non-finite values from an accepted state: {values:?}"
        );
    }
}

/// The instance's own time (`time` read as Float64), when it can be read.
fn current_time(inst: &Fmi3Instance) -> Option<f64> {
    let (status, t) = inst.get_float64(&[TIME_VR], 1);
    succeeded(status).then_some(t[0])
}

/// The instance `restored_state` works on, initialized, and its genuine state.
struct Restoring {
    inst: Fmi3Instance,
    genuine: fmi3FMUState,
    serialized: Vec<u8>,
}

/// (a) A payload sealed with a valid header and checksum, then fmi3DeserializeFMUState,
/// and if accepted: set, gets and a step. An odd first byte edits a genuine payload (the
/// rest read as (offset lo, offset hi, byte) triples), so that most inputs decode and reach
/// the validation; otherwise the rest is the payload itself. Afterwards the genuine state
/// is set again, so every input starts from the same instance.
pub fn restored_state<M: Model>(functions: &Fmi3Functions, data: &[u8]) {
    thread_local! {
        static RESTORING: OnceCell<Restoring> = const { OnceCell::new() };
    }
    let table = table::<M>();
    RESTORING.with(|cell| {
        let Restoring {
            inst,
            genuine,
            serialized,
        } = cell.get_or_init(|| {
            let options = CoSimulationOptions {
                early_return_allowed: true,
                ..CoSimulationOptions::default()
            };
            let inst = Fmi3Instance::co_simulation(functions, "fuzz", &table.token, options)
                .unwrap_or_else(|log| panic!("fmi3InstantiateCoSimulation: {log:?}"));
            assert_eq!(inst.enter_initialization_mode(0.0, None), fmi3OK);
            assert_eq!(
                inst.exit_initialization_mode(),
                fmi3OK,
                "{:?}",
                inst.messages()
            );
            let (status, genuine) = inst.get_state();
            assert_eq!(status, fmi3OK);
            let (status, serialized) = inst.serialize(genuine);
            assert_eq!(status, fmi3OK);
            Restoring {
                inst,
                genuine,
                serialized,
            }
        });
        let payload = match data.split_first() {
            Some((mode, edits)) if mode % 2 == 1 => {
                let mut payload = serialized[HEADER_LEN..].to_vec();
                for edit in edits.chunks_exact(3) {
                    let at = usize::from(u16::from_le_bytes([edit[0], edit[1]])) % payload.len();
                    payload[at] = edit[2];
                }
                payload
            }
            Some((_, raw)) => raw.to_vec(),
            None => Vec::new(),
        };
        let (status, state) = inst.deserialize(&reseal(serialized, &payload));
        assert!(status == fmi3OK || status == fmi3Error, "{status:?}");
        if status == fmi3OK {
            no_fatal(inst, inst.set_state(state), "fmi3SetFMUState");
            check_outputs(inst, table);
            if let Some(t) = current_time(inst) {
                no_fatal(inst, inst.do_step(t, 0.01).status, "fmi3DoStep");
                check_outputs(inst, table);
            }
            no_fatal(inst, inst.free_state(state), "fmi3FreeFMUState");
        }
        assert_eq!(inst.set_state(*genuine), fmi3OK, "{:?}", inst.messages());
        inst.logger().clear();
    });
}

/// Reads the fuzzer's bytes as a sequence of choices.
struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn byte(&mut self) -> Option<u8> {
        let (&b, rest) = self.0.split_first()?;
        self.0 = rest;
        Some(b)
    }

    /// A real: one of the values that break arithmetic, or eight raw bytes.
    fn real(&mut self) -> Option<f64> {
        const SPECIAL: [f64; 12] = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.01,
            1e-300,
            1e300,
            f64::MAX,
            f64::MIN_POSITIVE,
            f64::NAN,
            f64::INFINITY,
            1e9,
        ];
        let pick = self.byte()?;
        if usize::from(pick) < SPECIAL.len() {
            return Some(SPECIAL[usize::from(pick)]);
        }
        let raw = self.0.get(..8)?;
        let value = f64::from_le_bytes(raw.try_into().ok()?);
        self.0 = &self.0[8..];
        Some(value)
    }

    fn pick<T: Copy>(&mut self, from: &[T]) -> Option<T> {
        let i = usize::from(self.byte()?);
        from.get(i % from.len().max(1)).copied()
    }
}

/// The instances `call_sequence` uses: Co-Simulation with each choice of the master
/// (early return allowed, Event Mode used), and Model Exchange if the FMU offers it.
struct Instances {
    co_simulation: Vec<Fmi3Instance>,
    model_exchange: Option<Fmi3Instance>,
}

/// (b) A random sequence of calls over the FMI 3.0 C ABI of one instance. The first byte
/// chooses the instance (its low bits: the Co-Simulation options, or Model Exchange) and
/// whether debug logging is on.
pub fn call_sequence<M: Model>(functions: &Fmi3Functions, data: &[u8]) {
    thread_local! {
        static INSTANCES: OnceCell<Instances> = const { OnceCell::new() };
    }
    let table = table::<M>();
    INSTANCES.with(|cell| {
        let instances = cell.get_or_init(|| Instances {
            co_simulation: (0..4)
                .map(|k| {
                    let options = CoSimulationOptions {
                        logging_on: false,
                        early_return_allowed: k & 1 == 1,
                        event_mode_used: k & 2 == 2,
                    };
                    Fmi3Instance::co_simulation(functions, "fuzz", &table.token, options)
                        .unwrap_or_else(|log| panic!("fmi3InstantiateCoSimulation: {log:?}"))
                })
                .collect(),
            model_exchange: Fmi3Instance::model_exchange(functions, "fuzz", &table.token, false)
                .ok(),
        });
        let first = data.first().copied().unwrap_or(0);
        let inst = match (first >> 1) % 5 {
            4 => instances
                .model_exchange
                .as_ref()
                .unwrap_or(&instances.co_simulation[0]),
            k => &instances.co_simulation[usize::from(k)],
        };
        // fmi3Reset puts the instance back as instantiated, for a fraction of a new one.
        assert_eq!(inst.reset(), fmi3OK, "{:?}", inst.messages());
        assert_eq!(inst.set_debug_logging(first % 2 == 1), fmi3OK);
        sequence(inst, table, data.get(1..).unwrap_or_default());
        inst.logger().clear();
    });
}

fn sequence(inst: &Fmi3Instance, table: &Table, data: &[u8]) {
    let mut input = Bytes(data);
    let mut states: Vec<fmi3FMUState> = Vec::new();
    while let Some(op) = input.byte() {
        let status = match op % 24 {
            0 => {
                let (start, stop) = (input.real().unwrap_or(0.0), input.real());
                let stop = stop.filter(|_| op & 0x80 == 0);
                inst.enter_initialization_mode(start, stop)
            }
            1 => inst.exit_initialization_mode(),
            2 => inst.enter_step_mode(),
            3 => inst.enter_event_mode(),
            4 => {
                let t = match input.byte() {
                    Some(b) if b % 4 == 0 => input.real().unwrap_or(0.0),
                    _ => current_time(inst).unwrap_or(0.0),
                };
                let step = inst.do_step(t, input.real().unwrap_or(0.01));
                no_fatal(inst, step.status, "fmi3DoStep");
                if succeeded(step.status) {
                    assert!(
                        !step.last_successful_time.is_nan(),
                        "fmi3DoStep: lastSuccessfulTime NaN after {:?}",
                        step.status
                    );
                }
                step.status
            }
            5 => {
                let (vr, n) = input.pick(&table.float64).unwrap_or((0, 1));
                // Mostly the right number of values, sometimes one too few or too many.
                let n = match input.byte().unwrap_or(0) % 8 {
                    0 => n.saturating_sub(1),
                    1 => n + 1,
                    _ => n,
                };
                let values: Vec<f64> = (0..n).map(|_| input.real().unwrap_or(0.0)).collect();
                inst.set_float64(&[vr], &values)
            }
            6 => {
                check_outputs(inst, table);
                fmi3OK
            }
            7 => {
                let vr = input.pick(&table.int32).unwrap_or(0);
                let v = i32::from_le_bytes([0, 0, 0, 0].map(|_: u8| input.byte().unwrap_or(0)));
                inst.set_int32(&[vr], &[v])
            }
            8 => {
                let vr = input.pick(&table.enumerations).unwrap_or(0);
                let v = i64::from(input.byte().unwrap_or(0) as i8);
                inst.set_int64(&[vr], &[v])
            }
            9 => {
                let vr = input.pick(&table.booleans).unwrap_or(0);
                inst.set_booleans(&[vr], &[input.byte().unwrap_or(0) % 2 == 1])
            }
            10 => {
                let (s, state) = inst.get_state();
                if s == fmi3OK {
                    states.push(state);
                }
                s
            }
            11 => match input.pick(&states) {
                Some(state) => inst.set_state(state),
                None => fmi3OK,
            },
            12 => {
                let i = usize::from(input.byte().unwrap_or(0));
                if states.is_empty() {
                    fmi3OK
                } else {
                    let state = states.swap_remove(i % states.len());
                    inst.free_state(state)
                }
            }
            13 => match input.pick(&states) {
                Some(state) => {
                    let (s, bytes) = inst.serialize(state);
                    no_fatal(inst, s, "fmi3SerializeFMUState");
                    let (s, copy) = inst.deserialize(&bytes);
                    if s == fmi3OK {
                        states.push(copy);
                    }
                    s
                }
                None => fmi3OK,
            },
            14 => inst.reset(),
            15 => inst.terminate(),
            16 => inst.set_debug_logging(op > 128),
            17 => {
                let update = inst.update_discrete_states();
                no_fatal(inst, update.status, "fmi3UpdateDiscreteStates");
                update.status
            }
            18 => inst.enter_continuous_time_mode(),
            19 => inst.set_time(input.real().unwrap_or(0.0)),
            20 => inst.completed_integrator_step().0,
            21 => {
                let (s, n) = inst.number_of_continuous_states();
                no_fatal(inst, s, "fmi3GetNumberOfContinuousStates");
                let n = if s == fmi3OK { n.min(64) } else { 0 };
                let n = match input.byte().unwrap_or(0) % 8 {
                    0 => n.saturating_sub(1),
                    1 => n + 1,
                    _ => n,
                };
                let x: Vec<f64> = (0..n).map(|_| input.real().unwrap_or(0.0)).collect();
                inst.set_continuous_states(&x)
            }
            22 => {
                let (s, n) = inst.number_of_continuous_states();
                no_fatal(inst, s, "fmi3GetNumberOfContinuousStates");
                let n = if s == fmi3OK { n.min(64) } else { 0 };
                check_vector(inst, inst.continuous_states(n), "fmi3GetContinuousStates");
                check_vector(
                    inst,
                    inst.derivatives(n),
                    "fmi3GetContinuousStateDerivatives",
                );
                check_vector(inst, inst.nominals(n), "fmi3GetNominalsOfContinuousStates");
                fmi3OK
            }
            _ => {
                let (s, m) = inst.number_of_event_indicators();
                no_fatal(inst, s, "fmi3GetNumberOfEventIndicators");
                let m = if s == fmi3OK { m.min(64) } else { 0 };
                check_vector(inst, inst.event_indicators(m), "fmi3GetEventIndicators");
                fmi3OK
            }
        };
        no_fatal(inst, status, &format!("operation {}", op % 24));
        if status == fmi3OK {
            check_outputs(inst, table);
        }
    }
    for state in states {
        inst.free_state(state);
    }
}
