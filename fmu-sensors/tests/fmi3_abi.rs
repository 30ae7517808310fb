//! LanderSensors through its FMI 3.0 C functions: arrays set and read whole, Booleans, a
//! run that equals the sensor model's own, bit for bit.
use fmi_model::Model;
use fmi_testkit::fmi3_ffi::*;
use fmi_testkit::{fmi3_functions, CoSimulationOptions, Fmi3Functions, Fmi3Instance};
use fmu_sensors::model::{SensorParameters, Sensors, Truth};
use fmu_sensors::LanderSensors;

static FUNCTIONS: Fmi3Functions = fmi3_functions!(fmu_sensors);

fn vr(name: &str) -> u32 {
    LanderSensors::declarations()
        .iter()
        .find(|d| d.name == name)
        .unwrap_or_else(|| panic!("no declaration {name}"))
        .value_reference
}

fn truth(k: usize) -> Truth {
    let t = k as f64 * 0.01;
    Truth {
        r_nue_m: [5.0, 900.0 - 10.0 * t, 1.0],
        v_nue_mps: [1.0, -10.0, 0.0],
        q_body_to_nue: [1.0, 0.0, 0.0, 0.0],
        omega_body_radps: [0.0, 0.01, 0.0],
        specific_force_body_mps2: [0.0, 1.62, 0.0],
    }
}

#[test]
fn an_fmi3_run_equals_the_sensor_model_bit_for_bit() {
    let token = fmi3_export::instantiation_token::<LanderSensors>();
    let fmu = Fmi3Instance::co_simulation(
        &FUNCTIONS,
        "sensors",
        &token,
        CoSimulationOptions::default(),
    )
    .unwrap_or_else(|log| panic!("{log:?}"));
    assert_eq!(fmu.enter_initialization_mode(0.0, None), fmi3OK);
    assert_eq!(fmu.set_int32(&[vr("seed")], &[4]), fmi3OK);
    assert_eq!(
        fmu.set_float64(&[vr("velocimeter_dropout_probability")], &[0.2]),
        fmi3OK
    );
    assert_eq!(
        fmu.exit_initialization_mode(),
        fmi3OK,
        "{:?}",
        fmu.messages()
    );
    let params = SensorParameters {
        seed: 4,
        velocimeter: fmu_sensors::model::parameters::BeamErrors {
            dropout_probability: 0.2,
            ..SensorParameters::default().velocimeter
        },
        ..SensorParameters::default()
    };
    let mut model = Sensors::start(&params);
    for k in 0..100 {
        let t = truth(k);
        let inputs: [(&str, &[f64]); 5] = [
            ("r_nue", &t.r_nue_m),
            ("v_nue", &t.v_nue_mps),
            ("q_body_to_nue", &t.q_body_to_nue),
            ("omega_body", &t.omega_body_radps),
            ("specific_force_body", &t.specific_force_body_mps2),
        ];
        for (name, values) in inputs {
            assert_eq!(fmu.set_float64(&[vr(name)], values), fmi3OK, "{name}");
        }
        let expected = model.measure(&params, &t).unwrap();
        let (status, y) = fmu.get_float64(
            &[
                vr("accel_body_meas"),
                vr("gyro_body_meas"),
                vr("altimeter_range"),
                vr("velocimeter_los_velocity"),
            ],
            10,
        );
        assert_eq!(status, fmi3OK, "{:?}", fmu.messages());
        let mut want = expected.accel_body_meas_mps2.to_vec();
        want.extend(expected.gyro_body_meas_radps);
        want.push(expected.altimeter_range_m);
        want.extend(expected.velocimeter_los_velocity_mps);
        assert_eq!(y, want, "step {k}");
        let names = [
            "altimeter_valid",
            "velocimeter_valid_1",
            "velocimeter_valid_2",
            "velocimeter_valid_3",
        ];
        let (status, valid) = fmu.get_booleans(&names.map(vr));
        assert_eq!(status, fmi3OK);
        assert_eq!(valid[0], expected.altimeter_valid);
        assert_eq!(&valid[1..], &expected.velocimeter_valid);
        assert_eq!(
            fmu.do_step(k as f64 * 0.01, 0.01).status,
            fmi3OK,
            "{:?}",
            fmu.messages()
        );
        model.step(&params, 0.01).unwrap();
    }
}
