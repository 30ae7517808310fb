//! Runs one call sequence against one FMU and checks the invariants after every call and at
//! the end. See [`crate::fuzz`] for the list of invariants.
#![allow(unsafe_code)]

use super::ops::*;
use super::watchdog::Watchdog;
use crate::ffi::*;
use crate::instance::{Fmu, Instance};
use crate::logger::{LogSink, Record};
use crate::reference::{boolean_inputs_at, inputs_at, legal_run, Wiring, STEP_S};
use model_description::VariableKind;
use proptest::sample::Index;
use std::collections::HashSet;
use std::ffi::{c_char, CStr, CString};
use std::ptr;

/// Steps of the legal run that closes every sequence.
pub const CHECK_STEPS: usize = 20;
const HEADER_LEN: usize = 44;
const CATEGORIES: [&CStr; 6] = [
    c"logStatusOK",
    c"logStatusWarning",
    c"logStatusDiscard",
    c"logStatusError",
    c"logStatusFatal",
    c"logCalls",
];

/// What one FMU's fuzzing needs once: the reference result and seed buffers.
pub struct Baseline {
    pub reference: Vec<u64>,
    /// Valid serialized states to corrupt.
    pub buffers: Vec<Vec<u8>>,
    pub wiring: Wiring,
    declared: [HashSet<u32>; 4],
    by_kind: [Vec<u32>; 4],
    all: Vec<u32>,
}

impl Baseline {
    pub fn new(fmu: &Fmu) -> Result<Baseline, String> {
        let inst = fmu.instantiate("reference", false);
        let reference = legal_run(&inst, CHECK_STEPS)?;
        let (status, state) = inst.get_fmu_state();
        if status != fmi2OK {
            return Err(format!("fmi2GetFMUstate: {}", status.label()));
        }
        let buffers = vec![inst
            .serialize(state)
            .map_err(|s| format!("serialize: {}", s.label()))?];
        let kinds = [
            VariableKind::Real,
            VariableKind::Integer,
            VariableKind::Boolean,
            VariableKind::String,
        ];
        let by_kind = kinds.map(|k| {
            fmu.package
                .of_kind(k)
                .map(|v| v.value_reference)
                .collect::<Vec<_>>()
        });
        Ok(Baseline {
            reference,
            buffers,
            wiring: Wiring::of(fmu),
            declared: by_kind.clone().map(|v| v.into_iter().collect()),
            all: fmu
                .package
                .variables
                .iter()
                .map(|v| v.value_reference)
                .collect(),
            by_kind,
        })
    }
}

/// Counters over many sequences.
#[derive(Debug, Default, Clone)]
pub struct Stats {
    pub sequences: u64,
    /// Calls made by the generated operations.
    pub fuzz_calls: u64,
    /// Calls made to check the invariants (reset and legal runs, time queries).
    pub check_calls: u64,
    /// Returned statuses of the fuzz calls, by value 0..=4.
    pub statuses: [u64; 5],
    pub null_instances: u64,
    /// Crafted states that the FMU accepted (they pass every integrity check by design).
    pub crafted_accepted: u64,
    pub fatal_after_crafted: u64,
    /// The FMU's own predictions confirmed: calls that had to be refused and were.
    pub predicted_refusals: u64,
}

impl Stats {
    pub fn add(&mut self, other: &Stats) {
        self.sequences += other.sequences;
        self.fuzz_calls += other.fuzz_calls;
        self.check_calls += other.check_calls;
        for (a, b) in self.statuses.iter_mut().zip(other.statuses) {
            *a += b;
        }
        self.null_instances += other.null_instances;
        self.crafted_accepted += other.crafted_accepted;
        self.fatal_after_crafted += other.fatal_after_crafted;
        self.predicted_refusals += other.predicted_refusals;
    }
}

struct Slot<'a> {
    inst: Instance<'a>,
    time: f64,
    /// A crafted state was deserialized into this instance: its values may be anything a
    /// decoder accepts, so only "no crash, no hang, logged refusals, Reset works" apply.
    tainted: bool,
}

pub struct Session<'a> {
    fmu: &'a Fmu,
    base: &'a Baseline,
    dog: &'a Watchdog,
    slots: Vec<Option<Slot<'a>>>,
    /// Every FMU-state pointer handed out so far (live or freed, any instance's).
    states: Vec<fmi2FMUstate>,
    crafted: HashSet<usize>,
    buffers: Vec<Vec<u8>>,
    /// Zeroed memory passed as a component that is not an instance.
    foreign: Box<[u64; 32]>,
    guid: CString,
    /// The FMU declares Model Exchange: `fmi2Instantiate` must accept `fmi2ModelExchange`.
    model_exchange: bool,
    /// The FMU declares `providesDirectionalDerivative`: its calls may succeed (else every
    /// one must be refused).
    derivatives: bool,
    serial: u32,
    pub stats: Stats,
}

type Outcome = Result<(), String>;

/// The component a target resolves to, with its slot index when it is an instance.
enum Resolved {
    Skip,
    Instance(usize, fmi2Component),
    NotInstance(fmi2Component),
}

impl<'a> Session<'a> {
    pub fn new(fmu: &'a Fmu, base: &'a Baseline, dog: &'a Watchdog) -> Session<'a> {
        let mut session = Session {
            fmu,
            base,
            dog,
            slots: (0..SLOTS).map(|_| None).collect(),
            states: Vec::new(),
            crafted: HashSet::new(),
            buffers: base.buffers.clone(),
            foreign: Box::new([0; 32]),
            guid: fmu.guid(),
            model_exchange: fmu.package.description.model_exchange.is_some(),
            derivatives: fmu
                .package
                .description
                .co_simulation
                .as_ref()
                .and_then(|cs| cs.provides_directional_derivative)
                == Some(true),
            serial: 0,
            stats: Stats::default(),
        };
        let inst = fmu.instantiate("fuzz0", false);
        session.stats.check_calls += 1;
        session.slots[0] = Some(Slot {
            inst,
            time: 0.0,
            tainted: false,
        });
        session
    }

    /// Runs `ops`, then the closing check; the first violated invariant as `Err`.
    pub fn run(mut self, ops: &[Op]) -> Result<Stats, String> {
        self.stats.sequences = 1;
        for (i, op) in ops.iter().enumerate() {
            self.apply(op)
                .map_err(|e| format!("operation {i} {op:?}: {e}"))?;
        }
        self.verify()?;
        Ok(self.stats)
    }

    fn resolve(&self, target: Target) -> Resolved {
        match target {
            Target::Slot(i) => match &self.slots[i as usize] {
                Some(slot) => Resolved::Instance(i as usize, slot.inst.c),
                None => Resolved::Skip,
            },
            Target::Null => Resolved::NotInstance(ptr::null_mut()),
            Target::Foreign => Resolved::NotInstance(self.foreign.as_ptr() as fmi2Component),
        }
    }

    fn kind_index(kind: Kind) -> usize {
        match kind {
            Kind::Real => 0,
            Kind::Integer => 1,
            Kind::Boolean => 2,
            Kind::String => 3,
        }
    }

    /// Value references for `picks`, and whether one of them is not declared for `kind`.
    fn vrs(&self, kind: Kind, picks: &[VrPick]) -> (Vec<u32>, bool) {
        let k = Self::kind_index(kind);
        let of_kind = &self.base.by_kind[k];
        let vrs: Vec<u32> = picks
            .iter()
            .map(|p| match p {
                VrPick::OfKind(i) if !of_kind.is_empty() => of_kind[i.index(of_kind.len())],
                VrPick::OfKind(_) => u32::MAX,
                VrPick::Declared(i) => self.base.all[i.index(self.base.all.len())],
                VrPick::Raw(vr) => *vr,
            })
            .collect();
        let unknown = vrs.iter().any(|vr| !self.base.declared[k].contains(vr));
        (vrs, unknown)
    }

    fn seen_state(&self, index: Index) -> fmi2FMUstate {
        if self.states.is_empty() {
            ptr::null_mut()
        } else {
            self.states[index.index(self.states.len())]
        }
    }

    fn state_arg(&self, arg: StateArg) -> (fmi2FMUstate, Option<&'static str>) {
        match arg {
            StateArg::Null => (ptr::null_mut(), Some("the FMU state is NULL")),
            StateArg::Seen(i) => {
                let s = self.seen_state(i);
                (s, s.is_null().then_some("the FMU state is NULL"))
            }
            StateArg::Foreign => (
                self.foreign.as_ptr() as fmi2FMUstate,
                Some("the FMU state was never handed out"),
            ),
        }
    }

    /// Checks the status and the log of one call; `must_fail` is a reason the call had to
    /// return fmi2Error.
    fn finish(
        &mut self,
        function: &str,
        target: Option<usize>,
        status: fmi2Status,
        must_fail: Option<&str>,
    ) -> Outcome {
        self.stats.fuzz_calls += 1;
        if !(fmi2OK..=fmi2Fatal).contains(&status) {
            return Err(format!("{function} returned {status} ({})", status.label()));
        }
        self.stats.statuses[status.0 as usize] += 1;
        if let Some(reason) = must_fail {
            if status != fmi2Error {
                return Err(format!(
                    "{function} returned {} although {reason}",
                    status.label()
                ));
            }
            self.stats.predicted_refusals += 1;
        }
        // A call logs to its own instance's sink and to no other.
        for (i, slot) in self.slots.iter().enumerate() {
            let Some(slot) = slot else { continue };
            let records = slot.inst.take_log();
            if Some(i) == target {
                check_log(function, status, &slot.inst.name, slot.tainted, &records)?;
            } else if !records.is_empty() {
                return Err(format!(
                    "{function} on {target:?} logged to instance {i}: {records:?}"
                ));
            }
        }
        match target {
            None if status != fmi2Error => Err(format!(
                "{function} without an instance returned {}",
                status.label()
            )),
            _ => Ok(()),
        }
    }

    fn apply(&mut self, op: &Op) -> Outcome {
        let api = &self.fmu.api;
        let dog = self.dog;
        match op {
            Op::TypesPlatform => {
                let p = dog.watch("fmi2GetTypesPlatform", || unsafe {
                    (api.get_types_platform)()
                });
                self.stats.fuzz_calls += 1;
                expect_text(p, "default", "fmi2GetTypesPlatform")
            }
            Op::Version => {
                let p = dog.watch("fmi2GetVersion", || unsafe { (api.get_version)() });
                self.stats.fuzz_calls += 1;
                expect_text(p, "2.0", "fmi2GetVersion")
            }
            Op::Instantiate {
                slot,
                name,
                fmu_type,
                guid,
                callbacks,
                visible,
                logging_on,
            } => self.instantiate(
                *slot as usize,
                *name,
                *fmu_type,
                *guid,
                *callbacks,
                *visible,
                *logging_on,
            ),
            Op::FreeInstance(target) => match self.resolve(*target) {
                Resolved::Skip => Ok(()),
                Resolved::Instance(i, _) => {
                    let slot = self.slots[i].take().expect("resolved");
                    let sink = dog.watch("fmi2FreeInstance", || slot.inst.free());
                    self.stats.fuzz_calls += 1;
                    let records = sink.take();
                    match records.iter().find(|r| r.status >= fmi2Warning) {
                        Some(r) => Err(format!("fmi2FreeInstance logged {r:?}")),
                        None => Ok(()),
                    }
                }
                Resolved::NotInstance(c) => {
                    dog.watch("fmi2FreeInstance", || unsafe { (api.free_instance)(c) });
                    self.stats.fuzz_calls += 1;
                    Ok(())
                }
            },
            Op::SetDebugLogging {
                target,
                on,
                categories,
            } => {
                let (c, slot) = match self.resolve(*target) {
                    Resolved::Skip => return Ok(()),
                    Resolved::Instance(i, c) => (c, Some(i)),
                    Resolved::NotInstance(c) => (c, None),
                };
                let (status, must_fail) = match categories {
                    Ok(list) => {
                        let owned: Vec<Option<CString>> = list
                            .iter()
                            .map(|cat| match cat {
                                Category::Known(i) => Some(CATEGORIES[i.index(6)].to_owned()),
                                Category::Unknown(s) => {
                                    Some(CString::new(s.as_str()).expect("no NUL"))
                                }
                                Category::Null => None,
                            })
                            .collect();
                        let pointers: Vec<fmi2String> = owned
                            .iter()
                            .map(|o| o.as_ref().map_or(ptr::null(), |s| s.as_ptr()))
                            .collect();
                        let bad = owned.iter().any(|o| {
                            o.as_ref()
                                .is_none_or(|s| !CATEGORIES.contains(&s.as_c_str()))
                        });
                        let status = dog.watch("fmi2SetDebugLogging", || unsafe {
                            (api.set_debug_logging)(c, *on, pointers.len(), pointers.as_ptr())
                        });
                        (status, bad.then_some("a category is NULL or unknown"))
                    }
                    Err(n) => {
                        let status = dog.watch("fmi2SetDebugLogging", || unsafe {
                            (api.set_debug_logging)(c, *on, *n, ptr::null())
                        });
                        (
                            status,
                            (*n > 0).then_some("categories is NULL with nCategories > 0"),
                        )
                    }
                };
                self.finish("fmi2SetDebugLogging", slot, status, must_fail)
            }
            Op::SetupExperiment {
                target,
                tolerance_defined,
                tolerance,
                start,
                stop_defined,
                stop,
            } => {
                let (c, slot) = match self.resolve(*target) {
                    Resolved::Skip => return Ok(()),
                    Resolved::Instance(i, c) => (c, Some(i)),
                    Resolved::NotInstance(c) => (c, None),
                };
                let status = dog.watch("fmi2SetupExperiment", || unsafe {
                    (api.setup_experiment)(
                        c,
                        *tolerance_defined,
                        *tolerance,
                        *start,
                        *stop_defined,
                        *stop,
                    )
                });
                let must_fail = if !start.is_finite() {
                    Some("startTime is not finite")
                } else if *stop_defined != 0 && !(stop.is_finite() && stop >= start) {
                    Some("the stop time is not a finite time after the start")
                } else {
                    None
                };
                if status == fmi2OK {
                    if let Some(i) = slot {
                        self.slot_mut(i).time = *start;
                    }
                }
                self.finish("fmi2SetupExperiment", slot, status, must_fail)
            }
            Op::EnterInitializationMode(t) => self.simple(
                *t,
                "fmi2EnterInitializationMode",
                api.enter_initialization_mode,
            ),
            Op::ExitInitializationMode(t) => self.simple(
                *t,
                "fmi2ExitInitializationMode",
                api.exit_initialization_mode,
            ),
            Op::Terminate(t) => self.simple(*t, "fmi2Terminate", api.terminate),
            Op::Reset(t) => {
                let outcome = self.simple(*t, "fmi2Reset", api.reset);
                if let Target::Slot(i) = t {
                    if let Some(slot) = self.slots[*i as usize].as_mut() {
                        slot.time = 0.0;
                    }
                }
                outcome
            }
            Op::CancelStep(t) => {
                let (c, slot) = match self.resolve(*t) {
                    Resolved::Skip => return Ok(()),
                    Resolved::Instance(i, c) => (c, Some(i)),
                    Resolved::NotInstance(c) => (c, None),
                };
                let status = dog.watch("fmi2CancelStep", || unsafe {
                    (api.co_simulation.cancel_step)(c)
                });
                self.finish(
                    "fmi2CancelStep",
                    slot,
                    status,
                    Some("no step is ever pending"),
                )
            }
            Op::Get {
                target,
                kind,
                vrs,
                nulls,
            } => self.get(*target, *kind, vrs, *nulls),
            Op::SetReal {
                target,
                vrs,
                values,
                nulls,
            } => {
                let n = vrs.len().min(values.len());
                let non_finite = values[..n].iter().any(|v| !v.is_finite());
                let reason = non_finite.then_some("a value is not finite");
                let call = |c, vr: *const u32, n, value: *const f64| unsafe {
                    (api.set_real)(c, vr, n, value)
                };
                self.set(
                    *target,
                    Kind::Real,
                    &vrs[..n],
                    &values[..n],
                    *nulls,
                    reason,
                    "fmi2SetReal",
                    call,
                )
            }
            Op::SetInteger {
                target,
                vrs,
                values,
                nulls,
            } => {
                let n = vrs.len().min(values.len());
                let call = |c, vr: *const u32, n, value: *const i32| unsafe {
                    (api.set_integer)(c, vr, n, value)
                };
                self.set(
                    *target,
                    Kind::Integer,
                    &vrs[..n],
                    &values[..n],
                    *nulls,
                    None,
                    "fmi2SetInteger",
                    call,
                )
            }
            Op::SetBoolean {
                target,
                vrs,
                values,
                nulls,
            } => {
                let n = vrs.len().min(values.len());
                let call = |c, vr: *const u32, n, value: *const i32| unsafe {
                    (api.set_boolean)(c, vr, n, value)
                };
                self.set(
                    *target,
                    Kind::Boolean,
                    &vrs[..n],
                    &values[..n],
                    *nulls,
                    None,
                    "fmi2SetBoolean",
                    call,
                )
            }
            Op::SetString {
                target,
                vrs,
                values,
                nulls,
            } => {
                let n = vrs.len().min(values.len());
                let owned: Vec<Option<CString>> = values[..n]
                    .iter()
                    .map(|t| match t {
                        Text::Valid(s) => Some(CString::new(s.as_str()).expect("no NUL")),
                        Text::Invalid(bytes) => Some(CString::new(bytes.clone()).expect("no NUL")),
                        Text::Null => None,
                    })
                    .collect();
                let pointers: Vec<fmi2String> = owned
                    .iter()
                    .map(|o| o.as_ref().map_or(ptr::null(), |s| s.as_ptr()))
                    .collect();
                let call = |c, vr: *const u32, n, value: *const fmi2String| unsafe {
                    (api.set_string)(c, vr, n, value)
                };
                self.set(
                    *target,
                    Kind::String,
                    &vrs[..n],
                    &pointers,
                    *nulls,
                    None,
                    "fmi2SetString",
                    call,
                )
            }
            Op::GetFmuState { target, slot } => {
                let Some((c, index)) = self.component(*target) else {
                    return Ok(());
                };
                let (status, made) = self.with_state_slot(*slot, "fmi2GetFMUstate", |p| unsafe {
                    (api.get_fmu_state)(c, p)
                });
                if let Some(state) = made {
                    self.states.push(state);
                }
                self.finish(
                    "fmi2GetFMUstate",
                    index,
                    status,
                    matches!(slot, StateSlot::NullPointer)
                        .then_some("the FMUstate pointer is NULL"),
                )
            }
            Op::SetFmuState { target, state } => {
                let Some((c, index)) = self.component(*target) else {
                    return Ok(());
                };
                let (s, must_fail) = self.state_arg(*state);
                let status = dog.watch("fmi2SetFMUstate", || unsafe { (api.set_fmu_state)(c, s) });
                if let (fmi2OK, Some(i)) = (status, index) {
                    let crafted = self.crafted.contains(&(s as usize));
                    let slot = self.slot_mut(i);
                    slot.tainted |= crafted;
                    self.refresh_time(i);
                }
                self.finish("fmi2SetFMUstate", index, status, must_fail)
            }
            Op::FreeFmuState { target, slot } => {
                let Some((c, index)) = self.component(*target) else {
                    return Ok(());
                };
                let mut after = ptr::null_mut();
                let status = match slot {
                    StateSlot::NullPointer => dog.watch("fmi2FreeFMUstate", || unsafe {
                        (api.free_fmu_state)(c, ptr::null_mut())
                    }),
                    StateSlot::Fresh => dog.watch("fmi2FreeFMUstate", || unsafe {
                        (api.free_fmu_state)(c, &mut after)
                    }),
                    StateSlot::Existing(i) => {
                        after = self.seen_state(*i);
                        dog.watch("fmi2FreeFMUstate", || unsafe {
                            (api.free_fmu_state)(c, &mut after)
                        })
                    }
                };
                if status == fmi2OK && !after.is_null() {
                    return Err(
                        "fmi2FreeFMUstate returned fmi2OK without setting the state to NULL".into(),
                    );
                }
                self.finish(
                    "fmi2FreeFMUstate",
                    index,
                    status,
                    matches!(slot, StateSlot::NullPointer)
                        .then_some("the FMUstate pointer is NULL"),
                )
            }
            Op::SerializedSize {
                target,
                state,
                size_null,
            } => {
                let Some((c, index)) = self.component(*target) else {
                    return Ok(());
                };
                let (s, mut must_fail) = self.state_arg(*state);
                let mut size = 0usize;
                let out: *mut usize = if *size_null {
                    ptr::null_mut()
                } else {
                    &mut size
                };
                if *size_null {
                    must_fail = Some("size is NULL");
                }
                let status = dog.watch("fmi2SerializedFMUstateSize", || unsafe {
                    (api.serialized_fmu_state_size)(c, s, out)
                });
                if status == fmi2OK && size < HEADER_LEN {
                    return Err(format!("serialized size {size} is shorter than the header"));
                }
                self.finish("fmi2SerializedFMUstateSize", index, status, must_fail)
            }
            Op::Serialize {
                target,
                state,
                size_error,
                buffer_null,
            } => {
                let Some((c, index)) = self.component(*target) else {
                    return Ok(());
                };
                let (s, mut must_fail) = self.state_arg(*state);
                let mut true_size = 0usize;
                let sized = unsafe { (api.serialized_fmu_state_size)(c, s, &mut true_size) };
                self.stats.check_calls += 1;
                let size = if sized == fmi2OK { true_size } else { 64 }
                    .saturating_add_signed(*size_error as isize);
                if *size_error != 0 {
                    must_fail =
                        must_fail.or(Some("the size differs from fmi2SerializedFMUstateSize"));
                }
                if *buffer_null && size > 0 {
                    must_fail = must_fail.or(Some("the buffer is NULL"));
                }
                let mut bytes = vec![0u8; size];
                let buffer: *mut fmi2Byte = if *buffer_null {
                    ptr::null_mut()
                } else {
                    bytes.as_mut_ptr().cast()
                };
                let status = dog.watch("fmi2SerializeFMUstate", || unsafe {
                    (api.serialize_fmu_state)(c, s, buffer, size)
                });
                if status == fmi2OK && !*buffer_null {
                    if self.buffers.len() >= 16 {
                        self.buffers.swap_remove(0);
                    }
                    self.buffers.push(bytes);
                }
                // The size query logged too: drop its records before checking this call's.
                self.finish("fmi2SerializeFMUstate", index, status, must_fail)
            }
            Op::Deserialize {
                target,
                buffer,
                slot,
            } => self.deserialize(*target, buffer, *slot),
            Op::DirectionalDerivative { target, vrs } => {
                let Some((c, index)) = self.component(*target) else {
                    return Ok(());
                };
                let (vrs, _) = self.vrs(Kind::Real, vrs);
                let known = vec![1.0; vrs.len()];
                let mut unknown = vec![0.0; vrs.len()];
                let status = dog.watch("fmi2GetDirectionalDerivative", || unsafe {
                    (api.get_directional_derivative)(
                        c,
                        vrs.as_ptr(),
                        vrs.len(),
                        vrs.as_ptr(),
                        vrs.len(),
                        known.as_ptr(),
                        unknown.as_mut_ptr(),
                    )
                });
                let must_fail =
                    (!self.derivatives).then_some("directional derivatives are not provided");
                self.finish("fmi2GetDirectionalDerivative", index, status, must_fail)
            }
            Op::SetRealInputDerivatives {
                target,
                vrs,
                order,
                value,
            } => {
                let Some((c, index)) = self.component(*target) else {
                    return Ok(());
                };
                let (vrs, _) = self.vrs(Kind::Real, vrs);
                let orders = vec![*order; vrs.len()];
                let values = vec![*value; vrs.len()];
                let status = dog.watch("fmi2SetRealInputDerivatives", || unsafe {
                    (api.co_simulation.set_real_input_derivatives)(
                        c,
                        vrs.as_ptr(),
                        vrs.len(),
                        orders.as_ptr(),
                        values.as_ptr(),
                    )
                });
                self.finish(
                    "fmi2SetRealInputDerivatives",
                    index,
                    status,
                    Some("input derivatives are not supported"),
                )
            }
            Op::GetRealOutputDerivatives { target, vrs, order } => {
                let Some((c, index)) = self.component(*target) else {
                    return Ok(());
                };
                let (vrs, _) = self.vrs(Kind::Real, vrs);
                let orders = vec![*order; vrs.len()];
                let mut values = vec![0.0; vrs.len()];
                let status = dog.watch("fmi2GetRealOutputDerivatives", || unsafe {
                    (api.co_simulation.get_real_output_derivatives)(
                        c,
                        vrs.as_ptr(),
                        vrs.len(),
                        orders.as_ptr(),
                        values.as_mut_ptr(),
                    )
                });
                self.finish(
                    "fmi2GetRealOutputDerivatives",
                    index,
                    status,
                    Some("output derivatives are not supported"),
                )
            }
            Op::DoStep {
                target,
                t,
                h,
                no_set_prior,
            } => {
                let Some((c, index)) = self.component(*target) else {
                    return Ok(());
                };
                let time = index.map_or(0.0, |i| self.slot_mut(i).time);
                let t = match t {
                    TimeArg::Current => time,
                    TimeArg::Offset(f) => time + f * time.abs().max(1.0),
                    TimeArg::Raw(x) => *x,
                };
                let status = dog.watch("fmi2DoStep", || unsafe {
                    (api.co_simulation.do_step)(c, t, *h, *no_set_prior)
                });
                let must_fail = if !(h.is_finite() && *h > 0.0) {
                    Some("the step size is not a finite positive number")
                } else if !t.is_finite() {
                    Some("the communication point is not finite")
                } else {
                    None
                };
                if let Some(i) = index {
                    match status {
                        fmi2OK | fmi2Warning => self.slot_mut(i).time = t + h,
                        fmi2Discard => self.refresh_time(i),
                        _ => {}
                    }
                }
                self.finish("fmi2DoStep", index, status, must_fail)
            }
            Op::Status {
                target,
                which,
                kind,
                value_null,
            } => {
                let Some((c, index)) = self.component(*target) else {
                    return Ok(());
                };
                self.status(c, index, *which, *kind, *value_null)
            }
            Op::LegalInit(i) => self.legal_init(*i as usize),
            Op::LegalSteps(i, n) => self.legal_steps(*i as usize, *n as usize),
        }
    }

    fn component(&self, target: Target) -> Option<(fmi2Component, Option<usize>)> {
        match self.resolve(target) {
            Resolved::Skip => None,
            Resolved::Instance(i, c) => Some((c, Some(i))),
            Resolved::NotInstance(c) => Some((c, None)),
        }
    }

    fn name_of(&self, vr: u32) -> String {
        self.fmu
            .package
            .variables
            .iter()
            .find(|v| v.value_reference == vr && v.kind == VariableKind::Real)
            .map_or_else(|| format!("vr {vr}"), |v| v.name.clone())
    }

    /// For a violation report: the Real parameters and inputs of an instance that differ
    /// from their start values.
    fn describe(&self, i: usize) -> String {
        let Some(slot) = &self.slots[i] else {
            return String::new();
        };
        let changed: Vec<String> = self
            .fmu
            .package
            .description
            .variables()
            .filter(|v| v.real.is_some())
            .filter(|v| {
                matches!(
                    v.causality_or_default(),
                    model_description::Causality::Parameter | model_description::Causality::Input
                )
            })
            .filter_map(|v| {
                let (_, value) = slot.inst.get_reals(&[v.value_reference]);
                let start = v.real.as_ref().and_then(|r| r.start);
                (start != Some(value[0])).then(|| format!("{} = {:e}", v.name, value[0]))
            })
            .collect();
        slot.inst.take_log();
        format!(
            "values that differ from their start: {}",
            changed.join(", ")
        )
    }

    fn slot_mut(&mut self, i: usize) -> &mut Slot<'a> {
        self.slots[i].as_mut().expect("a live slot")
    }

    /// The FMU's time after a call that may have moved it unpredictably (a discarded step,
    /// a restored state), from fmi2LastSuccessfulTime when the state allows the query.
    fn refresh_time(&mut self, i: usize) {
        let slot = self.slots[i].as_mut().expect("a live slot");
        let (status, t) = self.dog.watch("fmi2GetRealStatus", || {
            slot.inst.real_status(fmi2LastSuccessfulTime)
        });
        self.stats.check_calls += 1;
        if status == fmi2OK {
            slot.time = t;
        }
        // The query's own log (a refusal when the state does not allow it) is not the
        // subject of the check that follows.
        slot.inst.take_log();
    }

    fn simple(
        &mut self,
        target: Target,
        function: &'static str,
        f: unsafe extern "C" fn(fmi2Component) -> fmi2Status,
    ) -> Outcome {
        let Some((c, index)) = self.component(target) else {
            return Ok(());
        };
        let status = self.dog.watch(function, || unsafe { f(c) });
        self.finish(function, index, status, None)
    }

    #[allow(clippy::too_many_arguments)]
    fn instantiate(
        &mut self,
        i: usize,
        name: NameArg,
        fmu_type: i32,
        guid: GuidArg,
        callbacks: CallbacksArg,
        visible: i32,
        logging_on: i32,
    ) -> Outcome {
        if let Some(old) = self.slots[i].take() {
            self.dog.watch("fmi2FreeInstance", || old.inst.free());
            self.stats.fuzz_calls += 1;
        }
        self.serial += 1;
        let name_text = format!("fuzz{i}_{}", self.serial);
        let name_c = CString::new(name_text.clone()).expect("no NUL");
        let name_ptr: fmi2String = match name {
            NameArg::Valid => name_c.as_ptr(),
            NameArg::Empty => c"".as_ptr(),
            NameArg::Null => ptr::null(),
        };
        let guid_c = match guid {
            GuidArg::Valid => Some(self.guid.clone()),
            GuidArg::Null => None,
            GuidArg::Altered(at) => {
                let mut bytes = self.guid.as_bytes().to_vec();
                let k = at.index(bytes.len());
                bytes[k] = if bytes[k] == b'0' { b'1' } else { b'0' };
                Some(CString::new(bytes).expect("no NUL"))
            }
            GuidArg::Garbage => Some(c"%s%s%n-not-a-guid".to_owned()),
        };
        let guid_ptr = guid_c.as_ref().map_or(ptr::null(), |g| g.as_ptr());
        let sink = Box::<LogSink>::default();
        let mut functions = sink.callbacks();
        if matches!(callbacks, CallbacksArg::NullLogger) {
            functions.logger = None;
        }
        let functions_ptr: *const fmi2CallbackFunctions = match callbacks {
            CallbacksArg::NullStruct => ptr::null(),
            _ => &functions,
        };
        let api = &self.fmu.api;
        let c = self.dog.watch("fmi2Instantiate", || unsafe {
            (api.instantiate)(
                name_ptr,
                fmu_type,
                guid_ptr,
                c"file:///tmp".as_ptr(),
                functions_ptr,
                visible,
                logging_on,
            )
        });
        self.stats.fuzz_calls += 1;
        let model_exchange = fmu_type == fmi2ModelExchange && self.model_exchange;
        let valid = matches!(name, NameArg::Valid)
            && (fmu_type == fmi2CoSimulation || model_exchange)
            && matches!(guid, GuidArg::Valid)
            && matches!(callbacks, CallbacksArg::Valid);
        if c.is_null() {
            self.stats.null_instances += 1;
            if valid {
                return Err(format!(
                    "fmi2Instantiate refused valid arguments: {:?}",
                    sink.all()
                ));
            }
            if matches!(callbacks, CallbacksArg::Valid) {
                let records = sink.take();
                if !records
                    .iter()
                    .any(|r| r.status == fmi2Error && r.message().starts_with("fmi2Instantiate"))
                {
                    return Err(format!(
                        "fmi2Instantiate returned NULL without an error message: {records:?}"
                    ));
                }
            }
            return Ok(());
        }
        // SAFETY: a live component of this FMU whose environment is `sink`.
        let inst = unsafe { Instance::from_raw(self.fmu, c, sink, name_text) };
        if !valid {
            drop(inst);
            return Err("fmi2Instantiate accepted invalid arguments".into());
        }
        if model_exchange {
            // The call sequences model Co-Simulation; Model Exchange has tests of its own.
            drop(inst);
            return Ok(());
        }
        let records = inst.take_log();
        check_log("fmi2Instantiate", fmi2OK, &inst.name, false, &records)?;
        self.slots[i] = Some(Slot {
            inst,
            time: 0.0,
            tainted: false,
        });
        Ok(())
    }

    fn arrays<T>(
        &self,
        nulls: Nulls,
        vrs: &[u32],
        values: *const T,
    ) -> (*const u32, *const T, usize) {
        let n = if nulls.vr && nulls.value && nulls.huge_count {
            usize::MAX / 2 + 3
        } else {
            vrs.len()
        };
        (
            if nulls.vr { ptr::null() } else { vrs.as_ptr() },
            if nulls.value { ptr::null() } else { values },
            n,
        )
    }

    fn null_reason(nulls: Nulls, n: usize) -> Option<&'static str> {
        ((nulls.vr || nulls.value) && n > 0).then_some("an array is NULL with nvr > 0")
    }

    fn get(&mut self, target: Target, kind: Kind, picks: &[VrPick], nulls: Nulls) -> Outcome {
        let Some((c, index)) = self.component(target) else {
            return Ok(());
        };
        let (vrs, unknown) = self.vrs(kind, picks);
        let api = &self.fmu.api;
        let len = vrs.len();
        let mut reals = vec![0.0f64; len];
        let mut ints = vec![0i32; len];
        let mut strings = vec![ptr::null::<c_char>(); len];
        let (status, n, function) = match kind {
            Kind::Real => {
                let (vr, value, n) = self.arrays(nulls, &vrs, reals.as_mut_ptr() as *const f64);
                (
                    self.dog.watch("fmi2GetReal", || unsafe {
                        (api.get_real)(c, vr, n, value as *mut f64)
                    }),
                    n,
                    "fmi2GetReal",
                )
            }
            Kind::Integer | Kind::Boolean => {
                let (vr, value, n) = self.arrays(nulls, &vrs, ints.as_mut_ptr() as *const i32);
                let f = if kind == Kind::Integer {
                    api.get_integer
                } else {
                    api.get_boolean
                };
                let name = if kind == Kind::Integer {
                    "fmi2GetInteger"
                } else {
                    "fmi2GetBoolean"
                };
                (
                    self.dog
                        .watch(name, || unsafe { f(c, vr, n, value as *mut i32) }),
                    n,
                    name,
                )
            }
            Kind::String => {
                let (vr, value, n) =
                    self.arrays(nulls, &vrs, strings.as_mut_ptr() as *const fmi2String);
                (
                    self.dog.watch("fmi2GetString", || unsafe {
                        (api.get_string)(c, vr, n, value as *mut fmi2String)
                    }),
                    n,
                    "fmi2GetString",
                )
            }
        };
        let must_fail = Self::null_reason(nulls, n)
            .or((unknown && n > 0).then_some("a value reference is unknown for the type"));
        if kind == Kind::Real && status == fmi2Error {
            if let Some(i) = index {
                self.no_unreadable_output(i)?;
            }
        }
        let succeeded = status == fmi2OK || status == fmi2Warning;
        if succeeded && !nulls.value {
            let tainted = index.is_some_and(|i| self.slot_mut(i).tainted);
            match kind {
                Kind::Real if !tainted => {
                    if let Some((vr, v)) = vrs.iter().zip(&reals).find(|(_, v)| !v.is_finite()) {
                        let described = index.map(|i| self.describe(i)).unwrap_or_default();
                        return Err(format!(
                            "fmi2GetReal returned {v} for {}; {described}",
                            self.name_of(*vr)
                        ));
                    }
                }
                Kind::Boolean => {
                    if let Some(v) = ints.iter().find(|v| !matches!(v, 0 | 1)) {
                        return Err(format!(
                            "fmi2GetBoolean returned {v}, neither fmi2True nor fmi2False"
                        ));
                    }
                }
                Kind::String => {
                    for p in &strings {
                        if p.is_null() {
                            return Err("fmi2GetString returned a NULL string".into());
                        }
                        // SAFETY: valid until the next fmi2GetString on this instance; reading
                        // it is the check (valgrind sees a bad pointer).
                        let _ = unsafe { CStr::from_ptr(*p) }.to_bytes().len();
                    }
                }
                _ => {}
            }
        }
        self.finish(function, index, status, must_fail)
    }

    #[allow(clippy::too_many_arguments)]
    fn set<T: Copy>(
        &mut self,
        target: Target,
        kind: Kind,
        picks: &[VrPick],
        values: &[T],
        nulls: Nulls,
        value_reason: Option<&'static str>,
        function: &'static str,
        call: impl FnOnce(fmi2Component, *const u32, usize, *const T) -> fmi2Status,
    ) -> Outcome {
        let Some((c, index)) = self.component(target) else {
            return Ok(());
        };
        let (vrs, unknown) = self.vrs(kind, picks);
        let values = &values[..vrs.len()];
        let (vr, value, n) = self.arrays(nulls, &vrs, values.as_ptr());
        let status = self.dog.watch(function, || call(c, vr, n, value));
        let must_fail = Self::null_reason(nulls, n)
            .or((unknown && n > 0).then_some("a value reference is unknown for the type"))
            .or(if nulls.value { None } else { value_reason });
        self.finish(function, index, status, must_fail)
    }

    /// Calls `f` with the `fmi2FMUstate*` that `slot` describes; the state it produced, if any.
    fn with_state_slot(
        &mut self,
        slot: StateSlot,
        what: &'static str,
        f: impl FnOnce(*mut fmi2FMUstate) -> fmi2Status,
    ) -> (fmi2Status, Option<fmi2FMUstate>) {
        let mut state: fmi2FMUstate = match slot {
            StateSlot::Existing(i) => self.seen_state(i),
            _ => ptr::null_mut(),
        };
        let p: *mut fmi2FMUstate = match slot {
            StateSlot::NullPointer => ptr::null_mut(),
            _ => &mut state,
        };
        let status = self.dog.watch(what, || f(p));
        let made = (status == fmi2OK && !state.is_null()).then_some(state);
        (status, made)
    }

    fn deserialize(&mut self, target: Target, buffer: &Buffer, slot: StateSlot) -> Outcome {
        let Some((c, index)) = self.component(target) else {
            return Ok(());
        };
        let pick = |i: &Index| self.buffers[i.index(self.buffers.len())].clone();
        let mut crafted = false;
        let (bytes, null_len, must_fail): (Vec<u8>, Option<usize>, Option<&str>) = match buffer {
            Buffer::Serialized(i) => (pick(i), None, None),
            Buffer::Flipped(i, at, mask) => {
                let mut b = pick(i);
                let k = at.index(b.len());
                b[k] ^= mask;
                // Every header byte is checked (the interface byte and the reserved one too),
                // and the payload by its checksum: any changed byte is refused.
                (b, None, Some("a byte of the buffer was changed"))
            }
            Buffer::Truncated(i, len) => {
                let mut b = pick(i);
                let keep = len.index(b.len());
                b.truncate(keep);
                (b, None, Some("the buffer was truncated"))
            }
            Buffer::Extended(i, tail) => {
                let mut b = pick(i);
                b.extend_from_slice(tail);
                (b, None, Some("bytes were appended to the buffer"))
            }
            Buffer::Crafted(i, at, mask) => {
                let mut b = pick(i);
                if b.len() > HEADER_LEN {
                    let k = HEADER_LEN + at.index(b.len() - HEADER_LEN);
                    b[k] ^= mask;
                    let crc = crc32fast::hash(&b[HEADER_LEN..]);
                    b[40..44].copy_from_slice(&crc.to_le_bytes());
                    crafted = true;
                }
                (b, None, None)
            }
            Buffer::Garbage(b) => (b.clone(), None, Some("the buffer is random bytes")),
            Buffer::Null(n) => (
                Vec::new(),
                Some(*n),
                Some("the buffer is NULL with a size > 0"),
            ),
        };
        let (data, size): (*const fmi2Byte, usize) = match null_len {
            Some(n) => (ptr::null(), n),
            None => (bytes.as_ptr().cast(), bytes.len()),
        };
        let api = &self.fmu.api;
        let (status, made) = self.with_state_slot(slot, "fmi2DeSerializeFMUstate", |p| unsafe {
            (api.de_serialize_fmu_state)(c, data, size, p)
        });
        if let Some(state) = made {
            self.states.push(state);
            if crafted {
                self.stats.crafted_accepted += 1;
                self.crafted.insert(state as usize);
            } else {
                self.crafted.remove(&(state as usize));
            }
        }
        let must_fail = must_fail
            .or(matches!(slot, StateSlot::NullPointer).then_some("the FMUstate pointer is NULL"));
        self.finish("fmi2DeSerializeFMUstate", index, status, must_fail)
    }

    fn status(
        &mut self,
        c: fmi2Component,
        index: Option<usize>,
        which: u8,
        kind: i32,
        value_null: bool,
    ) -> Outcome {
        let api = &self.fmu.api;
        let dog = self.dog;
        let mut status_value = fmi2Status(-1);
        let mut real = 0.0f64;
        let mut int = 0i32;
        let mut string: fmi2String = ptr::null();
        macro_rules! query {
            ($f:ident, $name:literal, $v:expr) => {{
                let p = if value_null {
                    ptr::null_mut()
                } else {
                    $v as *mut _
                };
                (
                    dog.watch($name, || unsafe { (api.co_simulation.$f)(c, kind, p) }),
                    $name,
                )
            }};
        }
        let (status, function) = match which {
            0 => query!(get_status, "fmi2GetStatus", &mut status_value),
            1 => query!(get_real_status, "fmi2GetRealStatus", &mut real),
            2 => query!(get_integer_status, "fmi2GetIntegerStatus", &mut int),
            3 => query!(get_boolean_status, "fmi2GetBooleanStatus", &mut int),
            _ => query!(get_string_status, "fmi2GetStringStatus", &mut string),
        };
        if status == fmi2OK && which == 4 && !value_null {
            if string.is_null() {
                return Err("fmi2GetStringStatus returned a NULL string".into());
            }
            // SAFETY: a string the FMU returned as valid.
            let _ = unsafe { CStr::from_ptr(string) }.to_bytes().len();
        }
        if status == fmi2OK && which == 1 && !value_null && !real.is_finite() {
            return Err(format!("fmi2LastSuccessfulTime is {real}"));
        }
        let must_fail = if value_null {
            Some("the value pointer is NULL")
        } else if !(0..=3).contains(&kind) {
            Some("the status kind is not an fmi2StatusKind")
        } else {
            None
        };
        self.finish(function, index, status, must_fail)
    }

    /// The export layer refuses to hand out a non-finite Real ("... is inf at the current
    /// state: not finite"): the refusal is logged, but a model that holds such a value on an
    /// instance without a crafted state publishes a state no master can read. Looks at the
    /// log of the last call on instance `i` (before `finish` takes it).
    fn no_unreadable_output(&mut self, i: usize) -> Outcome {
        let slot = self.slot_mut(i);
        if slot.tainted {
            return Ok(());
        }
        let log = slot.inst.sink.all();
        match log
            .iter()
            .find(|r| r.message().contains("at the current state: not finite"))
        {
            Some(record) => Err(format!(
                "fmi2GetReal refused a non-finite value on an instance holding no crafted \
                 state: {}; {}",
                record.message(),
                self.describe(i)
            )),
            None => Ok(()),
        }
    }

    fn legal_init(&mut self, i: usize) -> Outcome {
        let Some(slot) = self.slots[i].as_ref() else {
            return Ok(());
        };
        let c = slot.inst.c;
        let api = &self.fmu.api;
        let status = self.dog.watch("fmi2SetupExperiment", || unsafe {
            (api.setup_experiment)(c, 0, 0.0, 0.0, 0, 0.0)
        });
        if status == fmi2OK {
            self.slot_mut(i).time = 0.0;
        }
        self.finish("fmi2SetupExperiment", Some(i), status, None)?;
        let status = self.dog.watch("fmi2EnterInitializationMode", || unsafe {
            (api.enter_initialization_mode)(c)
        });
        self.finish("fmi2EnterInitializationMode", Some(i), status, None)?;
        let status = self.dog.watch("fmi2ExitInitializationMode", || unsafe {
            (api.exit_initialization_mode)(c)
        });
        self.finish("fmi2ExitInitializationMode", Some(i), status, None)
    }

    fn legal_steps(&mut self, i: usize, n: usize) -> Outcome {
        let Some(slot) = self.slots[i].as_ref() else {
            return Ok(());
        };
        let c = slot.inst.c;
        let lander = self.fmu.lander();
        let api = &self.fmu.api;
        for _ in 0..n {
            let t = self.slot_mut(i).time;
            let inputs = inputs_at(lander, t);
            let vrs = &self.base.wiring.inputs;
            let status = self.dog.watch("fmi2SetReal", || unsafe {
                (api.set_real)(c, vrs.as_ptr(), vrs.len(), inputs.as_ptr())
            });
            self.finish("fmi2SetReal", Some(i), status, None)?;
            let vrs = &self.base.wiring.boolean_inputs;
            if !vrs.is_empty() {
                let values: Vec<fmi2Boolean> = boolean_inputs_at(lander, t)
                    .into_iter()
                    .map(fmi2Boolean::from)
                    .collect();
                let status = self.dog.watch("fmi2SetBoolean", || unsafe {
                    (api.set_boolean)(c, vrs.as_ptr(), vrs.len(), values.as_ptr())
                });
                self.finish("fmi2SetBoolean", Some(i), status, None)?;
            }
            let outputs = self.base.wiring.outputs.clone();
            let mut values = vec![0.0; outputs.len()];
            let status = self.dog.watch("fmi2GetReal", || unsafe {
                (api.get_real)(c, outputs.as_ptr(), outputs.len(), values.as_mut_ptr())
            });
            if (status == fmi2OK || status == fmi2Warning) && !self.slot_mut(i).tainted {
                if let Some((vr, v)) = outputs.iter().zip(&values).find(|(_, v)| !v.is_finite()) {
                    return Err(format!(
                        "fmi2GetReal of output {} returned {v}; {}",
                        self.name_of(*vr),
                        self.describe(i)
                    ));
                }
            }
            if status == fmi2Error {
                self.no_unreadable_output(i)?;
            }
            self.finish("fmi2GetReal", Some(i), status, None)?;
            let status = self.dog.watch("fmi2DoStep", || unsafe {
                (api.co_simulation.do_step)(c, t, STEP_S, 1)
            });
            match status {
                fmi2OK | fmi2Warning => self.slot_mut(i).time = t + STEP_S,
                fmi2Discard => self.refresh_time(i),
                _ => {}
            }
            self.finish("fmi2DoStep", Some(i), status, None)?;
            if status != fmi2OK {
                break;
            }
        }
        Ok(())
    }

    /// After any sequence: fmi2Reset on every instance (a fresh one if the instance is
    /// beyond reset, which only a crafted state may cause), then the legal run gives exactly
    /// the reference result; and so does a new instance.
    fn verify(&mut self) -> Outcome {
        for i in 0..self.slots.len() {
            let Some(slot) = self.slots[i].take() else {
                continue;
            };
            slot.inst.take_log();
            let status = self.dog.watch("fmi2Reset", || slot.inst.reset());
            self.stats.check_calls += 1;
            let inst = if status == fmi2OK {
                slot.inst
            } else if slot.tainted && status == fmi2Error {
                self.stats.fatal_after_crafted += 1;
                slot.inst.free();
                self.fmu.instantiate("fresh", false)
            } else {
                return Err(format!(
                    "fmi2Reset on instance {i} returned {}: {:?}",
                    status.label(),
                    slot.inst.take_log()
                ));
            };
            self.compare(&inst, &format!("instance {i} after fmi2Reset"))?;
        }
        let fresh = self.fmu.instantiate("fresh", false);
        self.compare(&fresh, "a new instance")
    }

    fn compare(&mut self, inst: &Instance, what: &str) -> Outcome {
        let run = self
            .dog
            .watch("legal run", || legal_run(inst, CHECK_STEPS))
            .map_err(|e| format!("the legal run on {what} failed: {e}"))?;
        self.stats.check_calls += 3 + 3 * CHECK_STEPS as u64;
        if run != self.base.reference {
            let first = run
                .iter()
                .zip(&self.base.reference)
                .position(|(a, b)| a != b)
                .unwrap_or(run.len().min(self.base.reference.len()));
            return Err(format!(
                "the legal run on {what} differs from the reference at value {first}: {} vs {}",
                run.get(first).map_or(f64::NAN, |b| f64::from_bits(*b)),
                self.base
                    .reference
                    .get(first)
                    .map_or(f64::NAN, |b| f64::from_bits(*b)),
            ));
        }
        Ok(())
    }
}

fn expect_text(p: *const c_char, expected: &str, function: &str) -> Outcome {
    if p.is_null() {
        return Err(format!("{function} returned NULL"));
    }
    // SAFETY: a static string of the FMU.
    let got = unsafe { CStr::from_ptr(p) }.to_string_lossy();
    if got != expected {
        return Err(format!("{function} returned {got:?}, not {expected:?}"));
    }
    Ok(())
}

/// The log of one call on an instance: every message carries the instance name, a known
/// category and text; nothing is more severe than the returned status; an error (or fatal)
/// return comes with a message of that status naming the function; a warning return with a
/// warning message.
fn check_log(
    function: &str,
    status: fmi2Status,
    name: &str,
    tainted: bool,
    records: &[Record],
) -> Outcome {
    for r in records {
        if r.instance_name.as_deref() != Some(name) {
            return Err(format!(
                "{function}: message with instance name {:?}, expected {name:?}",
                r.instance_name
            ));
        }
        let category_known = r
            .category
            .as_deref()
            .is_some_and(|c| CATEGORIES.iter().any(|k| k.to_str() == Ok(c)));
        if !category_known || r.message.is_none() {
            return Err(format!("{function}: malformed message {r:?}"));
        }
        let severe = r.category.as_deref() != Some("logCalls") && r.status >= fmi2Warning;
        if severe && r.status > status {
            return Err(format!(
                "{function} returned {} but logged {r:?}",
                status.label()
            ));
        }
    }
    if status == fmi2Fatal && !tainted {
        return Err(format!("{function} returned fmi2Fatal: {records:?}"));
    }
    let needs = match status {
        fmi2Error | fmi2Fatal => Some(status),
        fmi2Warning => Some(fmi2Warning),
        _ => None,
    };
    if let Some(level) = needs {
        let explained = records.iter().any(|r| {
            r.status == level && (level == fmi2Warning || r.message().starts_with(function))
        });
        if !explained {
            return Err(format!(
                "{function} returned {} without a message naming it: {records:?}",
                status.label()
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(status: fmi2Status, category: &str, message: &str) -> Record {
        Record {
            instance_name: Some("i".into()),
            status,
            category: Some(category.into()),
            message: Some(message.into()),
        }
    }

    #[test]
    fn an_error_without_a_message_naming_the_function_is_a_violation() {
        assert!(check_log("fmi2DoStep", fmi2Error, "i", false, &[]).is_err());
        let other = record(
            fmi2Error,
            "logStatusError",
            "fmi2SetReal: unknown value reference 7",
        );
        assert!(check_log("fmi2DoStep", fmi2Error, "i", false, &[other]).is_err());
        let named = record(
            fmi2Error,
            "logStatusError",
            "fmi2DoStep: communicationStepSize 0",
        );
        assert!(check_log("fmi2DoStep", fmi2Error, "i", false, &[named]).is_ok());
    }

    #[test]
    fn a_message_more_severe_than_the_status_is_a_violation() {
        let error = record(fmi2Error, "logStatusError", "fmi2GetReal: something");
        assert!(check_log("fmi2GetReal", fmi2OK, "i", false, &[error]).is_err());
        // The call trace is logged with status OK and never counts as severe.
        let trace = record(fmi2OK, "logCalls", "fmi2GetReal(nvr=0)");
        assert!(check_log("fmi2GetReal", fmi2OK, "i", false, &[trace]).is_ok());
    }

    #[test]
    fn messages_must_carry_the_instance_name_and_a_declared_category() {
        let mut wrong_name = record(fmi2OK, "logCalls", "fmi2Reset()");
        wrong_name.instance_name = Some("other".into());
        assert!(check_log("fmi2Reset", fmi2OK, "i", false, &[wrong_name]).is_err());
        let unknown = record(fmi2OK, "logEverything", "fmi2Reset()");
        assert!(check_log("fmi2Reset", fmi2OK, "i", false, &[unknown]).is_err());
    }

    #[test]
    fn fatal_is_tolerated_only_after_a_crafted_state() {
        let fatal = record(fmi2Fatal, "logStatusFatal", "fmi2DoStep: internal error");
        assert!(check_log(
            "fmi2DoStep",
            fmi2Fatal,
            "i",
            false,
            std::slice::from_ref(&fatal)
        )
        .is_err());
        assert!(check_log("fmi2DoStep", fmi2Fatal, "i", true, &[fatal]).is_ok());
    }

    #[test]
    fn a_warning_status_needs_a_warning_message() {
        assert!(check_log("fmi2DoStep", fmi2Warning, "i", false, &[]).is_err());
        let warning = record(
            fmi2Warning,
            "logStatusWarning",
            "fmi2DoStep: degenerate inputs",
        );
        assert!(check_log("fmi2DoStep", fmi2Warning, "i", false, &[warning]).is_ok());
    }
}
