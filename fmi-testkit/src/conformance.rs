//! The conformance suite every FMU crate gets with one line in `tests/conformance.rs`:
//!
//! ```ignore
//! fmi_testkit::conformance!(fmu_gnc, LanderGnc);
//! // an FMU whose metadata lists Model Exchange:
//! fmi_testkit::conformance!(fmu_plant, LanderPlant, model_exchange);
//! ```
//!
//! Everything here is derived from the model's declaration table and the crate's
//! `[package.metadata.fmu]`, never from a list kept by hand, and runs through the crate's own
//! exported C functions in FMI 2.0 and 3.0 alike:
//!
//! - the life cycle (instantiate, initialize, step, terminate, reset, initialize again,
//!   free), a wrong token refused naming it, Model Exchange refused with the reason where
//!   the metadata does not offer it;
//! - every declared variable read, and set to its own value where the standard lets a
//!   master set it, refused naming it (and why) where not, in initialization and in step
//!   mode (so fixed parameters after initialization);
//! - every bound of every settable Real or Integer, and every non-finite Real, refused at
//!   the set with a log line naming the variable and its unit, the start value kept and
//!   the instance usable after a reset;
//! - calls in the wrong state refused naming the function and the state;
//! - the FMU state: get, set, serialize and deserialize continue bit for bit, a corrupt
//!   serialization is refused;
//! - the heap an instance holds (below 64 KiB, all freed), measured in a child process so
//!   that no other test allocates meanwhile;
//! - the checked-in `modelDescription.xml` / `modelDescription.fmi3.xml` match the code.
//!
//! What only one FMU can know (its physics, a message that suggests a unit, parameters
//! refused together) stays in that crate's own tests.
use crate::alloc::CountingAllocator;
use crate::driver::{Driver, Interface, Status, Version};
use fmi_model::{readable, Causality, Declaration, Kind, Limit, Model, Variability};
pub use fmu_metadata::{Fmi, FmuCrate};
use std::path::Path;

/// Heap bound of one instance, peak included.
pub const HEAP_LIMIT_BYTES: isize = 64 * 1024;

/// The environment variable that makes a heap check run its measurement (in the child
/// process the check starts) instead of starting a child.
pub const HEAP_CHILD: &str = "FMI_TESTKIT_HEAP_CHILD";

/// The FMU crate whose tests run (`CARGO_MANIFEST_DIR`), read from its Cargo.toml.
pub fn this_fmu(manifest_dir: &str) -> FmuCrate {
    let dir = Path::new(manifest_dir);
    let path = dir.join("Cargo.toml");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    fmu_metadata::parse_manifest(dir, &text)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .unwrap_or_else(|| {
            panic!(
                "{} has no [package.metadata.fmu]: the conformance suite is for FMU crates",
                path.display()
            )
        })
}

fn fmi(version: Version) -> Fmi {
    match version {
        Version::Fmi2 => Fmi::V2,
        Version::Fmi3 => Fmi::V3,
    }
}

/// The inputs of step `k` an FMU crate may give the suite (`conformance!(.., inputs = f)`)
/// for the checks that run steps (FMU state, heap): `(name, value)`, a vector's element as
/// `name[i]` from 1, a Boolean as 0 or 1. Without it, every input keeps its start value.
pub type Inputs = fn(k: usize) -> Vec<(&'static str, f64)>;

/// One version's entry points and token of the FMU under test.
#[derive(Debug)]
pub struct Subject<D: Driver + 'static> {
    pub functions: &'static D::Functions,
    pub token: String,
    pub manifest_dir: &'static str,
    pub inputs: Option<Inputs>,
}

/// Sets the inputs of step `k`, if the crate gave any.
fn feed<M: Model, D: Driver>(fmu: &D, inputs: Option<Inputs>, k: usize) {
    let Some(inputs) = inputs else {
        return;
    };
    for (name, value) in inputs(k) {
        let (base, element) = match name.split_once('[') {
            Some((base, rest)) => {
                let i: usize = rest
                    .trim_end_matches(']')
                    .parse()
                    .unwrap_or_else(|_| panic!("input {name}: no element number"));
                (base, i.checked_sub(1).expect("elements count from 1"))
            }
            None => (name, 0),
        };
        let d = M::declarations()
            .iter()
            .find(|d| d.name == base && d.causality == Causality::Input)
            .unwrap_or_else(|| panic!("{name} is no declared input"));
        let value = match read(fmu, d).1 {
            Value::Reals(mut bits) => {
                bits[element] = value.to_bits();
                Value::Reals(bits)
            }
            Value::Integer(_) => Value::Integer(value as i32),
            Value::Enumeration(_) => Value::Enumeration(value as i64),
            Value::Boolean(_) => Value::Boolean(value != 0.0),
            Value::String(_) => panic!("{name}: a String input takes no number"),
        };
        let status = write(fmu, d, &value);
        assert!(status.is_success(), "set {name}: {:?}", fmu.messages());
    }
}

impl<D: Driver> Subject<D> {
    fn open(&self, name: &str) -> D {
        D::instantiate(
            self.functions,
            name,
            &self.token,
            Interface::CoSimulation,
            false,
        )
        .unwrap_or_else(|log| panic!("{name}: instantiate failed: {log:?}"))
    }

    /// A fresh instance in initialization mode.
    fn initializing(&self, name: &str) -> D {
        let fmu = self.open(name);
        let status = fmu.enter_initialization_mode(0.0, None);
        assert_eq!(status, Status::Ok, "{name}: {:?}", fmu.messages());
        fmu
    }

    /// Panics unless the metadata ships this version: a suite that ran a version the crate
    /// does not ship would test nothing a user gets.
    fn shipped(&self) -> FmuCrate {
        let fmu = this_fmu(self.manifest_dir);
        assert!(
            fmu.ships(fmi(D::VERSION)),
            "{} does not ship {}: its [package.metadata.fmu] and the conformance! line disagree",
            fmu.model_identifier,
            fmi(D::VERSION)
        );
        fmu
    }
}

fn setter(version: Version, kind_name: &str) -> String {
    format!("{}Set{kind_name}", version.prefix())
}

fn real_type(version: Version) -> &'static str {
    match version {
        Version::Fmi2 => "Real",
        Version::Fmi3 => "Float64",
    }
}

/// The values of one declaration, as a master exchanges them.
#[derive(Debug, Clone, PartialEq)]
enum Value {
    /// Bits, so that NaN and -0.0 compare as what they are.
    Reals(Vec<u64>),
    Integer(i32),
    Enumeration(i64),
    Boolean(bool),
    String(String),
}

fn is_integer_exchanged<M>(d: &Declaration<M>) -> bool {
    matches!(
        d.kind,
        Kind::Integer { .. }
            | Kind::Enumeration {
                as_integer: true,
                ..
            }
    )
}

fn read<M, D: Driver>(fmu: &D, d: &Declaration<M>) -> (Status, Value) {
    let vr = d.value_reference;
    match d.kind {
        Kind::Real { shape, .. } => {
            let (s, v) = fmu.get_real_elements(vr, shape.len());
            (s, Value::Reals(v.iter().map(|x| x.to_bits()).collect()))
        }
        _ if is_integer_exchanged(d) => {
            let (s, v) = fmu.get_integers(&[vr]);
            (s, Value::Integer(v[0]))
        }
        Kind::Enumeration { .. } => {
            let (s, v) = fmu.get_enumeration(vr);
            (s, Value::Enumeration(v))
        }
        Kind::Boolean { .. } => {
            let (s, v) = fmu.get_booleans(&[vr]);
            (s, Value::Boolean(v[0]))
        }
        Kind::String { .. } => {
            let (s, v) = fmu.get_string(vr);
            (s, Value::String(v.unwrap_or_default()))
        }
        Kind::Integer { .. } => unreachable!("exchanged as an Integer"),
    }
}

fn write<M, D: Driver>(fmu: &D, d: &Declaration<M>, value: &Value) -> Status {
    let vr = d.value_reference;
    match value {
        Value::Reals(bits) => {
            let values: Vec<f64> = bits.iter().map(|b| f64::from_bits(*b)).collect();
            fmu.set_real_elements(vr, &values)
        }
        Value::Integer(v) => fmu.set_integers(&[vr], &[*v]),
        Value::Enumeration(v) => fmu.set_enumeration(vr, *v),
        Value::Boolean(v) => fmu.set_booleans(&[vr], &[*v]),
        Value::String(v) => fmu.set_string(vr, v),
    }
}

/// The name a log line gives element `i` of `d` (the same in both versions).
fn element_name<M>(d: &Declaration<M>, i: usize) -> String {
    match d.kind {
        Kind::Real {
            shape: fmi_model::Shape::Vector(_),
            ..
        } => format!("{}[{}]", d.name, i + 1),
        _ => d.name.to_string(),
    }
}

fn settable_at_all<M>(d: &Declaration<M>) -> bool {
    d.variability != Variability::Constant
        && matches!(d.causality, Causality::Parameter | Causality::Input)
}

fn settable_after_initialization<M>(d: &Declaration<M>) -> bool {
    settable_at_all(d) && (d.causality == Causality::Input || d.variability == Variability::Tunable)
}

/// Instantiate, initialize, step over the default experiment's first steps, terminate;
/// reset and do it again; free (on drop). Each step succeeds (OK or a warning) and ends
/// where it was asked to, unless the FMU ends the run.
pub fn life_cycle<M: Model, D: Driver>(subject: &Subject<D>) {
    subject.shipped();
    let fmu = subject.open("life cycle");
    assert!(fmu.messages().is_empty(), "{:?}", fmu.messages());
    let h = M::DEFAULT_EXPERIMENT.step_size;
    assert!(h > 0.0 && h.is_finite(), "default step size {h}");
    for round in 0..2 {
        fmu.initialize();
        let mut t = M::DEFAULT_EXPERIMENT.start_time;
        assert_eq!(t, 0.0, "the kit initializes at t = 0");
        for k in 0..10 {
            let step = fmu.step(t, h);
            assert!(
                step.status.is_success(),
                "round {round}, step {k}: {:?} {:?}",
                step.status,
                fmu.messages()
            );
            if step.ended_early || step.terminated {
                break;
            }
            t += h;
        }
        assert_eq!(fmu.terminate(), Status::Ok, "{:?}", fmu.messages());
        assert_eq!(fmu.reset(), Status::Ok, "{:?}", fmu.messages());
    }
}

/// A token not the FMU's is refused, for each interface the FMU offers: no instance, and a
/// log line quoting it.
pub fn wrong_token_refused<D: Driver>(subject: &Subject<D>) {
    let fmu = subject.shipped();
    let bad = "{not-the-token}";
    let mut interfaces = vec![Interface::CoSimulation];
    if fmu.ships_model_exchange(fmi(D::VERSION)) {
        interfaces.push(Interface::ModelExchange);
    }
    for interface in interfaces {
        let log = D::instantiate(subject.functions, "wrong token", bad, interface, false)
            .err()
            .unwrap_or_else(|| panic!("{interface:?} instantiated with the token {bad}"));
        let messages: Vec<String> = log.into_iter().filter_map(|r| r.message).collect();
        assert!(
            messages
                .iter()
                .any(|m| m.contains(bad) && m.contains("does not match")),
            "{interface:?}: {messages:?}"
        );
    }
}

/// Model Exchange where the metadata does not list it: refused with the reason; where it
/// does, it instantiates.
pub fn model_exchange_as_the_metadata_says<M: Model, D: Driver>(subject: &Subject<D>) {
    let fmu = subject.shipped();
    let result = D::instantiate(
        subject.functions,
        "model exchange",
        &subject.token,
        Interface::ModelExchange,
        false,
    );
    if fmu.ships_model_exchange(fmi(D::VERSION)) {
        assert!(result.is_ok(), "{:?}", result.err());
    } else {
        let log = result.err().expect("Model Exchange instantiated");
        let messages: Vec<String> = log.into_iter().filter_map(|r| r.message).collect();
        // The reason: the FMU, the interface it implements and that it is the only one.
        assert!(
            messages
                .iter()
                .any(|m| [M::MODEL_IDENTIFIER, "Co-Simulation", "only"]
                    .iter()
                    .all(|word| m.contains(word))),
            "{messages:?}"
        );
    }
}

/// In initialization mode and again in step mode: every declared variable reads; what a
/// master may set in that mode takes its own value back unchanged; what it may not is
/// refused with a log line naming it and why, and nothing changes.
pub fn every_variable_gets_and_sets<M: Model, D: Driver>(subject: &Subject<D>) {
    subject.shipped();
    let declarations = M::declarations();
    assert!(!declarations.is_empty(), "no declarations");
    for initialized in [false, true] {
        let mode = if initialized {
            "step"
        } else {
            "initialization"
        };
        let fmu = subject.initializing("get and set");
        if initialized {
            assert_eq!(
                fmu.exit_initialization_mode(),
                Status::Ok,
                "{:?}",
                fmu.messages()
            );
        }
        for d in declarations {
            let (status, value) = read(&fmu, d);
            assert!(
                status.is_success(),
                "get {} in {mode} mode: {status:?} {:?}",
                d.name,
                fmu.messages()
            );
            let may_set = if initialized {
                settable_after_initialization(d)
            } else {
                settable_at_all(d)
            };
            let status = write(&fmu, d, &value);
            if may_set {
                assert!(
                    status.is_success(),
                    "set {} to its own value in {mode} mode: {status:?} {:?}",
                    d.name,
                    fmu.messages()
                );
                let (_, again) = read(&fmu, d);
                assert_eq!(again, value, "{} read back in {mode} mode", d.name);
            } else {
                assert_eq!(status, Status::Error, "set {} in {mode} mode", d.name);
                let line = fmu.last_message();
                assert!(
                    line.contains(d.name) && line.contains("cannot be set"),
                    "set {} in {mode} mode: {line}",
                    d.name
                );
                // The standard allows only a reset after an Error; the kit takes the
                // instance back to the same mode to go on.
                assert_eq!(fmu.reset(), Status::Ok);
                assert_eq!(fmu.enter_initialization_mode(0.0, None), Status::Ok);
                if initialized {
                    assert_eq!(fmu.exit_initialization_mode(), Status::Ok);
                }
                let (_, after) = read(&fmu, d);
                assert_eq!(after, value, "{}: a refused set changed it", d.name);
            }
        }
    }
}

/// A value just past `limit` (the limit itself when it is exclusive).
fn past(limit: Limit, direction: f64) -> f64 {
    match limit {
        Limit::Inclusive(b) => b + direction * (b.abs() * 1e-9).max(1e-9),
        Limit::Exclusive(b) => b,
    }
}

/// Sets `bad` on a fresh instance in initialization mode and expects the set refused with
/// a log line holding each of `words`; then reset: the start value is back, and the
/// instance initializes and steps.
fn refused<M: Model, D: Driver>(
    subject: &Subject<D>,
    d: &Declaration<M>,
    bad: impl Fn(&Value) -> Value,
    words: &[String],
) {
    let fmu = subject.initializing("refusal");
    let (_, start) = read(&fmu, d);
    let status = write(&fmu, d, &bad(&start));
    let line = fmu.last_message();
    assert_eq!(status, Status::Error, "{}: {line}", d.name);
    for word in words {
        assert!(
            line.contains(word.as_str()),
            "{}: {word:?} not in {line:?}",
            d.name
        );
    }
    assert_eq!(fmu.reset(), Status::Ok, "{:?}", fmu.messages());
    assert_eq!(fmu.enter_initialization_mode(0.0, None), Status::Ok);
    assert_eq!(
        read(&fmu, d).1,
        start,
        "{}: the start value after a reset",
        d.name
    );
    assert_eq!(
        fmu.exit_initialization_mode(),
        Status::Ok,
        "{:?}",
        fmu.messages()
    );
    let step = fmu.step(0.0, M::DEFAULT_EXPERIMENT.step_size);
    assert!(step.status.is_success(), "{:?}", fmu.messages());
}

/// Every element of every settable Real past each declared bound, and NaN and ±inf; every
/// settable Integer past its bounds; every enumeration set to a value not an item: each
/// refused by the set, naming the variable (and a Real's unit). Returns how many values
/// were refused, so that a caller can see the suite probed something.
pub fn values_outside_the_declarations_refused<M: Model, D: Driver>(subject: &Subject<D>) -> usize {
    subject.shipped();
    let version = D::VERSION;
    let mut probed = 0;
    for d in M::declarations().iter().filter(|d| settable_at_all(d)) {
        match d.kind {
            Kind::Real {
                shape, min, max, ..
            } => {
                let unit = d.unit.filter(|u| *u != "1");
                let bounds = min
                    .map(|m| past(m, -1.0))
                    .into_iter()
                    .chain(max.map(|m| past(m, 1.0)));
                for element in 0..shape.len() {
                    let name = element_name(d, element);
                    let replace = |value: f64| {
                        move |start: &Value| match start {
                            Value::Reals(bits) => {
                                let mut bits = bits.clone();
                                bits[element] = value.to_bits();
                                Value::Reals(bits)
                            }
                            other => panic!("{other:?} for a Real"),
                        }
                    };
                    for value in bounds.clone() {
                        let mut words = vec![
                            setter(version, real_type(version)),
                            name.clone(),
                            "outside".into(),
                            readable(value),
                        ];
                        words.extend(unit.map(str::to_string));
                        refused(subject, d, replace(value), &words);
                        probed += 1;
                    }
                    for value in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                        let words = [
                            setter(version, real_type(version)),
                            name.clone(),
                            "not finite".into(),
                        ];
                        refused(subject, d, replace(value), &words);
                        probed += 1;
                    }
                }
            }
            Kind::Integer { min, max, .. } => {
                let bad = min
                    .and_then(|m| m.checked_sub(1))
                    .into_iter()
                    .chain(max.and_then(|m| m.checked_add(1)));
                for value in bad {
                    let words = [d.name.to_string(), "outside".into()];
                    refused(subject, d, |_| Value::Integer(value), &words);
                    probed += 1;
                }
            }
            Kind::Enumeration { ty, .. } => {
                let value = ty.max().unwrap_or(0).saturating_add(1);
                let words = [d.name.to_string(), ty.name.to_string()];
                let bad = move |start: &Value| match start {
                    Value::Integer(_) => Value::Integer(value),
                    _ => Value::Enumeration(i64::from(value)),
                };
                refused(subject, d, bad, &words);
                probed += 1;
            }
            Kind::Boolean { .. } | Kind::String { .. } => {}
        }
    }
    probed
}

/// Calls the state machine forbids: each refused with Error and a log line naming the
/// function and the state; the instance then resets and runs.
pub fn wrong_state_calls_refused<M: Model, D: Driver>(subject: &Subject<D>) {
    subject.shipped();
    let p = D::VERSION.prefix();
    let h = M::DEFAULT_EXPERIMENT.step_size;
    let expect = |fmu: &D, status: Status, function: &str| {
        let line = fmu.last_message();
        assert_eq!(status, Status::Error, "{function}: {line}");
        assert!(
            line.contains(&format!("{p}{function}")) && line.contains("illegal call in state"),
            "{function}: {line}"
        );
        assert_eq!(fmu.reset(), Status::Ok, "{function}: {:?}", fmu.messages());
        fmu.initialize();
        assert!(fmu.step(0.0, h).status.is_success(), "{:?}", fmu.messages());
    };
    let fmu = subject.open("wrong state");
    expect(&fmu, fmu.step(0.0, h).status, "DoStep");
    let fmu = subject.open("wrong state");
    expect(
        &fmu,
        fmu.exit_initialization_mode(),
        "ExitInitializationMode",
    );
    let fmu = subject.initializing("wrong state");
    expect(&fmu, fmu.step(0.0, h).status, "DoStep");
    let fmu = subject.open("wrong state");
    fmu.initialize();
    assert_eq!(fmu.terminate(), Status::Ok);
    expect(&fmu, fmu.step(0.0, h).status, "DoStep");
}

/// Every output (Real, Integer, enumeration, Boolean) after one step, as bits.
fn outputs<M: Model, D: Driver>(fmu: &D) -> Vec<Value> {
    M::declarations()
        .iter()
        .filter(|d| d.causality == Causality::Output && !matches!(d.kind, Kind::String { .. }))
        .map(|d| {
            let (status, value) = read(fmu, d);
            assert!(status.is_success(), "get {}: {:?}", d.name, fmu.messages());
            value
        })
        .collect()
}

/// `n` steps of the default step size from step `k0`: the status and every output after
/// each.
fn run<M: Model, D: Driver>(
    fmu: &D,
    inputs: Option<Inputs>,
    k0: usize,
    n: usize,
) -> Vec<(Status, Vec<Value>)> {
    let h = M::DEFAULT_EXPERIMENT.step_size;
    (k0..k0 + n)
        .map(|k| {
            feed::<M, D>(fmu, inputs, k);
            let step = fmu.step(k as f64 * h, h);
            assert!(step.status.is_success(), "step {k}: {:?}", fmu.messages());
            (step.status, outputs::<M, D>(fmu))
        })
        .collect()
}

/// Save the FMU state after a few steps and serialize it; the continuation from it is the
/// same bit for bit when the state is set back, and when the serialization is deserialized
/// into another instance; a serialization with a byte flipped is refused.
pub fn fmu_state_round_trip<M: Model, D: Driver>(subject: &Subject<D>) {
    subject.shipped();
    // Short of any end the default run may come to (a touchdown), long enough to move.
    let (before, after) = (5, 10);
    let fmu = subject.open("state");
    fmu.initialize();
    run::<M, D>(&fmu, subject.inputs, 0, before);
    let (status, state) = fmu.get_state();
    assert_eq!(status, Status::Ok, "{:?}", fmu.messages());
    let (status, bytes) = fmu.serialize(state);
    assert_eq!(status, Status::Ok, "{:?}", fmu.messages());
    let continuation = run::<M, D>(&fmu, subject.inputs, before, after);
    assert_eq!(fmu.set_state(state), Status::Ok, "{:?}", fmu.messages());
    assert_eq!(
        run::<M, D>(&fmu, subject.inputs, before, after),
        continuation,
        "after set state"
    );
    assert_eq!(fmu.free_state(state), Status::Ok);

    let other = subject.open("deserialized");
    other.initialize();
    let (status, restored) = other.deserialize(&bytes);
    assert_eq!(status, Status::Ok, "{:?}", other.messages());
    assert_eq!(
        other.set_state(restored),
        Status::Ok,
        "{:?}",
        other.messages()
    );
    assert_eq!(
        run::<M, D>(&other, subject.inputs, before, after),
        continuation,
        "after deserialize"
    );
    assert_eq!(other.free_state(restored), Status::Ok);

    let mut corrupt = bytes;
    let last = corrupt.len() - 1;
    corrupt[last] ^= 0xff;
    let (status, refused) = other.deserialize(&corrupt);
    assert_eq!(
        status,
        Status::Error,
        "a corrupt serialization was accepted"
    );
    assert!(D::is_null(refused));
}

/// The heap one instance holds while it is initialized, fed its inputs (their start values,
/// then the crate's [`Inputs`] if it gave any) and read every output for up to 200 steps: below [`HEAP_LIMIT_BYTES`] at its peak, all of
/// it freed by the free. Measured twice (the first also counts what the process sets up
/// once), judged on the second.
pub fn heap_within_limit<M: Model, D: Driver>(subject: &Subject<D>, allocator: &CountingAllocator) {
    let inputs: Vec<&Declaration<M>> = M::declarations()
        .iter()
        .filter(|d| d.causality == Causality::Input)
        .collect();
    let h = M::DEFAULT_EXPERIMENT.step_size;
    for round in 0..2 {
        let heap = allocator.measure(
            || subject.open("heap"),
            |fmu| {
                assert_eq!(fmu.enter_initialization_mode(0.0, None), Status::Ok);
                let starts: Vec<Value> = inputs.iter().map(|d| read(fmu, d).1).collect();
                assert_eq!(
                    fmu.exit_initialization_mode(),
                    Status::Ok,
                    "{:?}",
                    fmu.messages()
                );
                for k in 0..200 {
                    for (d, value) in inputs.iter().zip(&starts) {
                        assert!(write(fmu, d, value).is_success(), "{:?}", fmu.messages());
                    }
                    feed::<M, D>(fmu, subject.inputs, k);
                    outputs::<M, D>(fmu);
                    let step = fmu.step(k as f64 * h, h);
                    assert!(step.status.is_success(), "{:?}", fmu.messages());
                    if step.ended_early || step.terminated {
                        break;
                    }
                }
            },
        );
        println!(
            "{} instance heap, {:?}, round {round}: {heap:?}",
            M::MODEL_IDENTIFIER,
            D::VERSION
        );
        assert!(heap.held > 0, "the counter must see the instance");
        assert!(
            heap.peak < HEAP_LIMIT_BYTES,
            "{} bytes at peak, limit {HEAP_LIMIT_BYTES}",
            heap.peak
        );
        if round == 1 {
            assert_eq!(
                heap.after, 0,
                "freeing the instance left {} bytes",
                heap.after
            );
        }
    }
}

/// The name libtest gives test `function` of module `module_path` (`module_path!()`, which
/// starts with the crate's name where libtest's names do not): the conformance suite may be
/// a module of a crate's one test binary or that binary's root.
pub fn test_name(module_path: &str, function: &str) -> String {
    match module_path.split_once("::") {
        Some((_, module)) => format!("{module}::{function}"),
        None => function.to_owned(),
    }
}

/// Runs `test` (this test binary's test of that exact name) alone in a child process, where
/// [`HEAP_CHILD`] is set: there no other test allocates while it measures.
pub fn in_a_child_process(test: &str) {
    let exe = std::env::current_exe().expect("the test binary");
    let output = std::process::Command::new(exe)
        .args([test, "--exact", "--nocapture", "--test-threads=1"])
        .env(HEAP_CHILD, "1")
        .output()
        .expect("run the test binary again");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    println!("{text}");
    assert!(
        output.status.success(),
        "{test} failed in its child process:\n{text}"
    );
    assert!(
        text.contains("1 passed"),
        "{test} did not run in its child:\n{text}"
    );
}

/// The checked-in model descriptions (`modelDescription.xml` for FMI 2.0,
/// `modelDescription.fmi3.xml` for FMI 3.0, each where the crate keeps one) are what the
/// code generates; `generate(version)` gives the one the crate packages.
pub fn checked_in_descriptions_match(manifest_dir: &str, generate: impl Fn(Fmi) -> String) {
    let fmu = this_fmu(manifest_dir);
    let mut checked = 0;
    for (version, file, bin) in [
        (Fmi::V2, "modelDescription.xml", String::new()),
        (Fmi::V3, "modelDescription.fmi3.xml", "_fmi3".to_string()),
    ] {
        let path = Path::new(manifest_dir).join(file);
        if !fmu.ships(version) || !path.exists() {
            continue;
        }
        let regenerate = format!(
            "cargo run -p {} --bin {}_model_description{bin} > {}/{file}",
            fmu.package,
            fmu.lib_name,
            Path::new(manifest_dir)
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        );
        crate::assert_file_matches(&path, &generate(version), &regenerate);
        checked += 1;
    }
    println!("{checked} checked-in model descriptions compared");
}

/// Fails unless the conformance! line says `model_exchange` exactly when the metadata
/// offers Model Exchange in some version: the descriptions compared are the ones packaged.
pub fn model_exchange_declared(manifest_dir: &str, declared: bool) {
    let fmu = this_fmu(manifest_dir);
    let offered = Fmi::ALL.iter().any(|v| fmu.ships_model_exchange(*v));
    assert_eq!(
        declared,
        offered,
        "{}: [package.metadata.fmu] {} Model Exchange; write `conformance!(.., {})`",
        fmu.model_identifier,
        if offered { "offers" } else { "does not offer" },
        if offered {
            "model_exchange"
        } else {
            "without model_exchange"
        }
    );
}

/// The conformance suite of an FMU crate, in its `tests/conformance.rs`:
/// `fmi_testkit::conformance!(fmu_gnc, LanderGnc);`, with `, model_exchange` when its
/// `[package.metadata.fmu]` lists Model Exchange (the model is then a `ContinuousModel`),
/// and `, inputs = f` ([`Inputs`]) to step it with inputs of the crate's choosing.
/// The crate must export both FMI versions and depend on `fmi2-export` and `fmi3-export`
/// (every FMU crate does). It installs a counting global allocator in that test binary.
#[macro_export]
macro_rules! conformance {
    ($krate:ident, $model:ident, model_exchange $(, inputs = $inputs:path)?) => {
        $crate::conformance!(@suite $krate, $model, true, $crate::conformance!(@inputs $($inputs)?), |version| {
            let fmu = $crate::conformance::this_fmu(env!("CARGO_MANIFEST_DIR"));
            match (version, fmu.ships_model_exchange(version)) {
                ($crate::conformance::Fmi::V2, true) => ::fmi2_export::model_description_xml_me::<$krate::$model>(),
                ($crate::conformance::Fmi::V2, false) => ::fmi2_export::model_description_xml::<$krate::$model>(),
                ($crate::conformance::Fmi::V3, true) => ::fmi3_export::model_description_xml_me::<$krate::$model>(),
                ($crate::conformance::Fmi::V3, false) => ::fmi3_export::model_description_xml::<$krate::$model>(),
            }
        });
    };
    ($krate:ident, $model:ident $(, inputs = $inputs:path)?) => {
        $crate::conformance!(@suite $krate, $model, false, $crate::conformance!(@inputs $($inputs)?), |version| match version {
            $crate::conformance::Fmi::V2 => ::fmi2_export::model_description_xml::<$krate::$model>(),
            $crate::conformance::Fmi::V3 => ::fmi3_export::model_description_xml::<$krate::$model>(),
        });
    };
    (@inputs) => {
        ::std::option::Option::None
    };
    (@inputs $inputs:path) => {
        ::std::option::Option::Some($inputs as $crate::conformance::Inputs)
    };
    (@suite $krate:ident, $model:ident, $me:expr, $inputs:expr, $generate:expr) => {
        #[global_allocator]
        static CONFORMANCE_ALLOCATOR: $crate::CountingAllocator = $crate::CountingAllocator::new();
        static CONFORMANCE_FMI2: $crate::Fmi2Functions = $crate::fmi2_functions!($krate);
        static CONFORMANCE_FMI3: $crate::Fmi3Functions = $crate::fmi3_functions!($krate);

        fn fmi2() -> $crate::conformance::Subject<$crate::Fmi2> {
            $crate::conformance::Subject {
                functions: &CONFORMANCE_FMI2,
                token: ::fmi2_export::guid::<$krate::$model>(),
                manifest_dir: env!("CARGO_MANIFEST_DIR"),
                inputs: $inputs,
            }
        }

        fn fmi3() -> $crate::conformance::Subject<$crate::Fmi3> {
            $crate::conformance::Subject {
                functions: &CONFORMANCE_FMI3,
                token: ::fmi3_export::instantiation_token::<$krate::$model>(),
                manifest_dir: env!("CARGO_MANIFEST_DIR"),
                inputs: $inputs,
            }
        }

        #[test]
        fn checked_in_model_descriptions_match_the_code() {
            $crate::conformance::model_exchange_declared(env!("CARGO_MANIFEST_DIR"), $me);
            $crate::conformance::checked_in_descriptions_match(env!("CARGO_MANIFEST_DIR"), $generate);
        }

        $crate::conformance!(@version $krate, $model, fmi2, Fmi2,
            fmi2_life_cycle, fmi2_wrong_token_is_refused, fmi2_model_exchange_as_the_metadata_says,
            fmi2_every_variable_gets_and_sets, fmi2_values_outside_the_declarations_are_refused,
            fmi2_wrong_state_calls_are_refused, fmi2_fmu_state_round_trip, fmi2_heap_within_limit);
        $crate::conformance!(@version $krate, $model, fmi3, Fmi3,
            fmi3_life_cycle, fmi3_wrong_token_is_refused, fmi3_model_exchange_as_the_metadata_says,
            fmi3_every_variable_gets_and_sets, fmi3_values_outside_the_declarations_are_refused,
            fmi3_wrong_state_calls_are_refused, fmi3_fmu_state_round_trip, fmi3_heap_within_limit);
    };
    (@version $krate:ident, $model:ident, $subject:ident, $driver:ident,
        $life:ident, $token:ident, $me:ident, $vars:ident, $bounds:ident, $states:ident,
        $fmu_state:ident, $heap:ident) => {
        #[test]
        fn $life() {
            $crate::conformance::life_cycle::<$krate::$model, $crate::$driver>(&$subject());
        }

        #[test]
        fn $token() {
            $crate::conformance::wrong_token_refused::<$crate::$driver>(&$subject());
        }

        #[test]
        fn $me() {
            $crate::conformance::model_exchange_as_the_metadata_says::<$krate::$model, $crate::$driver>(&$subject());
        }

        #[test]
        fn $vars() {
            $crate::conformance::every_variable_gets_and_sets::<$krate::$model, $crate::$driver>(&$subject());
        }

        #[test]
        fn $bounds() {
            let probed = $crate::conformance::values_outside_the_declarations_refused::<$krate::$model, $crate::$driver>(&$subject());
            println!("{probed} values refused");
        }

        #[test]
        fn $states() {
            $crate::conformance::wrong_state_calls_refused::<$krate::$model, $crate::$driver>(&$subject());
        }

        #[test]
        fn $fmu_state() {
            $crate::conformance::fmu_state_round_trip::<$krate::$model, $crate::$driver>(&$subject());
        }

        #[test]
        fn $heap() {
            if ::std::env::var_os($crate::conformance::HEAP_CHILD).is_some() {
                $crate::conformance::heap_within_limit::<$krate::$model, $crate::$driver>(&$subject(), &CONFORMANCE_ALLOCATOR);
            } else {
                $crate::conformance::in_a_child_process(&$crate::conformance::test_name(
                    module_path!(),
                    stringify!($heap),
                ));
            }
        }
    };
}
