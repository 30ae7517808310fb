//! The fuzzing bodies, shared by the per-FMU fuzz crates (each FMU exports the same C
//! symbols, so each is linked into a crate of its own and includes this file).
//!
//! A crash is a panic here: a status the standard does not allow for the call, `fmi2Fatal`
//! (no input may break an instance), or a non-finite value from a get that reported success.
//!
//! What does not depend on the input is made once per process (each binary fuzzs one model):
//! the table of value references, the GUID, and for `restored_state` an initialized
//! instance with a genuine state, put back after every input. Building them per input
//! (two GUID hashes over the whole variable table, an instantiation, an initialization)
//! was most of the time an execution took.
#![allow(dead_code)]

use fmi2_export::variable::{Access, Variable};
use fmi_export::snapshot::{reseal, HEADER_LEN};
use fmi_model::Model;
use fmi_testkit::fmi2::*;
use fmi_testkit::{Fmi2Functions, Instance};
use std::cell::OnceCell;
use std::sync::OnceLock;

/// Value references of the variables a call sequence uses, by type.
struct Table {
    reals: Vec<u32>,
    integers: Vec<u32>,
    booleans: Vec<u32>,
    guid: String,
}

fn table<M: Model>() -> &'static Table {
    // One model per fuzz binary, so one table.
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| {
        let all: Vec<Variable<M>> = fmi2_export::variables::<M>();
        let of = |keep: fn(&Access<M>) -> bool| {
            let mut vrs: Vec<u32> = all
                .iter()
                .filter(|v| keep(&v.access))
                .map(|v| v.value_reference)
                .collect();
            vrs.dedup();
            vrs
        };
        Table {
            reals: of(|a| matches!(a, Access::Real { .. })),
            integers: of(|a| matches!(a, Access::Integer { .. } | Access::Enumeration { .. })),
            booleans: of(|a| matches!(a, Access::Boolean { .. })),
            guid: fmi2_export::guid::<M>(),
        }
    })
}

fn no_fatal(inst: &Instance, status: fmi2Status, call: &str) {
    assert!(
        status != fmi2Fatal && status != fmi2Pending,
        "{call} returned {status:?}: {:?}",
        inst.messages()
    );
}

/// All Reals; finite whenever the get succeeds.
fn check_outputs(inst: &Instance, reals: &[u32]) {
    let (status, values) = inst.get_reals(reals);
    no_fatal(inst, status, "fmi2GetReal");
    if status == fmi2OK || status == fmi2Warning {
        assert!(
            values.iter().all(|v| v.is_finite()),
            "non-finite output from an accepted state: {values:?}"
        );
    }
}

fn current_time(inst: &Instance) -> Option<f64> {
    let mut t = 0.0;
    // SAFETY: one out-element of a live instance.
    let status = unsafe {
        (inst.functions().co_simulation.get_real_status)(inst.component(), fmi2LastSuccessfulTime, &mut t)
    };
    (status == fmi2OK).then_some(t)
}

/// The instance `restored_state` works on, initialized, and its genuine state.
struct Restoring {
    inst: Instance,
    genuine: fmi2FMUstate,
    serialized: Vec<u8>,
}

/// (a) A payload sealed with a valid header and checksum, then fmi2DeSerializeFMUstate, and
/// if accepted: set, gets and a step. An odd first byte edits a genuine payload (the rest
/// read as (offset lo, offset hi, byte) triples), so that most inputs decode and reach the
/// validation; otherwise the rest is the payload itself. Afterwards the genuine state is
/// set again, so every input starts from the same instance.
pub fn restored_state<M: Model>(functions: &Fmi2Functions, data: &[u8]) {
    thread_local! {
        static RESTORING: OnceCell<Restoring> = const { OnceCell::new() };
    }
    let reals = &table::<M>().reals;
    RESTORING.with(|cell| {
        let Restoring {
            inst,
            genuine,
            serialized,
        } = cell.get_or_init(|| {
            let inst = Instance::instantiate(functions, "fuzz", &table::<M>().guid);
            assert_eq!(inst.initialize(), fmi2OK, "{:?}", inst.messages());
            let genuine = inst.get_state();
            let serialized = inst.serialize(genuine);
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
        assert!(status == fmi2OK || status == fmi2Error, "{status:?}");
        if status == fmi2OK {
            no_fatal(inst, inst.set_state(state), "fmi2SetFMUstate");
            check_outputs(inst, reals);
            if let Some(t) = current_time(inst) {
                no_fatal(inst, inst.do_step(t, 0.01), "fmi2DoStep");
                check_outputs(inst, reals);
            }
            no_fatal(inst, inst.free_state(state), "fmi2FreeFMUstate");
        }
        assert_eq!(inst.set_state(*genuine), fmi2OK, "{:?}", inst.messages());
        inst.clear_log();
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
            0.0, -0.0, 1.0, -1.0, 0.01, 1e-300, 1e300, f64::MAX, f64::MIN_POSITIVE,
            f64::NAN, f64::INFINITY, 1e9,
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

/// (b) A random sequence of calls over the C ABI of one instance.
pub fn call_sequence<M: Model>(functions: &Fmi2Functions, data: &[u8]) {
    thread_local! {
        static INSTANCE: OnceCell<Instance> = const { OnceCell::new() };
    }
    INSTANCE.with(|cell| {
        let inst = cell.get_or_init(|| {
            Instance::new(functions, "fuzz", &table::<M>().guid, false)
                .unwrap_or_else(|log| panic!("fmi2Instantiate refused a valid instance: {log:?}"))
        });
        // fmi2Reset puts the instance back as instantiated (the standard's own promise,
        // checked bit for bit by the robustness tests), for a fraction of a new one.
        assert_eq!(inst.reset(), fmi2OK, "{:?}", inst.messages());
        let on = fmi2Boolean::from(data.first() == Some(&1));
        // SAFETY: no categories.
        let s = unsafe { (inst.functions().set_debug_logging)(inst.component(), on, 0, std::ptr::null()) };
        assert_eq!(s, fmi2OK);
        sequence::<M>(inst, data);
        inst.clear_log();
    });
}

fn sequence<M: Model>(inst: &Instance, data: &[u8]) {
    let table = table::<M>();
    let mut input = Bytes(data.get(1..).unwrap_or_default());
    let mut states: Vec<fmi2FMUstate> = Vec::new();
    let c = inst.component();
    let f = *inst.functions();
    while let Some(op) = input.byte() {
        let status = match op % 16 {
            0 => {
                let (start, stop) = (input.real().unwrap_or(0.0), input.real());
                inst.setup_experiment(start, stop)
            }
            1 => inst.enter_initialization_mode(),
            2 => inst.exit_initialization_mode(),
            3 => {
                let t = match input.byte() {
                    Some(b) if b % 4 == 0 => input.real().unwrap_or(0.0),
                    _ => current_time(inst).unwrap_or(0.0),
                };
                inst.do_step(t, input.real().unwrap_or(0.01))
            }
            4 => {
                let vr = input.pick(&table.reals).unwrap_or(0);
                inst.set_reals(&[vr], &[input.real().unwrap_or(0.0)])
            }
            5 => {
                check_outputs(inst, &table.reals);
                fmi2OK
            }
            6 => {
                let vr = input.pick(&table.integers).unwrap_or(0);
                let v = i32::from_le_bytes([0, 0, 0, 0].map(|_: u8| input.byte().unwrap_or(0)));
                inst.set_integers(&[vr], &[v])
            }
            7 => {
                let vr = input.pick(&table.booleans).unwrap_or(0);
                inst.set_boolean(vr, input.byte().unwrap_or(0) % 2 == 1)
            }
            8 => {
                let mut state: fmi2FMUstate = std::ptr::null_mut();
                // SAFETY: an out-pointer to a NULL state.
                let s = unsafe { (f.get_fmu_state)(c, &mut state) };
                if s == fmi2OK {
                    states.push(state);
                }
                s
            }
            9 => match input.pick(&states) {
                Some(state) => inst.set_state(state),
                None => fmi2OK,
            },
            10 => {
                let i = usize::from(input.byte().unwrap_or(0));
                if states.is_empty() {
                    fmi2OK
                } else {
                    let state = states.swap_remove(i % states.len());
                    inst.free_state(state)
                }
            }
            11 => match input.pick(&states) {
                Some(state) => {
                    let bytes = inst.serialize(state);
                    let (s, copy) = inst.deserialize(&bytes);
                    if s == fmi2OK {
                        states.push(copy);
                    }
                    s
                }
                None => fmi2OK,
            },
            12 => inst.reset(),
            13 => inst.terminate(),
            // SAFETY: no categories.
            14 => unsafe { (f.set_debug_logging)(c, fmi2Boolean::from(op > 128), 0, std::ptr::null()) },
            _ => {
                let mut status = fmi2OK;
                // SAFETY: one out-element.
                unsafe { (f.co_simulation.get_status)(c, fmi2DoStepStatus, &mut status) }
            }
        };
        no_fatal(inst, status, &format!("operation {}", op % 16));
        if status == fmi2OK {
            check_outputs(inst, &table.reals);
        }
    }
    for state in states {
        inst.free_state(state);
    }
}
