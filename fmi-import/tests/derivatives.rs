//! Directional and adjoint derivatives through the importer: against the Reference-FMUs'
//! VanDerPol (exact partials written by hand in its C, checked here against the formula of
//! its equations), and refused before the call when an FMU does not declare them.
use crate::archives::STUB_DESCRIPTION;
use crate::common::StubFmu;
use fmi_import::{CallError, Fmu, Instance, InstanceOptions, Interface, MeVector};

#[path = "fixtures/reference_fmus.rs"]
mod reference_fmus;

const MU: f64 = 3.5;
// x0, der(x0), x1, der(x1), mu
const X0: u32 = 1;
const DER_X0: u32 = 2;
const X1: u32 = 3;
const DER_X1: u32 = 4;

/// The Jacobian of `der(x0) = x1`, `der(x1) = mu (1 - x0^2) x1 - x0`.
fn van_der_pol_jacobian(x0: f64, x1: f64) -> [[f64; 2]; 2] {
    [
        [0.0, 1.0],
        [-2.0 * MU * x0 * x1 - 1.0, MU * (1.0 - x0 * x0)],
    ]
}

fn model_exchange(fmu: &Fmu) -> Instance {
    let mut instance = fmu
        .instantiate_with(
            "vdp",
            InstanceOptions {
                interface: Interface::ModelExchange,
                ..Default::default()
            },
        )
        .expect("instantiate");
    instance.setup_experiment(None, 0.0, None).unwrap();
    instance.enter_initialization_mode().unwrap();
    instance.set_real_by_name("mu", MU).unwrap();
    instance.exit_initialization_mode().unwrap();
    instance.enter_continuous_time_mode().unwrap();
    instance
}

fn check_van_der_pol(version: u8) {
    let temp = tempfile::tempdir().unwrap();
    let Some(dir) = reference_fmus::van_der_pol(version, temp.path()) else {
        return;
    };
    let fmu = Fmu::load(&dir).expect("load VanDerPol");
    let mut vdp = model_exchange(&fmu);
    assert_eq!(vdp.derivative_refusal(false), None);

    // GIVEN the declared structure: states x0, x1; der(x0) on x1 only, der(x1) on both
    let structure = vdp.derivative_structure().unwrap();
    assert_eq!(structure.states, [X0, X1]);
    assert_eq!(structure.derivatives[0].unknown, DER_X0);
    assert_eq!(structure.derivatives[0].knowns.as_deref(), Some(&[X1][..]));
    assert!(structure.derivatives[1].depends_on(X0) && structure.derivatives[1].depends_on(X1));

    for (x0, x1) in [(2.0, 0.0), (-0.7, 1.3), (0.25, -2.5)] {
        vdp.set_continuous_states(&[x0, x1]).unwrap();
        let expected = van_der_pol_jacobian(x0, x1);
        // WHEN each column is asked for with a unit seed
        for (column, known) in [X0, X1].into_iter().enumerate() {
            let mut sensitivity = [f64::NAN; 2];
            vdp.get_directional_derivative(&[DER_X0, DER_X1], &[known], &[1.0], &mut sensitivity)
                .unwrap();
            // THEN it is the Jacobian's column
            for row in 0..2 {
                assert!(
                    (sensitivity[row] - expected[row][column]).abs() < 1e-12,
                    "FMI {version} at ({x0}, {x1}): d der[{row}] / d x[{column}] = {} not {}",
                    sensitivity[row],
                    expected[row][column]
                );
            }
        }
        // AND a seed of both states is the Jacobian times the seed
        let seed = [0.3, -1.1];
        let mut sensitivity = [f64::NAN; 2];
        vdp.get_directional_derivative(&[DER_X0, DER_X1], &[X0, X1], &seed, &mut sensitivity)
            .unwrap();
        for row in 0..2 {
            let jv = expected[row][0] * seed[0] + expected[row][1] * seed[1];
            assert!((sensitivity[row] - jv).abs() < 1e-12);
        }
        // AND it agrees with a central difference of the derivatives the FMU computes
        let mut plus = [0.0; 2];
        let mut minus = [0.0; 2];
        let h = 1e-6;
        vdp.set_continuous_states(&[x0 + h, x1]).unwrap();
        vdp.get_vector(MeVector::Derivatives, &mut plus).unwrap();
        vdp.set_continuous_states(&[x0 - h, x1]).unwrap();
        vdp.get_vector(MeVector::Derivatives, &mut minus).unwrap();
        assert!(((plus[1] - minus[1]) / (2.0 * h) - expected[1][0]).abs() < 1e-6);
        vdp.set_continuous_states(&[x0, x1]).unwrap();

        // AND in FMI 3.0 the adjoint is the transposed product
        if version == 3 {
            let weights = [0.6, -0.4];
            let mut adjoint = [f64::NAN; 2];
            vdp.get_adjoint_derivative(&[DER_X0, DER_X1], &[X0, X1], &weights, &mut adjoint)
                .unwrap();
            for column in 0..2 {
                let wj = weights[0] * expected[0][column] + weights[1] * expected[1][column];
                assert!((adjoint[column] - wj).abs() < 1e-12, "adjoint {adjoint:?}");
            }
        }
    }
    // AND an FMI 2.0 instance has no adjoint, refused without a call
    if version == 2 {
        let error = vdp
            .get_adjoint_derivative(&[DER_X0], &[X0], &[1.0], &mut [0.0])
            .unwrap_err();
        assert!(error.to_string().contains("FMI 2.0"), "{error}");
    }
    // AND a seed of the wrong length is refused naming the variables
    let error = vdp
        .get_directional_derivative(&[DER_X0], &[X0, X1], &[1.0], &mut [0.0])
        .unwrap_err();
    let text = error.to_string();
    assert!(
        text.contains("2 value references but 1 values") && text.contains("der(x0)"),
        "{text}"
    );
}

#[test]
fn van_der_pol_fmi2_gives_its_exact_jacobian() {
    check_van_der_pol(2);
}

#[test]
fn van_der_pol_fmi3_gives_its_exact_jacobian_and_its_adjoint() {
    check_van_der_pol(3);
}

#[test]
fn an_fmu_that_does_not_declare_derivatives_is_not_asked() {
    // GIVEN the stub, whose description declares no providesDirectionalDerivative
    let stub = StubFmu::standard();
    let fmu = Fmu::load(&stub.dir).unwrap();
    let mut instance = fmu.instantiate("stub", false).unwrap();
    // WHEN derivatives are asked for
    let error = instance
        .get_directional_derivative(&[0], &[0], &[1.0], &mut [0.0])
        .unwrap_err();
    // THEN the importer refuses, naming the function, the instance, the model, the flag and
    // the variables, without calling the FMU (whose function would answer fmi2Error)
    let CallError::InvalidArgument {
        function, reason, ..
    } = &error
    else {
        panic!("not a refusal: {error}");
    };
    assert_eq!(*function, "fmi2GetDirectionalDerivative");
    let text = error.to_string();
    for part in [
        "instance 'stub'",
        "not called",
        "model 'Stub'",
        "providesDirectionalDerivative=\"true\"",
        "<CoSimulation>",
        "(x)",
    ] {
        assert!(text.contains(part), "{part:?} missing from {text}");
    }
    assert!(reason.contains("partials"), "{reason}");
}

#[test]
fn an_fmu_that_declares_derivatives_is_asked_and_its_failure_names_the_variables() {
    // GIVEN the stub declaring the capability (its function answers fmi2Error)
    let description = STUB_DESCRIPTION.replace(
        "canSerializeFMUstate=\"true\"/>",
        "canSerializeFMUstate=\"true\" providesDirectionalDerivative=\"true\"/>",
    );
    assert_ne!(description, STUB_DESCRIPTION);
    let stub = StubFmu::build(&[], &description);
    let fmu = Fmu::load(&stub.dir).unwrap();
    let mut instance = fmu.instantiate("stub", false).unwrap();
    let error = instance
        .get_directional_derivative(&[0], &[0], &[1.0], &mut [0.0])
        .unwrap_err();
    // THEN the FMU was called, and the error says what was asked of which model
    let CallError::Fmi(fmi) = &error else {
        panic!("not the FMU's error: {error}");
    };
    assert_eq!(fmi.function, "fmi2GetDirectionalDerivative");
    let text = error.to_string();
    assert!(
        text.contains("model 'Stub' failed to give the partials of (x) with respect to (x)"),
        "{text}"
    );
}
