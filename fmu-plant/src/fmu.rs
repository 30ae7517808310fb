//! The FMI face of the plant: the variable table (each variable declared once) and the
//! [`Model`] implementation. Names follow `shared/INTERFACE.md` to the letter.
use crate::physics::frames::quaternion_to_scalar_first;
use crate::physics::parameters::{
    PlantParameters, MOON_RADIUS_M, MOON_ROTATION_RATE_RADPS, SITE_LATITUDE_RAD, SITE_LONGITUDE_RAD,
};
use crate::physics::plant::{Advance, Commands, Plant, PlantRun};
use fmi2_export::{
    Access, Causality, Dependencies, EnumerationDecl, Experiment, Initial, Log, Model, ModelError,
    StepEnd, Variability, Variable,
};
use serde::{Deserialize, Serialize};

/// Values the master reads, refreshed by `calculate_values`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
struct Outputs {
    r_nue: [f64; 3],
    v_nue: [f64; 3],
    q_body_to_nue: [f64; 4],
    omega_body: [f64; 3],
    mass: f64,
    altitude: f64,
    thrust_actual: f64,
    torque_actual_body: [f64; 3],
    engine_torque_body: [f64; 3],
    propellant_used: f64,
}

/// The LanderPlant FMU instance. Everything lives here: no global state.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct LanderPlant {
    parameters: PlantParameters,
    commands: Commands,
    /// Set by `exit_initialization` from the validated parameters.
    running: Option<(Plant, PlantRun)>,
    outputs: Outputs,
}

impl LanderPlant {
    fn refresh_outputs(&mut self) {
        let p = &self.parameters;
        let provisional;
        let (plant, run) = match &self.running {
            Some((plant, run)) => (plant, run),
            // Initialization mode: show the initial state the parameters give, when they
            // are valid; otherwise the raw parameter values (validation reports the error).
            None => match Plant::new(p) {
                Ok((plant, run, _)) => {
                    provisional = (plant, run);
                    (&provisional.0, &provisional.1)
                }
                Err(_) => {
                    self.outputs = Outputs {
                        r_nue: p.r0_nue_m.into(),
                        v_nue: p.v0_nue_mps.into(),
                        q_body_to_nue: p.q0_body_to_nue,
                        omega_body: p.omega0_body_radps.into(),
                        mass: p.m0_kg,
                        altitude: p.r0_nue_m.y,
                        ..Outputs::default()
                    };
                    return;
                }
            },
        };
        let x = &run.state;
        let (r_nue, v_nue) = plant.translation.to_nue(&x.translation);
        let delivered = plant.delivered(
            x,
            &self.commands,
            run.propellant_exhausted || run.touchdown.is_some(),
        );
        self.outputs = Outputs {
            r_nue: r_nue.into(),
            v_nue: v_nue.into(),
            q_body_to_nue: quaternion_to_scalar_first(&x.q_body_to_nue),
            omega_body: x.omega_body.into(),
            mass: x.mass_kg,
            altitude: plant.altitude(x),
            thrust_actual: delivered.thrust_n,
            torque_actual_body: delivered.rcs_torque_body_nm.into(),
            engine_torque_body: delivered.engine_torque_body_nm.into(),
            propellant_used: p.m0_kg - x.mass_kg,
        };
    }

    fn touchdown_field(&self, f: impl Fn(&crate::physics::plant::Touchdown) -> f64) -> f64 {
        self.running
            .as_ref()
            .and_then(|(_, run)| run.touchdown.as_ref())
            .map_or(0.0, f)
    }
}

/// Most RK4 sub-steps one `fmi2DoStep` may take (about a second of CPU). Without a bound, a
/// huge communication step never returns: 1e300 s in orbit about the spherical Moon, or 1 s
/// with `integration_step` = 1e-12 s, would hang the master's call for minutes or forever.
const MAX_SUB_STEPS_PER_STEP: f64 = 1e6;

impl Model for LanderPlant {
    const MODEL_IDENTIFIER: &'static str = "LanderPlant";
    const MODEL_NAME: &'static str = "LanderPlant";
    const DESCRIPTION: &'static str = "6-DOF lunar lander: rigid-body attitude, flat (paper eq. 2) or spherical rotating \
         (eq. 1) translation, throttleable engines and RCS with saturation, RK4, touchdown and propellant events";
    const DEFAULT_EXPERIMENT: Experiment = Experiment {
        start_time: 0.0,
        stop_time: 172.0,
        step_size: 0.01,
        tolerance: None,
    };

    fn variables() -> &'static [Variable<Self>] {
        VARIABLES
    }

    fn enumeration_types() -> &'static [EnumerationDecl] {
        &[EnumerationDecl {
            name: "TranslationModel",
            description: "Translational equations of motion",
            items: &[
                (
                    "flat",
                    1,
                    "Flat, non-rotating Moon, uniform gravity (paper eq. 2)",
                ),
                (
                    "spherical",
                    2,
                    "Spherical Moon with rotation and central gravity (paper eq. 1, corrected)",
                ),
            ],
        }]
    }

    fn output_dependencies(output: &str) -> Dependencies {
        // The navigation outputs are functions of the state alone, so a controller can close
        // its loop through them without an algebraic loop. The delivered actuator values
        // depend on the current command when no lag is configured.
        match output {
            "thrust_actual"
            | "engine_torque_body[1]"
            | "engine_torque_body[2]"
            | "engine_torque_body[3]" => Dependencies::Inputs(&["thrust_cmd"]),
            "torque_actual_body[1]" => Dependencies::Inputs(&["torque_cmd_body[1]"]),
            "torque_actual_body[2]" => Dependencies::Inputs(&["torque_cmd_body[2]"]),
            "torque_actual_body[3]" => Dependencies::Inputs(&["torque_cmd_body[3]"]),
            _ => Dependencies::NoInputs,
        }
    }

    fn calculate_values(&mut self, _log: &mut Log) {
        self.refresh_outputs();
    }

    fn exit_initialization(&mut self, _start_time: f64, log: &mut Log) -> Result<(), ModelError> {
        let (plant, run, warning) =
            Plant::new(&self.parameters).map_err(|e| ModelError::InvalidParameter {
                name: e.name,
                value: e.value,
                reason: e.reason,
            })?;
        if let Some(w) = warning {
            log.warning(w);
        }
        self.running = Some((plant, run));
        Ok(())
    }

    fn do_step(&mut self, t: f64, h: f64, log: &mut Log) -> Result<StepEnd, ModelError> {
        let Some((plant, run)) = self.running.as_mut() else {
            return Err(ModelError::Other(
                "do_step before exit_initialization".into(),
            ));
        };
        if run.touchdown.is_some() {
            return Ok(StepEnd::Stopped {
                time: t,
                terminated: true,
                reason: "the lander is on the ground".into(),
            });
        }
        let sub_steps = h / plant.integration_step_s;
        if sub_steps > MAX_SUB_STEPS_PER_STEP {
            return Err(ModelError::Other(format!(
                "communicationStepSize {h} s would take {sub_steps:e} RK4 sub-steps of \
                 integration_step = {} s; at most {MAX_SUB_STEPS_PER_STEP:e} per fmi2DoStep: \
                 use shorter communication steps",
                plant.integration_step_s
            )));
        }
        let before = *run;
        let advance = plant.advance(run, &self.commands, t, h);
        if !run.state.is_finite() {
            *run = before;
            return Err(ModelError::Other(format!(
                "the state became non-finite in the step from t = {t} s"
            )));
        }
        if run.propellant_exhausted && !before.propellant_exhausted {
            log.warning(format!(
                "propellant exhausted in the step from t = {t} s: mass = dry_mass = {} kg, engines cut",
                plant.dry_mass_kg
            ));
        }
        Ok(match advance {
            Advance::Reached => StepEnd::Complete,
            Advance::Touchdown(time) => {
                let td = run
                    .touchdown
                    .expect("a touchdown advance records the touchdown");
                StepEnd::Stopped {
                    time,
                    terminated: true,
                    reason: format!(
                        "touchdown at t = {time} s: v_nue = [{:.3}, {:.3}, {:.3}] m/s, tilt = {:.2} deg",
                        td.v_nue_mps.x,
                        td.v_nue_mps.y,
                        td.v_nue_mps.z,
                        td.tilt_rad.to_degrees()
                    ),
                }
            }
        })
    }
}

type V = Variable<LanderPlant>;
type Get = fn(&LanderPlant) -> f64;
type Set = fn(&mut LanderPlant, f64);

const fn input(
    name: &'static str,
    vr: u32,
    unit: &'static str,
    description: &'static str,
    get: Get,
    set: Set,
) -> V {
    Variable {
        name,
        value_reference: vr,
        causality: Causality::Input,
        variability: Variability::Continuous,
        initial: None,
        unit: Some(unit),
        description,
        access: Access::Real {
            start: Some(0.0),
            min: None,
            max: None,
            get,
            set: Some(set),
        },
    }
}

const fn output(
    name: &'static str,
    vr: u32,
    variability: Variability,
    unit: &'static str,
    description: &'static str,
    get: Get,
) -> V {
    Variable {
        name,
        value_reference: vr,
        causality: Causality::Output,
        variability,
        initial: Some(Initial::Calculated),
        unit: Some(unit),
        description,
        access: Access::Real {
            start: None,
            min: None,
            max: None,
            get,
            set: None,
        },
    }
}

const fn parameter(
    name: &'static str,
    vr: u32,
    unit: &'static str,
    start: f64,
    description: &'static str,
    get: Get,
    set: Set,
) -> V {
    Variable {
        name,
        value_reference: vr,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        initial: Some(Initial::Exact),
        unit: Some(unit),
        description,
        access: Access::Real {
            start: Some(start),
            min: None,
            max: None,
            get,
            set: Some(set),
        },
    }
}

const fn flag(
    name: &'static str,
    vr: u32,
    description: &'static str,
    get: fn(&LanderPlant) -> bool,
) -> V {
    Variable {
        name,
        value_reference: vr,
        causality: Causality::Output,
        variability: Variability::Discrete,
        initial: Some(Initial::Calculated),
        unit: None,
        description,
        access: Access::Boolean {
            start: None,
            get,
            set: None,
        },
    }
}

const CONTINUOUS: Variability = Variability::Continuous;
const DISCRETE: Variability = Variability::Discrete;

fn running_flag(m: &LanderPlant, f: impl Fn(&PlantRun) -> bool) -> bool {
    m.running.as_ref().is_some_and(|(_, run)| f(run))
}

/// The variable table, one row per variable as in the model description (kept on one line
/// each so that the table reads as a table).
#[rustfmt::skip]
static VARIABLES: &[V] = &[
    // Inputs (LanderGnc outputs).
    input("thrust_cmd", 1, "N", "Commanded total engine thrust along body +y; at or below engine_off_threshold the engines are off, otherwise saturated to engine_count x [engine_thrust_min, engine_thrust_max]", |m| m.commands.thrust_cmd_n, |m, v| m.commands.thrust_cmd_n = v),
    input("torque_cmd_body[1]", 2, "N.m", "Commanded RCS torque about body x (yaw), saturated to rcs_torque_limit", |m| m.commands.torque_cmd_body_nm.x, |m, v| m.commands.torque_cmd_body_nm.x = v),
    input("torque_cmd_body[2]", 3, "N.m", "Commanded RCS torque about body y (roll, the thrust axis), saturated to rcs_torque_limit", |m| m.commands.torque_cmd_body_nm.y, |m, v| m.commands.torque_cmd_body_nm.y = v),
    input("torque_cmd_body[3]", 4, "N.m", "Commanded RCS torque about body z (pitch), saturated to rcs_torque_limit", |m| m.commands.torque_cmd_body_nm.z, |m, v| m.commands.torque_cmd_body_nm.z = v),
    // Outputs (LanderGnc inputs).
    output("r_nue[1]", 10, CONTINUOUS, "m", "Position of the centre of mass, North (landing site at the origin)", |m| m.outputs.r_nue[0]),
    output("r_nue[2]", 11, CONTINUOUS, "m", "Position of the centre of mass, Up", |m| m.outputs.r_nue[1]),
    output("r_nue[3]", 12, CONTINUOUS, "m", "Position of the centre of mass, East", |m| m.outputs.r_nue[2]),
    output("v_nue[1]", 13, CONTINUOUS, "m/s", "Velocity relative to the Moon's surface, North", |m| m.outputs.v_nue[0]),
    output("v_nue[2]", 14, CONTINUOUS, "m/s", "Velocity relative to the Moon's surface, Up", |m| m.outputs.v_nue[1]),
    output("v_nue[3]", 15, CONTINUOUS, "m/s", "Velocity relative to the Moon's surface, East", |m| m.outputs.v_nue[2]),
    output("q_body_to_nue[1]", 16, CONTINUOUS, "1", "Attitude quaternion body to NUE (Hamilton), scalar part", |m| m.outputs.q_body_to_nue[0]),
    output("q_body_to_nue[2]", 17, CONTINUOUS, "1", "Attitude quaternion body to NUE, x (North) component of the vector part", |m| m.outputs.q_body_to_nue[1]),
    output("q_body_to_nue[3]", 18, CONTINUOUS, "1", "Attitude quaternion body to NUE, y (Up) component of the vector part", |m| m.outputs.q_body_to_nue[2]),
    output("q_body_to_nue[4]", 19, CONTINUOUS, "1", "Attitude quaternion body to NUE, z (East) component of the vector part", |m| m.outputs.q_body_to_nue[3]),
    output("omega_body[1]", 20, CONTINUOUS, "rad/s", "Body angular rate about x (yaw)", |m| m.outputs.omega_body[0]),
    output("omega_body[2]", 21, CONTINUOUS, "rad/s", "Body angular rate about y (roll, the thrust axis)", |m| m.outputs.omega_body[1]),
    output("omega_body[3]", 22, CONTINUOUS, "rad/s", "Body angular rate about z (pitch)", |m| m.outputs.omega_body[2]),
    output("mass", 23, CONTINUOUS, "kg", "Current total mass", |m| m.outputs.mass),
    // Extra outputs.
    output("altitude", 24, CONTINUOUS, "m", "Height above the surface: r_nue[2] for the flat Moon, radius minus moon_radius for the spherical one", |m| m.outputs.altitude),
    output("thrust_actual", 25, CONTINUOUS, "N", "Engine thrust delivered after saturation, lag and propellant cut-off", |m| m.outputs.thrust_actual),
    output("torque_actual_body[1]", 26, CONTINUOUS, "N.m", "RCS torque delivered about body x after saturation and lag", |m| m.outputs.torque_actual_body[0]),
    output("torque_actual_body[2]", 27, CONTINUOUS, "N.m", "RCS torque delivered about body y after saturation and lag", |m| m.outputs.torque_actual_body[1]),
    output("torque_actual_body[3]", 28, CONTINUOUS, "N.m", "RCS torque delivered about body z after saturation and lag", |m| m.outputs.torque_actual_body[2]),
    output("engine_torque_body[1]", 29, CONTINUOUS, "N.m", "Disturbance torque of the misaligned/offset thrust line about body x", |m| m.outputs.engine_torque_body[0]),
    output("engine_torque_body[2]", 30, CONTINUOUS, "N.m", "Disturbance torque of the misaligned/offset thrust line about body y", |m| m.outputs.engine_torque_body[1]),
    output("engine_torque_body[3]", 31, CONTINUOUS, "N.m", "Disturbance torque of the misaligned/offset thrust line about body z", |m| m.outputs.engine_torque_body[2]),
    output("propellant_used", 32, CONTINUOUS, "kg", "m0 minus the current mass", |m| m.outputs.propellant_used),
    flag("propellant_exhausted", 33, "True once the mass has reached dry_mass; the engines deliver no thrust from then on", |m| running_flag(m, |r| r.propellant_exhausted)),
    flag("touchdown", 34, "True once the altitude has reached 0; the simulation ends there (fmi2Terminated)", |m| running_flag(m, |r| r.touchdown.is_some())),
    output("touchdown_time", 35, DISCRETE, "s", "Time of touchdown (0 before touchdown)", |m| m.touchdown_field(|t| t.time_s)),
    output("touchdown_v_nue[1]", 36, DISCRETE, "m/s", "Velocity at touchdown, North (0 before touchdown)", |m| m.touchdown_field(|t| t.v_nue_mps.x)),
    output("touchdown_v_nue[2]", 37, DISCRETE, "m/s", "Velocity at touchdown, Up (0 before touchdown)", |m| m.touchdown_field(|t| t.v_nue_mps.y)),
    output("touchdown_v_nue[3]", 38, DISCRETE, "m/s", "Velocity at touchdown, East (0 before touchdown)", |m| m.touchdown_field(|t| t.v_nue_mps.z)),
    output("touchdown_q_body_to_nue[1]", 39, DISCRETE, "1", "Attitude at touchdown, scalar part (0 before touchdown)", |m| m.touchdown_field(|t| t.q_body_to_nue.w)),
    output("touchdown_q_body_to_nue[2]", 40, DISCRETE, "1", "Attitude at touchdown, vector part x (0 before touchdown)", |m| m.touchdown_field(|t| t.q_body_to_nue.i)),
    output("touchdown_q_body_to_nue[3]", 41, DISCRETE, "1", "Attitude at touchdown, vector part y (0 before touchdown)", |m| m.touchdown_field(|t| t.q_body_to_nue.j)),
    output("touchdown_q_body_to_nue[4]", 42, DISCRETE, "1", "Attitude at touchdown, vector part z (0 before touchdown)", |m| m.touchdown_field(|t| t.q_body_to_nue.k)),
    output("touchdown_omega_body[1]", 43, DISCRETE, "rad/s", "Body rate at touchdown about x (0 before touchdown)", |m| m.touchdown_field(|t| t.omega_body_radps.x)),
    output("touchdown_omega_body[2]", 44, DISCRETE, "rad/s", "Body rate at touchdown about y (0 before touchdown)", |m| m.touchdown_field(|t| t.omega_body_radps.y)),
    output("touchdown_omega_body[3]", 45, DISCRETE, "rad/s", "Body rate at touchdown about z (0 before touchdown)", |m| m.touchdown_field(|t| t.omega_body_radps.z)),
    output("touchdown_tilt", 46, DISCRETE, "rad", "Angle between the thrust axis and the local vertical at touchdown (0 before touchdown)", |m| m.touchdown_field(|t| t.tilt_rad)),
    // Initial state.
    parameter("r0_nue[1]", 100, "m", 0.0, "Initial position, North", |m| m.parameters.r0_nue_m.x, |m, v| m.parameters.r0_nue_m.x = v),
    parameter("r0_nue[2]", 101, "m", 800.0, "Initial position, Up (must be above the surface)", |m| m.parameters.r0_nue_m.y, |m, v| m.parameters.r0_nue_m.y = v),
    parameter("r0_nue[3]", 102, "m", 0.0, "Initial position, East", |m| m.parameters.r0_nue_m.z, |m, v| m.parameters.r0_nue_m.z = v),
    parameter("v0_nue[1]", 103, "m/s", 0.0, "Initial velocity, North", |m| m.parameters.v0_nue_mps.x, |m, v| m.parameters.v0_nue_mps.x = v),
    parameter("v0_nue[2]", 104, "m/s", 0.0, "Initial velocity, Up", |m| m.parameters.v0_nue_mps.y, |m, v| m.parameters.v0_nue_mps.y = v),
    parameter("v0_nue[3]", 105, "m/s", 0.0, "Initial velocity, East", |m| m.parameters.v0_nue_mps.z, |m, v| m.parameters.v0_nue_mps.z = v),
    parameter("q0_body_to_nue[1]", 106, "1", 1.0, "Initial attitude body to NUE, scalar part (normalised if |q0| is within 1e-3 of 1, refused otherwise)", |m| m.parameters.q0_body_to_nue[0], |m, v| m.parameters.q0_body_to_nue[0] = v),
    parameter("q0_body_to_nue[2]", 107, "1", 0.0, "Initial attitude body to NUE, vector part x", |m| m.parameters.q0_body_to_nue[1], |m, v| m.parameters.q0_body_to_nue[1] = v),
    parameter("q0_body_to_nue[3]", 108, "1", 0.0, "Initial attitude body to NUE, vector part y", |m| m.parameters.q0_body_to_nue[2], |m, v| m.parameters.q0_body_to_nue[2] = v),
    parameter("q0_body_to_nue[4]", 109, "1", 0.0, "Initial attitude body to NUE, vector part z", |m| m.parameters.q0_body_to_nue[3], |m, v| m.parameters.q0_body_to_nue[3] = v),
    parameter("omega0_body[1]", 110, "rad/s", 0.0, "Initial body rate about x", |m| m.parameters.omega0_body_radps.x, |m, v| m.parameters.omega0_body_radps.x = v),
    parameter("omega0_body[2]", 111, "rad/s", 0.0, "Initial body rate about y", |m| m.parameters.omega0_body_radps.y, |m, v| m.parameters.omega0_body_radps.y = v),
    parameter("omega0_body[3]", 112, "rad/s", 0.0, "Initial body rate about z", |m| m.parameters.omega0_body_radps.z, |m, v| m.parameters.omega0_body_radps.z = v),
    parameter("m0", 113, "kg", 900.0, "Initial total mass", |m| m.parameters.m0_kg, |m, v| m.parameters.m0_kg = v),
    // Vehicle and environment.
    parameter("g", 120, "m/s2", 1.62, "Surface gravity of the Moon (spherical model: mu = g moon_radius^2)", |m| m.parameters.gravity_mps2, |m, v| m.parameters.gravity_mps2 = v),
    parameter("isp", 121, "s", 300.0, "Specific impulse of the main engines", |m| m.parameters.isp_s, |m, v| m.parameters.isp_s = v),
    parameter("g0", 122, "m/s2", 9.81, "Standard gravity in the rocket equation m' = -T / (isp g0)", |m| m.parameters.g0_mps2, |m, v| m.parameters.g0_mps2 = v),
    parameter("dry_mass", 123, "kg", 600.0, "Mass without propellant; at it the engines cut out", |m| m.parameters.dry_mass_kg, |m, v| m.parameters.dry_mass_kg = v),
    parameter("inertia_body[1]", 124, "kg.m2", 400.0, "Principal moment of inertia about body x (Ixx)", |m| m.parameters.inertia_body_kgm2.x, |m, v| m.parameters.inertia_body_kgm2.x = v),
    parameter("inertia_body[2]", 125, "kg.m2", 300.0, "Principal moment of inertia about body y (Iyy)", |m| m.parameters.inertia_body_kgm2.y, |m, v| m.parameters.inertia_body_kgm2.y = v),
    parameter("inertia_body[3]", 126, "kg.m2", 450.0, "Principal moment of inertia about body z (Izz)", |m| m.parameters.inertia_body_kgm2.z, |m, v| m.parameters.inertia_body_kgm2.z = v),
    Variable {
        name: "engine_count",
        value_reference: 130,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        initial: Some(Initial::Exact),
        unit: None,
        description: "Number of throttleable main engines, fired together",
        access: Access::Integer {
            start: Some(2),
            min: Some(1),
            max: None,
            get: |m| i32::try_from(m.parameters.engines.count).unwrap_or(i32::MAX),
            // A negative count becomes 0 and is refused by the validation, by name.
            set: Some(|m, v| m.parameters.engines.count = u32::try_from(v).unwrap_or(0)),
        },
    },
    parameter("engine_thrust_min", 131, "N", 360.0, "Minimum thrust of one engine when on", |m| m.parameters.engines.min_thrust_per_engine_n, |m, v| m.parameters.engines.min_thrust_per_engine_n = v),
    parameter("engine_thrust_max", 132, "N", 800.0, "Maximum thrust of one engine", |m| m.parameters.engines.max_thrust_per_engine_n, |m, v| m.parameters.engines.max_thrust_per_engine_n = v),
    parameter("engine_off_threshold", 133, "N", 1.0, "A thrust command at or below this value switches the engines off", |m| m.parameters.engines.off_threshold_n, |m, v| m.parameters.engines.off_threshold_n = v),
    parameter("engine_time_constant", 134, "s", 0.0, "First-order lag of the delivered thrust (0 = none)", |m| m.parameters.engines.time_constant_s, |m, v| m.parameters.engines.time_constant_s = v),
    parameter("thrust_misalignment", 135, "rad", 0.0, "Angle between the thrust direction and body +y", |m| m.parameters.thrust_line.misalignment_rad, |m, v| m.parameters.thrust_line.misalignment_rad = v),
    parameter("thrust_misalignment_azimuth", 136, "rad", 0.0, "Direction of the misalignment in the body x-z plane, from +x towards +z", |m| m.parameters.thrust_line.misalignment_azimuth_rad, |m, v| m.parameters.thrust_line.misalignment_azimuth_rad = v),
    parameter("thrust_point_body[1]", 137, "m", 0.0, "Thrust application point relative to the centre of mass, body x (lateral offset)", |m| m.parameters.thrust_line.point_body_m.x, |m, v| m.parameters.thrust_line.point_body_m.x = v),
    parameter("thrust_point_body[2]", 138, "m", -1.0, "Thrust application point relative to the centre of mass, body y (nozzle below the centre of mass)", |m| m.parameters.thrust_line.point_body_m.y, |m, v| m.parameters.thrust_line.point_body_m.y = v),
    parameter("thrust_point_body[3]", 139, "m", 0.0, "Thrust application point relative to the centre of mass, body z (lateral offset)", |m| m.parameters.thrust_line.point_body_m.z, |m, v| m.parameters.thrust_line.point_body_m.z = v),
    parameter("rcs_thruster_force", 140, "N", 58.0, "Force of one RCS thruster", |m| m.parameters.rcs.thruster_force_n, |m, v| m.parameters.rcs.thruster_force_n = v),
    parameter("rcs_moment_arm", 141, "m", 1.0, "Moment arm of an RCS couple", |m| m.parameters.rcs.moment_arm_m, |m, v| m.parameters.rcs.moment_arm_m = v),
    parameter("rcs_time_constant", 142, "s", 0.0, "First-order lag of the delivered RCS torque (0 = none)", |m| m.parameters.rcs.time_constant_s, |m, v| m.parameters.rcs.time_constant_s = v),
    Variable {
        name: "rcs_torque_limit",
        value_reference: 143,
        causality: Causality::CalculatedParameter,
        variability: Variability::Fixed,
        initial: Some(Initial::Calculated),
        unit: Some("N.m"),
        description: "Per-axis RCS torque limit: one couple, 2 x rcs_thruster_force x rcs_moment_arm",
        access: Access::Real {
            start: None,
            min: None,
            max: None,
            get: |m| m.parameters.rcs.torque_limit_nm(),
            set: None,
        },
    },
    // Translation model.
    Variable {
        name: "translation_model",
        value_reference: 150,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        initial: Some(Initial::Exact),
        unit: None,
        description: "Translational equations of motion: 1 = flat Moon (paper eq. 2), 2 = spherical rotating Moon (eq. 1)",
        access: Access::Enumeration {
            type_name: "TranslationModel",
            start: Some(1),
            get: |m| m.parameters.translation_model,
            set: Some(|m, v| m.parameters.translation_model = v),
        },
    },
    parameter("moon_radius", 151, "m", MOON_RADIUS_M, "Mean radius of the Moon (spherical model)", |m| m.parameters.moon_radius_m, |m, v| m.parameters.moon_radius_m = v),
    parameter("moon_rotation_rate", 152, "rad/s", MOON_ROTATION_RATE_RADPS, "Sidereal rotation rate of the Moon (spherical model)", |m| m.parameters.moon_rotation_rate_radps, |m, v| m.parameters.moon_rotation_rate_radps = v),
    parameter("site_latitude", 153, "rad", SITE_LATITUDE_RAD, "Latitude of the landing site (spherical model; default Chandrayaan-3, 69.373 deg S)", |m| m.parameters.site_latitude_rad, |m, v| m.parameters.site_latitude_rad = v),
    parameter("site_longitude", 154, "rad", SITE_LONGITUDE_RAD, "Longitude of the landing site (spherical model; default Chandrayaan-3, 32.319 deg E)", |m| m.parameters.site_longitude_rad, |m, v| m.parameters.site_longitude_rad = v),
    parameter("integration_step", 160, "s", 0.01, "Maximum RK4 sub-step; a communication step is split into sub-steps of this size, the last one shortened", |m| m.parameters.integration_step_s, |m, v| m.parameters.integration_step_s = v),
];

#[cfg(test)]
mod tests {
    use super::*;
    use fmi2_export::Access;

    #[test]
    fn table_starts_equal_the_physics_defaults() {
        // The start values in the table and PlantParameters::default() are written twice
        // (the table needs constants); they must agree so that a fresh instance and the
        // model description describe the same plant.
        let fresh = LanderPlant::default();
        for v in LanderPlant::variables() {
            match &v.access {
                Access::Real {
                    start: Some(s),
                    get,
                    ..
                } => {
                    let got = get(&fresh);
                    assert!(
                        (got - s).abs() <= 1e-7 * s.abs(),
                        "{}: start {s}, default {got}",
                        v.name
                    );
                }
                Access::Integer {
                    start: Some(s),
                    get,
                    ..
                }
                | Access::Enumeration {
                    start: Some(s),
                    get,
                    ..
                } => {
                    assert_eq!(get(&fresh), *s, "{}", v.name)
                }
                _ => {}
            }
        }
    }

    #[test]
    fn the_export_layer_accepts_the_table() {
        assert_eq!(fmi2_export::check_table::<LanderPlant>(), Ok(()));
    }

    #[test]
    fn names_and_value_references_are_unique() {
        let vars = LanderPlant::variables();
        let mut names: Vec<_> = vars.iter().map(|v| v.name).collect();
        let mut refs: Vec<_> = vars.iter().map(|v| v.value_reference).collect();
        names.sort_unstable();
        refs.sort_unstable();
        names.dedup();
        refs.dedup();
        assert_eq!(names.len(), vars.len());
        assert_eq!(refs.len(), vars.len());
    }

    #[test]
    fn the_interface_contract_names_are_all_present_with_their_causality() {
        let vars = LanderPlant::variables();
        let find = |n: &str| {
            vars.iter()
                .find(|v| v.name == n)
                .unwrap_or_else(|| panic!("{n} missing"))
        };
        let mut contract = vec![
            ("thrust_cmd".to_string(), Causality::Input),
            ("mass".into(), Causality::Output),
            ("m0".into(), Causality::Parameter),
        ];
        for (base, n, c) in [
            ("torque_cmd_body", 3, Causality::Input),
            ("r_nue", 3, Causality::Output),
            ("v_nue", 3, Causality::Output),
            ("q_body_to_nue", 4, Causality::Output),
            ("omega_body", 3, Causality::Output),
            ("r0_nue", 3, Causality::Parameter),
            ("v0_nue", 3, Causality::Parameter),
            ("q0_body_to_nue", 4, Causality::Parameter),
            ("omega0_body", 3, Causality::Parameter),
        ] {
            contract.extend((1..=n).map(|k| (format!("{base}[{k}]"), c)));
        }
        for (name, causality) in contract {
            assert_eq!(find(&name).causality, causality, "{name}");
        }
    }

    #[test]
    fn reals_carry_a_unit() {
        for v in LanderPlant::variables() {
            if matches!(v.access, Access::Real { .. }) {
                assert!(v.unit.is_some(), "{} has no unit", v.name);
            }
        }
    }

    #[test]
    fn scalar_first_quaternion_output_matches_the_parameter_order() {
        // GIVEN q0 = a 90 deg rotation about body z, scalar first
        let mut m = LanderPlant::default();
        let h = std::f64::consts::FRAC_1_SQRT_2;
        m.parameters.q0_body_to_nue = [h, 0.0, 0.0, h];
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        // WHEN the outputs are computed
        m.calculate_values(&mut log);
        // THEN q_body_to_nue[1] is the scalar part, [4] the z part
        assert!((m.outputs.q_body_to_nue[0] - h).abs() < 1e-15);
        assert!((m.outputs.q_body_to_nue[3] - h).abs() < 1e-15);
        assert_eq!(m.outputs.q_body_to_nue[1], 0.0);
    }

    #[test]
    fn a_bad_parameter_is_refused_by_name_at_exit_initialization() {
        let mut m = LanderPlant::default();
        m.parameters.dry_mass_kg = 1000.0;
        let err = m.exit_initialization(0.0, &mut Log::default()).unwrap_err();
        assert!(
            matches!(err, ModelError::InvalidParameter { name: "m0", .. }),
            "{err:?}"
        );
    }

    #[test]
    fn a_step_needing_more_sub_steps_than_the_bound_is_refused_before_integrating() {
        // GIVEN a lander climbing so fast that it stays aloft for 1.2e6 s
        let mut m = LanderPlant::default();
        m.parameters.v0_nue_mps.y = 1e6;
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        let before = m.running.as_ref().unwrap().1.state;
        // WHEN a master asks for one step of 1e300 s (or just over the bound)
        for h in [1e300, (MAX_SUB_STEPS_PER_STEP + 1.0) * 0.01] {
            let err = m.do_step(0.0, h, &mut log).unwrap_err();
            // THEN it is refused at once, naming the step size, and the state is untouched
            assert!(err.to_string().contains("communicationStepSize"), "{err}");
            assert_eq!(m.running.as_ref().unwrap().1.state, before);
        }
        // AND a step at the bound is still taken
        assert!(m
            .do_step(0.0, MAX_SUB_STEPS_PER_STEP * 0.01 * 1e-3, &mut log)
            .is_ok());
    }

    #[test]
    fn touchdown_stops_the_step_at_the_crossing_and_terminates() {
        // GIVEN a free fall from 5 m (engines off)
        let mut m = LanderPlant::default();
        m.parameters.r0_nue_m.y = 5.0;
        let mut log = Log::default();
        m.exit_initialization(0.0, &mut log).unwrap();
        // WHEN stepping in 0.1 s steps
        let mut t = 0.0;
        let end = loop {
            match m.do_step(t, 0.1, &mut log).unwrap() {
                StepEnd::Complete => t += 0.1,
                stopped => break stopped,
            }
            assert!(t < 10.0, "no touchdown");
        };
        // THEN it stops at sqrt(2 h / g) with the free-fall velocity, and stays stopped
        let t_exact = (2.0 * 5.0 / 1.62f64).sqrt();
        let StepEnd::Stopped {
            time, terminated, ..
        } = end
        else {
            unreachable!()
        };
        assert!(terminated);
        assert!((time - t_exact).abs() < 1e-9, "{time} vs {t_exact}");
        m.calculate_values(&mut log);
        let v_td = m.touchdown_field(|td| td.v_nue_mps.y);
        assert!((v_td + 1.62 * t_exact).abs() < 1e-8, "{v_td}");
        assert!(m.outputs.altitude.abs() < 1e-9);
        assert!(matches!(
            m.do_step(time, 0.1, &mut log),
            Ok(StepEnd::Stopped {
                terminated: true,
                ..
            })
        ));
    }
}
