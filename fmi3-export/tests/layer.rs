//! The FMI 3.0 layer on a model of its own, exported into this test binary.
#![allow(unsafe_code)]

use fmi_model::{decl, Declaration};
use fmi_testkit::{CoSimulationOptions, Fmi3Instance};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
struct Product {
    gain: f64,
    u: [f64; 2],
}

static PRODUCT: [Declaration<Product>; 3] = [
    decl!(0, parameter gain: gain, "1", ""),
    decl!(1, input u[2]: u, "1", ""),
    decl!(3, output y: get |m, _| m.gain * (m.u[0] + m.u[1]), "1", ""),
];

fmi_testkit::test_model!(
    Product,
    PRODUCT,
    "an output that overflows for large inputs"
);

fmi3_export::export_fmi3!(Product);

/// No NaN or infinity reaches the master with an OK status: a read whose value is not
/// finite is refused naming the variable (and element), and the instance answers again
/// once its inputs give finite values.
#[test]
fn a_non_finite_output_is_refused_and_the_instance_stays_usable() {
    let functions = fmi_testkit::fmi3_functions!(crate);
    let token = fmi3_export::instantiation_token::<Product>();
    let fmu = Fmi3Instance::co_simulation(&functions, "p", &token, CoSimulationOptions::default())
        .expect("instantiated");
    assert_eq!(
        fmu.enter_initialization_mode(0.0, None),
        fmi3_export::ffi::fmi3OK
    );
    // GIVEN a gain whose product with the inputs overflows
    assert_eq!(
        fmu.set_float64(&[0, 1], &[f64::MAX, 1.0, 1.0]),
        fmi3_export::ffi::fmi3OK
    );
    // WHEN the output is read THEN it is refused, naming it
    let (status, _) = fmu.get_float64(&[3], 1);
    assert_eq!(status, fmi3_export::ffi::fmi3Error);
    let message = fmu.last_message();
    assert!(
        message.starts_with("fmi3GetFloat64: variable y (vr 3) is inf"),
        "{message}"
    );
    // AND with inputs that give a finite value the same read answers
    assert_eq!(
        fmu.set_float64(&[1], &[0.25, 0.25]),
        fmi3_export::ffi::fmi3OK
    );
    let (status, y) = fmu.get_float64(&[3], 1);
    assert_eq!(status, fmi3_export::ffi::fmi3OK);
    assert_eq!(y, [f64::MAX * 0.5]);
}
