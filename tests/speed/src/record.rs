//! The paper scenario flown once in the harness, kept as the input sequences that the
//! single-FMU measurements replay: each FMU then sees what it sees in the closed loop, every
//! phase of the flight included (hover, the guidance re-solves of the descent, the final
//! hover), and a plant written by someone else can be fed exactly the same commands.
use anyhow::{ensure, Context, Result};
use cosim::master::{RunEnd, Simulation, Trajectory};
use cosim::system::{ParamValue, SystemDescription};
use std::path::Path;

/// LanderPlant's outputs = LanderGnc's inputs (docs/interface.md), in this order.
pub const NAVIGATION: [&str; 14] = [
    "r_nue[1]",
    "r_nue[2]",
    "r_nue[3]",
    "v_nue[1]",
    "v_nue[2]",
    "v_nue[3]",
    "q_body_to_nue[1]",
    "q_body_to_nue[2]",
    "q_body_to_nue[3]",
    "q_body_to_nue[4]",
    "omega_body[1]",
    "omega_body[2]",
    "omega_body[3]",
    "mass",
];

/// LanderGnc's outputs = LanderPlant's inputs, in this order.
pub const COMMANDS: [&str; 4] = [
    "thrust_cmd",
    "torque_cmd_body[1]",
    "torque_cmd_body[2]",
    "torque_cmd_body[3]",
];

/// The scenario's instance names (harness/scenarios/paper.toml).
pub const GNC: &str = "gnc";
pub const PLANT: &str = "plant";

/// What each FMU exchanged at every communication point of one paper flight.
#[derive(Debug, Clone)]
pub struct PaperRecord {
    pub system: SystemDescription,
    /// `t_k` of every communication point, the stop time last.
    pub times: Vec<f64>,
    /// The plant's outputs at `t_k` (after its step to `t_k`).
    pub navigation: Vec<[f64; 14]>,
    /// The controller's commands at `t_k`, which drive the plant from `t_k` to `t_{k+1}`.
    pub commands: Vec<[f64; 4]>,
}

impl PaperRecord {
    /// Flies the built-in paper scenario with the FMUs of `fmu_dir`, ending at `stop_time_s`
    /// when given (a shorter flight for quick runs).
    pub fn fly(fmu_dir: &Path, stop_time_s: Option<f64>) -> Result<Self> {
        let mut system = paper_system(stop_time_s)?;
        let columns: Vec<String> = NAVIGATION
            .iter()
            .map(|name| format!("{PLANT}.{name}"))
            .chain(COMMANDS.iter().map(|name| format!("{GNC}.{name}")))
            .collect();
        system.record = Some(columns.clone());
        let mut simulation = Simulation::new(system.clone(), fmu_dir)?;
        let mut trajectory = Trajectory {
            names: simulation.column_names().to_vec(),
            ..Default::default()
        };
        let end = simulation.run(&mut trajectory)?;
        ensure!(
            end == RunEnd::Completed,
            "the paper flight ended early ({end:?}): nothing to replay"
        );
        ensure!(
            trajectory.names == columns,
            "the harness recorded {:?}, not the columns asked for",
            trajectory.names
        );
        let navigation = (0..trajectory.len())
            .map(|k| trajectory.row(k)[..14].try_into().expect("14 columns"))
            .collect();
        let commands = (0..trajectory.len())
            .map(|k| trajectory.row(k)[14..].try_into().expect("4 columns"))
            .collect();
        Ok(Self {
            system,
            times: trajectory.times,
            navigation,
            commands,
        })
    }

    /// Communication steps of the flight (one fewer than recorded points).
    pub fn steps(&self) -> usize {
        self.times.len() - 1
    }

    pub fn step_size_s(&self) -> f64 {
        self.system.step_size
    }

    /// The scenario's parameters of one instance.
    pub fn parameters(&self, instance: &str) -> &[(String, ParamValue)] {
        self.system
            .instance(instance)
            .map_or(&[], |i| i.parameters.as_slice())
    }

    /// The navigation LanderGnc was given at step `k`.
    ///
    /// In the harness's Gauss-Seidel exchange every output is read after the step and the
    /// controller comes first: at `t_k` it reads the plant at `t_k`. The replay checks this bit
    /// for bit against the recorded commands.
    pub fn gnc_inputs(&self, k: usize) -> &[f64; 14] {
        &self.navigation[k]
    }
}

/// The built-in paper scenario, optionally ending earlier.
pub fn paper_system(stop_time_s: Option<f64>) -> Result<SystemDescription> {
    let mut system = lander::scenarios::load("paper").context("the built-in paper scenario")?;
    if let Some(stop) = stop_time_s {
        ensure!(
            stop > system.start_time && stop <= system.stop_time,
            "a shortened flight must end within ({}, {}] s, not at {stop} s",
            system.start_time,
            system.stop_time
        );
        system.stop_time = stop;
    }
    Ok(system)
}
