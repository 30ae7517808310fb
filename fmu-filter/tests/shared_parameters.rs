//! The parameters LanderFilter shares with LanderSensors (the IMU noises and calibration
//! 1-sigmas, the beams, the terrain) have the same names, units and defaults, so that both left at their defaults
//! describe the same sensors. Only the generated descriptions are compared: no C symbol of
//! either FMU is linked.
use fmu_filter::LanderFilter;
use fmu_sensors::LanderSensors;
use model_description::StartValue;

#[test]
fn the_parameters_shared_with_the_sensors_have_their_units_and_defaults() {
    let sensors = fmi2_export::model_description::<LanderSensors>();
    let filter = fmi2_export::model_description::<LanderFilter>();
    let mut shared = 0;
    for f in &filter.model_variables.variables {
        let Some(s) = sensors
            .model_variables
            .variables
            .iter()
            .find(|s| s.name == f.name)
        else {
            continue;
        };
        if f.causality != Some(model_description::Causality::Parameter) {
            continue;
        }
        match (f.start(), s.start()) {
            (Some(StartValue::Real(a)), Some(StartValue::Real(b))) => {
                assert!((a - b).abs() <= 1e-15 * b.abs(), "{}: {a} vs {b}", f.name)
            }
            (a, b) => assert_eq!(a, b, "{}", f.name),
        }
        let unit =
            |v: &model_description::ScalarVariable| v.real.as_ref().and_then(|r| r.unit.clone());
        assert_eq!(unit(f), unit(s), "{}", f.name);
        shared += 1;
    }
    // Sample period, 6 IMU noises, 4 calibration 1-sigmas, altimeter beam (3) and noises
    // (2), three beams (9) and their noise, terrain height and normal (3).
    assert_eq!(shared, 30);
}
