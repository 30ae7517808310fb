//! The declarations: each variable declared once, one line each.
use crate::oscillator::{Oscillator, MASS_KG};
use fmi_model::{decl, Declaration};

#[rustfmt::skip]
pub static DECLARATIONS: [Declaration<Oscillator>; 17] = [
    // Real
    decl!(0, parameter x0: x0_m, "m", "Initial position"),
    decl!(1, tunable k: k_n_per_m, "N/m", "Spring stiffness", min = 0.0),
    decl!(2, tunable c: c_ns_per_m, "N.s/m", "Viscous damping coefficient", min = 0.0),
    decl!(3, tunable threshold: threshold_m, "m", "Position whose crossing stops the simulation when stop_at_threshold is set"),
    decl!(4, input u: u_n, "N", "External force, held over each communication step"),
    decl!(5, output x: x_m, "m", "Position"),
    decl!(6, output v: v_m_per_s, "m/s", "Velocity"),
    decl!(7, calculated_tunable omega_n: omega_n_rad_per_s, "rad/s", "Undamped natural angular frequency sqrt(k / mass)"),
    decl!(8, constant mass: get |_, _| MASS_KG, "kg", "Mass"),
    // Model Exchange: the derivatives of the states x and v, and the event indicator
    decl!(9, derivative der_x: get |m, _| m.v_m_per_s, "m/s", "Time derivative of x"),
    decl!(10, derivative der_v: get |m, _| m.acceleration(), "m/s2", "Time derivative of v"),
    decl!(11, local threshold_offset: get |m, _| m.threshold_offset(), "m", "Event indicator: x - threshold while stop_at_threshold is set, 1 otherwise"),
    // Integer and Enumeration (value references unique across types, as FMI 3.0 requires)
    decl!(12, discrete_output step_count: step_count as i32, "Number of completed or stopped communication steps"),
    decl!(13, parameter substeps: substeps as i32, "RK4 sub-steps per communication step", int_min = 1, int_max = 1000),
    decl!(14, parameter crossing_direction: crossing as enum crate::Crossing, "Which threshold crossings stop the simulation"),
    // Boolean
    decl!(15, parameter stop_at_threshold: stop_at_threshold as bool, "Stop (terminated) when x crosses threshold"),
    // String
    decl!(16, parameter label: label as String, "Name used in log messages"),
];
