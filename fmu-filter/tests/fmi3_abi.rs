//! LanderFilter through its FMI 3.0 C functions: arrays set and read whole, Boolean inputs,
//! Integer outputs, a run that equals the filter model's own, bit for bit.
use fmi_model::Model;
use fmi_testkit::fmi3_ffi::*;
use fmi_testkit::{fmi3_functions, CoSimulationOptions, Fmi3Functions, Fmi3Instance};
use fmu_filter::fmu::{step, Measurements};
use fmu_filter::model::covariance::NAVIGATION;
use fmu_filter::model::{Eskf, FilterParameters, Imu};
use fmu_filter::LanderFilter;

static FUNCTIONS: Fmi3Functions = fmi3_functions!(fmu_filter);

fn vr(name: &str) -> u32 {
    LanderFilter::declarations()
        .iter()
        .find(|d| d.name == name)
        .unwrap_or_else(|| panic!("no declaration {name}"))
        .value_reference
}

/// Plausible measurements of a descent from 800 m, the third beam lost every fourth step.
fn measurements(k: usize) -> Measurements {
    let t = k as f64 * 0.01;
    Measurements {
        imu: Imu {
            accel_body_mps2: [0.001, 1.62, -0.002],
            gyro_body_radps: [1e-5, 0.0, -2e-5],
        },
        altimeter_range_m: 800.0 - 8.0 * t + 0.1 * libm::sin(13.0 * t),
        altimeter_valid: true,
        velocimeter_los_velocity_mps: [7.5, 7.6, 7.4],
        velocimeter_valid: [true, true, !k.is_multiple_of(4)],
    }
}

#[test]
fn an_fmi3_run_equals_the_filter_model_bit_for_bit() {
    let token = fmi3_export::instantiation_token::<LanderFilter>();
    let fmu =
        Fmi3Instance::co_simulation(&FUNCTIONS, "filter", &token, CoSimulationOptions::default())
            .unwrap_or_else(|log| panic!("{log:?}"));
    assert_eq!(fmu.enter_initialization_mode(0.0, None), fmi3OK);
    assert_eq!(fmu.set_float64(&[vr("v0_nue")], &[0.0, -8.0, 0.0]), fmi3OK);
    assert_eq!(fmu.set_booleans(&[vr("chi2_gating")], &[true]), fmi3OK);
    assert_eq!(
        fmu.exit_initialization_mode(),
        fmi3OK,
        "{:?}",
        fmu.messages()
    );
    let params = FilterParameters {
        v0_nue_mps: [0.0, -8.0, 0.0],
        chi2_gating: true,
        ..FilterParameters::default()
    };
    let mut eskf = Eskf::start(&params);
    for k in 0..200 {
        let m = measurements(k);
        let reals: [(&str, &[f64]); 4] = [
            ("accel_body_meas", &m.imu.accel_body_mps2),
            ("gyro_body_meas", &m.imu.gyro_body_radps),
            ("altimeter_range", &[m.altimeter_range_m]),
            ("velocimeter_los_velocity", &m.velocimeter_los_velocity_mps),
        ];
        for (name, values) in reals {
            assert_eq!(fmu.set_float64(&[vr(name)], values), fmi3OK, "{name}");
        }
        let names = [
            "altimeter_valid",
            "velocimeter_valid_1",
            "velocimeter_valid_2",
            "velocimeter_valid_3",
        ];
        let flags = [
            m.altimeter_valid,
            m.velocimeter_valid[0],
            m.velocimeter_valid[1],
            m.velocimeter_valid[2],
        ];
        assert_eq!(fmu.set_booleans(&names.map(vr), &flags), fmi3OK);
        let (status, y) = fmu.get_float64(
            &[
                vr("r_nue"),
                vr("v_nue"),
                vr("q_body_to_nue"),
                vr("covariance_diag"),
            ],
            25,
        );
        assert_eq!(status, fmi3OK, "{:?}", fmu.messages());
        let mut want = eskf.r_nue_m.to_vec();
        want.extend(eskf.v_nue_mps);
        want.extend(eskf.q_body_to_nue);
        want.extend(&eskf.covariance_diagonal()[..NAVIGATION]);
        assert_eq!(y, want, "step {k}");
        assert_eq!(
            fmu.do_step(k as f64 * 0.01, 0.01).status,
            fmi3OK,
            "{:?}",
            fmu.messages()
        );
        let innovations = step(&mut eskf, &params, &m, 0.01);
        let (status, dof) = fmu.get_int32(&[
            vr("altimeter_dof"),
            vr("velocimeter_dof"),
            vr("measurements_rejected"),
        ]);
        assert_eq!(status, fmi3OK);
        assert_eq!(
            dof,
            [
                innovations.altimeter_dof,
                innovations.velocimeter_dof,
                innovations.rejected
            ]
        );
        let (_, nis) = fmu.get_float64(&[vr("nis_altimeter"), vr("nis_velocimeter")], 2);
        assert_eq!(
            nis,
            [innovations.nis_altimeter, innovations.nis_velocimeter]
        );
    }
}
