//! Parameter refusals through either FMI version, written once so that every FMU crate can
//! check, for FMI 2.0 and 3.0 alike, that a value its model rejects is refused with a log
//! line a user can act on, and that the instance stays usable.
use crate::driver::{Driver, Interface, Status, Version};
use fmi_model::Model;

/// What a model must refuse, by scalar Real parameter name.
#[derive(Debug, Clone, Copy)]
pub struct Refusals {
    /// `(name, value, how the log shows the value)`: refused by the set itself.
    pub in_the_set: &'static [(&'static str, f64, &'static str)],
    /// Sets each accepted that exit initialization refuses together.
    pub at_exit: &'static [AtExit],
    /// The communication step the instance takes to show it is still usable.
    pub step: f64,
}

impl Refusals {
    /// Every case, through version `D`'s functions of model `M`.
    pub fn check<M: Model, D: Driver>(&self, functions: &D::Functions, token: &str) {
        let cases: Vec<Refusal<'_>> = self
            .in_the_set
            .iter()
            .map(|&(name, value, shown)| Refusal {
                value_reference: value_reference::<M>(name),
                name,
                value,
                shown,
            })
            .collect();
        assert_refused_in_the_set::<D>(functions, token, &cases, self.step);
        for case in self.at_exit {
            let sets: Vec<(u32, f64)> = case
                .sets
                .iter()
                .map(|&(n, v)| (value_reference::<M>(n), v))
                .collect();
            let (name, says) = (case.name, case.says);
            assert_refused_at_exit::<D>(functions, token, &sets, name, says, self.step);
        }
    }
}

fn value_reference<M: Model>(name: &str) -> u32 {
    M::declarations()
        .iter()
        .find(|d| d.name == name)
        .unwrap_or_else(|| panic!("no declaration {name}"))
        .value_reference
}

/// Parameter values each within its bounds that the model rejects together.
#[derive(Debug, Clone, Copy)]
pub struct AtExit {
    /// `(name, value)`, set in this order.
    pub sets: &'static [(&'static str, f64)],
    /// The variable the log line names, and what else it says.
    pub name: &'static str,
    pub says: &'static str,
}

/// A scalar Real parameter value the FMU must refuse.
#[derive(Debug, Clone, Copy)]
pub struct Refusal<'a> {
    pub value_reference: u32,
    pub name: &'a str,
    pub value: f64,
    /// How the log line shows the value (`"-0.001"`, `"NaN"`).
    pub shown: &'a str,
}

/// The version's setter of a scalar Real, as the log names it.
fn real_setter(version: Version) -> &'static str {
    match version {
        Version::Fmi2 => "fmi2SetReal",
        Version::Fmi3 => "fmi3SetFloat64",
    }
}

fn open<D: Driver>(functions: &D::Functions, token: &str) -> D {
    let fmu = D::instantiate(functions, "refusals", token, Interface::CoSimulation, false)
        .unwrap_or_else(|log| panic!("instantiate failed: {log:?}"));
    assert_eq!(fmu.enter_initialization_mode(0.0, None), Status::Ok);
    fmu
}

/// Each case on a fresh Co-Simulation instance in initialization mode: the set returns
/// Error and the last log line names the setter, the variable and the value. After an Error
/// both versions allow only a reset (or restoring a state, or freeing the instance): after
/// one the parameter has its start value and the instance initializes and takes a step of
/// `h`.
pub fn assert_refused_in_the_set<D: Driver>(
    functions: &D::Functions,
    token: &str,
    cases: &[Refusal<'_>],
    h: f64,
) {
    let setter = real_setter(D::VERSION);
    for case in cases {
        let fmu: D = open(functions, token);
        let start = fmu.real(case.value_reference);
        let status = fmu.set_real(case.value_reference, case.value);
        let line = fmu.last_message();
        assert_eq!(status, Status::Error, "{}: {line}", case.name);
        for word in [setter, case.name, case.shown] {
            assert!(
                line.contains(word),
                "{}: '{word}' not in '{line}'",
                case.name
            );
        }
        assert_eq!(fmu.reset(), Status::Ok, "{:?}", fmu.messages());
        assert_eq!(fmu.enter_initialization_mode(0.0, None), Status::Ok);
        assert_eq!(fmu.real(case.value_reference).to_bits(), start.to_bits());
        assert_eq!(
            fmu.exit_initialization_mode(),
            Status::Ok,
            "{:?}",
            fmu.messages()
        );
        assert_eq!(fmu.step(0.0, h).status, Status::Ok, "{:?}", fmu.messages());
    }
}

/// Values each accepted by its set that together the model rejects: exit initialization
/// returns Error with a log line naming `name` and `shown`, and after a reset the instance
/// initializes from its start values and takes a step of `h`.
pub fn assert_refused_at_exit<D: Driver>(
    functions: &D::Functions,
    token: &str,
    sets: &[(u32, f64)],
    name: &str,
    shown: &str,
    h: f64,
) {
    let fmu: D = open(functions, token);
    for &(vr, value) in sets {
        assert_eq!(fmu.set_real(vr, value), Status::Ok, "{:?}", fmu.messages());
    }
    let status = fmu.exit_initialization_mode();
    let line = fmu.last_message();
    assert_eq!(status, Status::Error, "{name}: {line}");
    for word in [name, shown] {
        assert!(line.contains(word), "{name}: '{word}' not in '{line}'");
    }
    assert_eq!(fmu.reset(), Status::Ok, "{:?}", fmu.messages());
    fmu.initialize();
    assert_eq!(fmu.step(0.0, h).status, Status::Ok, "{:?}", fmu.messages());
}
