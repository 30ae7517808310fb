//! Partial derivatives through the FMI 3.0 layer, on a small Model Exchange model of its own
//! whose Jacobian is known in closed form: directional and adjoint products, array knowns
//! serialized, the refusals (wrong kinds, lengths, NULL, state) and the model description.
#![allow(unsafe_code)]

use fmi_model::{
    decl, ContinuousModel, Declaration, Dependencies, EventUpdate, Experiment, Log, Model,
    ModelError, ScalarRef, StepEnd,
};
use fmi_testkit::{CoSimulationOptions, Fmi3Instance};
use serde::{Deserialize, Serialize};

/// `x' = [x1, -k x0 + u0 x0]`, `y = x0^2 + u0 u1`: a dense little Jacobian.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct Spring {
    k: f64,
    u: [f64; 2],
    x: [f64; 2],
}

// Positions in the declaration table (k is 0).
const U: usize = 1;
const Y: usize = 2;
const X: usize = 3;
const DER_X: usize = 4;

static SPRING: [Declaration<Spring>; 6] = [
    decl!(0, parameter k: k, "1", ""),
    decl!(1, input u[2]: u, "1", ""),
    decl!(3, output y: get |m, _| m.x[0] * m.x[0] + m.u[0] * m.u[1], "1", ""),
    decl!(4, continuous_state x[2]: get |m, i| m.x[i], "1", ""),
    decl!(6, derivative der_x[2]: get |m, i| m.rate()[i], "1", ""),
    decl!(8, local z: get |m, _| m.x[0], "1", ""),
];

impl Spring {
    fn rate(&self) -> [f64; 2] {
        [self.x[1], -self.k * self.x[0] + self.u[0] * self.x[0]]
    }

    /// d(value)/d(known) by hand.
    fn partial(&self, unknown: ScalarRef, known: ScalarRef) -> f64 {
        let (u, x, k) = (self.u, self.x, self.k);
        match (
            unknown.declaration,
            unknown.element,
            known.declaration,
            known.element,
        ) {
            (Y, _, X, 0) => 2.0 * x[0],
            (Y, _, U, 0) => u[1],
            (Y, _, U, 1) => u[0],
            (DER_X, 0, X, 1) => 1.0,
            (DER_X, 1, X, 0) => -k + u[0],
            (DER_X, 1, U, 0) => x[0],
            _ => 0.0,
        }
    }
}

impl Model for Spring {
    const MODEL_IDENTIFIER: &'static str = "Spring";
    const MODEL_NAME: &'static str = "Spring";
    const VERSION: &'static str = "0.0.0";
    const DESCRIPTION: &'static str = "a model with a known Jacobian";
    const DEFAULT_EXPERIMENT: Experiment = Experiment {
        start_time: 0.0,
        stop_time: 1.0,
        step_size: 0.1,
        tolerance: None,
    };
    const PROVIDES_DIRECTIONAL_DERIVATIVES: bool = true;

    fn declarations() -> &'static [Declaration<Self>] {
        &SPRING
    }

    fn output_dependencies(_output: &str) -> Dependencies {
        Dependencies::AllInputs
    }

    fn exit_initialization(&mut self, _: f64, _: &mut Log) -> Result<(), ModelError> {
        Ok(())
    }

    fn directional_derivative(
        &mut self,
        unknowns: &[ScalarRef],
        knowns: &[ScalarRef],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> Result<(), ModelError> {
        for (out, &unknown) in sensitivity.iter_mut().zip(unknowns) {
            *out = knowns
                .iter()
                .zip(seed)
                .map(|(&known, s)| self.partial(unknown, known) * s)
                .sum();
        }
        Ok(())
    }

    fn do_step(&mut self, _: f64, _: f64, _: &mut Log) -> Result<StepEnd, ModelError> {
        Ok(StepEnd::Complete)
    }
}

impl ContinuousModel for Spring {
    const STATE_DERIVATIVES: &'static [(&'static str, &'static str)] = &[("x", "der_x")];
    const EVENT_INDICATORS: usize = 1;
    const EVENT_INDICATOR_VARIABLES: &'static [&'static str] = &["z"];
    const DECLARES_STATE_DEPENDENCIES: bool = true;

    fn state_dependencies(unknown: &str) -> Option<&'static [&'static str]> {
        match unknown {
            "y" | "der_x" => Some(&["x"]),
            _ => None,
        }
    }

    fn derivative_input_dependencies(_: &str) -> Dependencies {
        Dependencies::Inputs(&["u"])
    }

    fn state_count(&self) -> usize {
        2
    }
    fn event_indicator_count(&self) -> usize {
        1
    }
    fn set_time(&mut self, _: f64) {}
    fn states(&self, x: &mut [f64]) {
        x.copy_from_slice(&self.x);
    }
    fn set_states(&mut self, x: &[f64]) -> Result<(), ModelError> {
        self.x.copy_from_slice(x);
        Ok(())
    }
    fn nominals(&self, nominal: &mut [f64]) {
        nominal.fill(1.0);
    }
    fn derivatives(&mut self, dx: &mut [f64]) -> Result<(), ModelError> {
        dx.copy_from_slice(&self.rate());
        Ok(())
    }
    fn event_indicators(&mut self, z: &mut [f64]) -> Result<(), ModelError> {
        z[0] = self.x[0];
        Ok(())
    }
    fn update_discrete_states(&mut self, _: &mut Log) -> Result<EventUpdate, ModelError> {
        Ok(EventUpdate::default())
    }
}

fmi3_export::export_fmi3!(Spring, model_exchange);

use fmi3_export::ffi::{fmi3Error, fmi3OK};

/// A Model Exchange instance in Continuous-Time Mode at k = 3, u = [0.5, 2], x = [1.5, -1].
fn running() -> Fmi3Instance {
    let functions = fmi_testkit::fmi3_functions!(crate);
    let token = fmi3_export::instantiation_token::<Spring>();
    let fmu = Fmi3Instance::model_exchange(&functions, "s", &token, true).expect("instantiated");
    assert_eq!(fmu.enter_initialization_mode(0.0, None), fmi3OK);
    assert_eq!(fmu.set_float64(&[0, 1], &[3.0, 0.5, 2.0]), fmi3OK);
    assert_eq!(fmu.exit_initialization_mode(), fmi3OK);
    assert_eq!(fmu.enter_continuous_time_mode(), fmi3OK);
    assert_eq!(fmu.set_continuous_states(&[1.5, -1.0]), fmi3OK);
    fmu
}

/// The Jacobian of [y, der_x[1], der_x[2]] over [u[1], u[2], x[1], x[2]] at `running()`.
const JACOBIAN: [[f64; 4]; 3] = [
    [2.0, 0.5, 3.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
    [1.5, 0.0, -2.5, 0.0],
];

#[test]
fn directional_derivatives_are_the_jacobian_times_the_seed_with_arrays_serialized() {
    let fmu = running();
    let seed = [0.25, -1.0, 2.0, 0.5];
    // Unknowns y and der_x (2 elements), knowns u (2) and x (2): serialized counts 3 and 4.
    let (status, sensitivity) = fmu.derivative(false, &[3, 6], &[1, 4], &seed, 3);
    assert_eq!(status, fmi3OK, "{:?}", fmu.messages());
    for (row, value) in JACOBIAN.iter().zip(&sensitivity) {
        let expected: f64 = row.iter().zip(&seed).map(|(j, s)| j * s).sum();
        assert_eq!(*value, expected);
    }
}

#[test]
fn the_adjoint_is_the_transposed_product() {
    let fmu = running();
    let seed = [1.0, -2.0, 0.75];
    let (status, sensitivity) = fmu.derivative(true, &[3, 6], &[1, 4], &seed, 4);
    assert_eq!(status, fmi3OK, "{:?}", fmu.messages());
    for (j, value) in sensitivity.iter().enumerate() {
        let expected: f64 = (0..3).map(|i| seed[i] * JACOBIAN[i][j]).sum();
        assert_eq!(*value, expected, "column {j}");
    }
}

#[test]
fn bad_arguments_are_refused_naming_them_and_the_instance_stays_usable() {
    let fmu = running();
    let refused = |unknowns: &[u32], knowns: &[u32], seed: &[f64], n: usize, says: &str| {
        let (status, values) = fmu.derivative(false, unknowns, knowns, seed, n);
        assert_eq!(status, fmi3Error, "{unknowns:?} {knowns:?}");
        let message = fmu.last_message();
        assert!(message.contains(says), "{message}");
        assert!(values.iter().all(|v| v.is_nan() || *v == 0.0));
    };
    refused(
        &[3],
        &[0],
        &[1.0],
        1,
        "known k (vr 0) is a fixed Real parameter",
    );
    refused(
        &[8],
        &[1],
        &[1.0, 0.0],
        1,
        "unknown z (vr 8) is a continuous Real local",
    );
    refused(
        &[4],
        &[1],
        &[1.0, 0.0],
        2,
        "unknown x[1] (vr 4) is a continuous state",
    );
    refused(&[3], &[77], &[1.0], 1, "known vr 77: no variable has it");
    refused(
        &[3],
        &[1],
        &[1.0],
        1,
        "nSeed = 1, but the knowns have 2 elements",
    );
    refused(
        &[3],
        &[1],
        &[1.0, 0.0],
        2,
        "nSensitivity = 2, but the unknowns have 1",
    );
    refused(
        &[3],
        &[1],
        &[f64::NAN, 0.0],
        1,
        "seed[0] = NaN is not finite",
    );
    refused(&[3], &[999_999], &[1.0], 1, "known time (vr 999999)");
    // A product that overflows (dy/du[1] = u[2] = 2 times 1e308) is never handed out.
    refused(&[3], &[1], &[1e308, 0.0], 1, "sensitivity[0] (y) = inf");
    // NULL arrays with a count.
    let function = fmu.functions().derivatives.directional;
    let mut out = [0.0];
    let status = unsafe {
        function(
            fmu.instance(),
            std::ptr::null(),
            1,
            [1u32].as_ptr(),
            1,
            [1.0, 0.0].as_ptr(),
            2,
            out.as_mut_ptr(),
            1,
        )
    };
    assert_eq!(status, fmi3Error);
    assert!(fmu.last_message().contains("argument unknowns is NULL"));
    // AND the instance still answers
    let (status, _) = fmu.derivative(false, &[3], &[1], &[1.0, 0.0], 1);
    assert_eq!(status, fmi3OK, "{:?}", fmu.messages());
}

#[test]
fn co_simulation_knows_inputs_only_and_instantiated_is_no_state_for_derivatives() {
    let functions = fmi_testkit::fmi3_functions!(crate);
    let token = fmi3_export::instantiation_token::<Spring>();
    let fmu = Fmi3Instance::co_simulation(&functions, "s", &token, CoSimulationOptions::default())
        .expect("instantiated");
    let (status, _) = fmu.derivative(false, &[3], &[1], &[1.0, 0.0], 1);
    assert_eq!(status, fmi3Error);
    assert!(
        fmu.last_message()
            .contains("illegal call in state Instantiated"),
        "{}",
        fmu.last_message()
    );
    assert_eq!(fmu.enter_initialization_mode(0.0, None), fmi3OK);
    assert_eq!(fmu.set_float64(&[1], &[0.5, 2.0]), fmi3OK);
    assert_eq!(fmu.exit_initialization_mode(), fmi3OK);
    let (status, dy) = fmu.derivative(false, &[3], &[1], &[1.0, 0.0], 1);
    assert_eq!(status, fmi3OK, "{:?}", fmu.messages());
    assert_eq!(dy, [2.0]);
    let (status, _) = fmu.derivative(false, &[3], &[4], &[1.0, 0.0], 1);
    assert_eq!(status, fmi3Error);
    assert!(
        fmu.last_message()
            .contains("known x[1] (vr 4) is a continuous state"),
        "{}",
        fmu.last_message()
    );
}

#[test]
fn the_description_declares_the_capability_and_every_dependency() {
    let xml = fmi3_export::model_description_xml_me::<Spring>();
    assert!(
        xml.contains(r#"providesDirectionalDerivatives="true" providesAdjointDerivatives="true""#)
    );
    assert!(
        xml.contains(r#"<Output valueReference="3" dependencies="1 4"/>"#),
        "{xml}"
    );
    assert!(
        xml.contains(r#"<ContinuousStateDerivative valueReference="6" dependencies="1 4"/>"#),
        "{xml}"
    );
}
