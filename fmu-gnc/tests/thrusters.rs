//! The thruster chain of LanderGnc: allocation plus PWPF against the torque it is asked for.
use fmu_gnc::actuation::{duties, PwpfBank};
use fmu_gnc::params::GncParameters;
use nalgebra::Vector3;

/// The mean torque the eight thrusters deliver over the last half of `seconds` of a constant
/// command, from the duties the chain outputs each period.
fn mean_torque(torque_cmd: Vector3<f64>, seconds: f64) -> Vector3<f64> {
    let p = GncParameters::default();
    let allocator = p.allocator();
    let settings = p.pwpf_settings();
    let period = p.rcs_duty_period_s;
    let mut bank = PwpfBank::default();
    let steps = (seconds / period).round() as usize;
    let mut on_time_s = [0.0; 8];
    for k in 0..steps {
        let (duty, next) = duties(&allocator, &settings, &bank, &torque_cmd, true, period);
        bank = next;
        if k >= steps / 2 {
            for (acc, d) in on_time_s.iter_mut().zip(duty) {
                *acc += d * period;
            }
        }
    }
    let window_s = period * (steps - steps / 2) as f64;
    allocator.torque_body_nm(&on_time_s.map(|s| s / window_s))
}

#[test]
fn allocation_plus_pwpf_tracks_a_constant_torque_on_average_within_2_percent() {
    // Torques from 12 to 116 N m (10 % to 100 % of a couple), about one axis and mixed.
    for torque in [
        Vector3::new(0.0, 0.0, 12.0),
        Vector3::new(0.0, -30.0, 0.0),
        Vector3::new(58.0, 0.0, 0.0),
        Vector3::new(0.0, 0.0, -100.0),
        Vector3::new(20.0, -40.0, 70.0),
        Vector3::new(-50.0, 50.0, -25.0),
        Vector3::new(0.0, 116.0, 0.0),
    ] {
        let mean = mean_torque(torque, 60.0);
        let error = (mean - torque).norm() / torque.norm();
        assert!(
            error < 0.02,
            "{torque}: mean {mean}, error {:.2} %",
            100.0 * error
        );
    }
}

#[test]
fn a_torque_inside_the_dead_zone_fires_nothing() {
    // 1 N m asks for under 1 % of a couple: the modulator's dead zone.
    assert_eq!(
        mean_torque(Vector3::new(0.0, 1.0, 0.0), 10.0),
        Vector3::zeros()
    );
}

/// The start value of a variable in a checked-in model description (each FMU's own tests
/// keep its file in step with its code).
fn start_value(xml: &str, name: &str) -> f64 {
    let at = xml
        .find(&format!("name=\"{name}\""))
        .unwrap_or_else(|| panic!("{name} is not declared"));
    let rest = &xml[at..];
    let start = rest.find("start=\"").expect("a start value") + 7;
    let end = start + rest[start..].find('"').unwrap();
    rest[start..end].parse().unwrap()
}

#[test]
fn the_default_geometry_is_the_plants() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let gnc = std::fs::read_to_string(dir.join("modelDescription.xml")).unwrap();
    let plant = std::fs::read_to_string(dir.join("../fmu-plant/modelDescription.xml")).unwrap();
    let mut names = vec!["rcs_thruster_force".to_string()];
    for base in ["rcs_position_body", "rcs_direction_body"] {
        names.extend((1..=24).map(|i| format!("{base}[{i}]")));
    }
    for name in names {
        assert_eq!(
            start_value(&gnc, &name),
            start_value(&plant, &name),
            "{name}"
        );
    }
}
