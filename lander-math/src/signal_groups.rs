//! The signal groups the lander FMUs share, by the names their terminals give them: one
//! place for the member names, so that a tool matching terminals by name connects any two
//! of our FMUs (and a foreign model that uses the same names).

/// What a vehicle's navigation says: position, velocity, attitude, rate, mass.
pub const NAVIGATION_KIND: &str = "_lander_fmi_Navigation";
pub const NAVIGATION: [&str; 5] = ["r_nue", "v_nue", "q_body_to_nue", "omega_body", "mass"];

/// What the controller commands: main-engine thrust, control torque, RCS duty cycles.
pub const COMMANDS_KIND: &str = "_lander_fmi_Commands";
pub const COMMANDS: [&str; 3] = ["thrust_cmd", "torque_cmd_body", "rcs_duty"];

/// What the sensors see of the true motion: the navigation kinematics and the specific force.
pub const KINEMATICS_KIND: &str = "_lander_fmi_Kinematics";
pub const KINEMATICS: [&str; 5] = [
    "r_nue",
    "v_nue",
    "q_body_to_nue",
    "omega_body",
    "specific_force_body",
];

/// What the sensors measure, as the filter takes it.
pub const MEASUREMENTS_KIND: &str = "_lander_fmi_Measurements";
pub const MEASUREMENTS: [&str; 8] = [
    "accel_body_meas",
    "gyro_body_meas",
    "altimeter_range",
    "altimeter_valid",
    "velocimeter_los_velocity",
    "velocimeter_valid_1",
    "velocimeter_valid_2",
    "velocimeter_valid_3",
];
