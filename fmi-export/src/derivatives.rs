//! Partial derivatives, once for both versions: FMI 2.0 `fmi2GetDirectionalDerivative`,
//! FMI 3.0 `fmi3GetDirectionalDerivative` and `fmi3GetAdjointDerivative`.
//!
//! A layer resolves the master's value references to scalar elements (FMI 2.0: one per
//! reference; FMI 3.0: every element of an array, serialized) and checks that its lengths
//! match; here the rest is checked before the model sees anything: which variables may be
//! knowns and unknowns, a finite seed. What goes out is checked too: a sensitivity that is
//! not finite is never handed out with status OK.
//!
//! What the FMUs support, in every state both standards allow the calls in: unknowns are
//! continuous Real outputs and, under Model Exchange, state derivatives; knowns are
//! continuous Real inputs and, under Model Exchange, continuous states. Anything else the
//! standards also allow (parameters in initialization, discrete outputs in Event Mode, the
//! independent variable) is refused naming the variable: no model of ours differentiates it.
//!
//! The adjoint `seed^T J` is built from forward columns `J e_j`, one model call per known.
use crate::instance::Instance;
use crate::state::Interface;
use crate::status::{CallError, Success};
use crate::version::Abi;
use fmi_model::{Causality, Kind, Model, ScalarRef, Variability};

/// Which product a call asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// `sensitivity = J seed` (seed per known, sensitivity per unknown).
    Forward,
    /// `sensitivity^T = seed^T J` (seed per unknown, sensitivity per known).
    Adjoint,
}

/// One scalar element a master named, as its layer resolved it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Element {
    pub scalar: ScalarRef,
    /// The value reference the master passed (for messages).
    pub vr: u32,
}

/// The name of an element as a master reads it: `r_nue[2]`, `mass`.
pub fn element_name<M: Model>(scalar: ScalarRef) -> String {
    let d = &M::declarations()[scalar.declaration];
    if d.shape().len() > 1 {
        format!("{}[{}]", d.name, scalar.element + 1)
    } else {
        d.name.to_string()
    }
}

fn is_real<M>(d: &fmi_model::Declaration<M>) -> bool {
    matches!(d.kind, Kind::Real { .. })
}

/// Why `element` cannot be an unknown of this call, if it cannot.
fn check_unknown<M: Model>(
    element: Element,
    interface: Interface,
    states: &[(&str, &str)],
) -> Result<(), CallError> {
    let d = &M::declarations()[element.scalar.declaration];
    let model_exchange = interface == Interface::ModelExchange;
    let output = d.causality == Causality::Output && d.variability == Variability::Continuous;
    let derivative = model_exchange && states.iter().any(|(_, der)| *der == d.name);
    if is_real(d) && (output || derivative) {
        return Ok(());
    }
    Err(CallError::InvalidArgument(format!(
        "unknown {} (vr {}) is {}: the unknowns of this FMU's derivatives are continuous Real \
         outputs{}",
        element_name::<M>(element.scalar),
        element.vr,
        what(d, states),
        if model_exchange {
            " and state derivatives"
        } else {
            " (state derivatives under Model Exchange only)"
        }
    )))
}

/// Why `element` cannot be a known of this call, if it cannot.
fn check_known<M: Model>(
    element: Element,
    interface: Interface,
    states: &[(&str, &str)],
) -> Result<(), CallError> {
    let d = &M::declarations()[element.scalar.declaration];
    let model_exchange = interface == Interface::ModelExchange;
    let input = d.causality == Causality::Input && d.variability == Variability::Continuous;
    let state = model_exchange && states.iter().any(|(state, _)| *state == d.name);
    if is_real(d) && (input || state) {
        return Ok(());
    }
    Err(CallError::InvalidArgument(format!(
        "known {} (vr {}) is {}: the knowns of this FMU's derivatives are continuous Real \
         inputs{}",
        element_name::<M>(element.scalar),
        element.vr,
        what(d, states),
        if model_exchange {
            " and continuous states"
        } else {
            " (continuous states under Model Exchange only)"
        }
    )))
}

/// What a declaration is, in a refusal's words.
fn what<M>(d: &fmi_model::Declaration<M>, states: &[(&str, &str)]) -> String {
    let kind = match d.kind {
        Kind::Real { .. } => "Real",
        Kind::Integer { .. } => "Integer",
        Kind::Enumeration { .. } => "Enumeration",
        Kind::Boolean { .. } => "Boolean",
        Kind::String { .. } => "String",
    };
    if states.iter().any(|(state, _)| *state == d.name) {
        return "a continuous state".into();
    }
    if states.iter().any(|(_, der)| *der == d.name) {
        return "a state derivative".into();
    }
    let causality = match d.causality {
        Causality::Parameter => "parameter",
        Causality::CalculatedParameter => "calculated parameter",
        Causality::Input => "input",
        Causality::Output => "output",
        Causality::Local => "local variable",
        Causality::Independent => "independent variable",
    };
    let variability = match d.variability {
        Variability::Constant => "constant",
        Variability::Fixed => "fixed",
        Variability::Tunable => "tunable",
        Variability::Discrete => "discrete",
        Variability::Continuous => "continuous",
    };
    format!("a {variability} {kind} {causality}")
}

/// The lengths a layer checks: seed and sensitivity against the serialized counts of the
/// knowns and unknowns, as `direction` pairs them.
pub fn check_lengths(
    direction: Direction,
    knowns: usize,
    unknowns: usize,
    seed: usize,
    sensitivity: usize,
) -> Result<(), CallError> {
    let (seed_expected, sensitivity_expected, seed_of, sensitivity_of) = match direction {
        Direction::Forward => (knowns, unknowns, "knowns", "unknowns"),
        Direction::Adjoint => (unknowns, knowns, "unknowns", "knowns"),
    };
    if seed != seed_expected {
        return Err(CallError::InvalidArgument(format!(
            "nSeed = {seed}, but the {seed_of} have {seed_expected} elements"
        )));
    }
    if sensitivity != sensitivity_expected {
        return Err(CallError::InvalidArgument(format!(
            "nSensitivity = {sensitivity}, but the {sensitivity_of} have {sensitivity_expected} \
             elements"
        )));
    }
    Ok(())
}

/// The derivative a call asks for, into `sensitivity` (its length checked by the layer,
/// see [`check_lengths`]). `states` are the model's `(state, derivative)` declaration names
/// (empty for a model without Model Exchange). Refused arguments and a model's refusal leave
/// the instance as it was.
#[allow(clippy::too_many_arguments)]
pub fn evaluate<M: Model, A: Abi>(
    inst: &mut Instance<M, A>,
    f: A::Function,
    direction: Direction,
    states: &[(&str, &str)],
    unknowns: &[Element],
    knowns: &[Element],
    seed: &[f64],
    sensitivity: &mut [f64],
) -> Result<Success, CallError> {
    let interface = inst.interface();
    for &u in unknowns {
        check_unknown::<M>(u, interface, states)?;
    }
    for &k in knowns {
        check_known::<M>(k, interface, states)?;
    }
    if let Some(i) = seed.iter().position(|v| !v.is_finite()) {
        return Err(CallError::InvalidArgument(format!(
            "seed[{i}] = {} is not finite",
            seed[i]
        )));
    }
    let success = inst.refresh(f);
    let unknown_refs: Vec<ScalarRef> = unknowns.iter().map(|e| e.scalar).collect();
    let known_refs: Vec<ScalarRef> = knowns.iter().map(|e| e.scalar).collect();
    let computed = match direction {
        Direction::Forward => {
            inst.core
                .model
                .directional_derivative(&unknown_refs, &known_refs, seed, sensitivity)
        }
        Direction::Adjoint => adjoint(
            &mut inst.core.model,
            &unknown_refs,
            &known_refs,
            seed,
            sensitivity,
        ),
    };
    // A derivative changes nothing in the model: whatever it could not compute (a
    // configuration it does not differentiate, a pair it refuses), the instance stays as it
    // was, in its state.
    if let Err(e) = computed {
        sensitivity.fill(0.0);
        return Err(CallError::Model(crate::describe_model_error::<M>(&e)));
    }
    if let Some(i) = sensitivity.iter().position(|v| !v.is_finite()) {
        let value = sensitivity[i];
        sensitivity.fill(0.0);
        let of = match direction {
            Direction::Forward => unknowns[i],
            Direction::Adjoint => knowns[i],
        };
        return Err(CallError::Model(format!(
            "sensitivity[{i}] ({}) = {value} at the current values: not finite",
            element_name::<M>(of.scalar)
        )));
    }
    Ok(success)
}

/// `sensitivity[j] = sum_i seed[i] dU_i/dK_j`: column `j` of the Jacobian from one forward
/// call with the unit seed `e_j`, then its dot product with the seed.
fn adjoint<M: Model>(
    model: &mut M,
    unknowns: &[ScalarRef],
    knowns: &[ScalarRef],
    seed: &[f64],
    sensitivity: &mut [f64],
) -> Result<(), fmi_model::ModelError> {
    let mut unit = vec![0.0; knowns.len()];
    let mut column = vec![0.0; unknowns.len()];
    for j in 0..knowns.len() {
        unit[j] = 1.0;
        let result = model.directional_derivative(unknowns, knowns, &unit, &mut column);
        unit[j] = 0.0;
        result?;
        sensitivity[j] = seed.iter().zip(&column).map(|(s, c)| s * c).sum();
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_pair_seed_and_sensitivity_with_knowns_or_unknowns() {
        assert!(check_lengths(Direction::Forward, 3, 2, 3, 2).is_ok());
        assert!(check_lengths(Direction::Adjoint, 3, 2, 2, 3).is_ok());
        let e = check_lengths(Direction::Forward, 3, 2, 2, 2).unwrap_err();
        assert_eq!(e.to_string(), "nSeed = 2, but the knowns have 3 elements");
        let e = check_lengths(Direction::Adjoint, 3, 2, 2, 2).unwrap_err();
        assert_eq!(
            e.to_string(),
            "nSensitivity = 2, but the knowns have 3 elements"
        );
    }
}
