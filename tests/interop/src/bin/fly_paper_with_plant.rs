//! Flies the harness's paper scenario with another plant FMU in place of LanderPlant and
//! writes the trajectory as CSV (the harness's format).
//!
//! A process of its own, so that a plant whose binary needs its environment prepared gets
//! it from the command line: pythonfmu's binary calls into a Python interpreter it does not
//! link, so the process must be started with libpython preloaded (`LD_PRELOAD`) and
//! `PYTHONHOME` naming that Python's installation (tests/interop/tests/python_plant.rs).
//!
//! Usage: fly_paper_with_plant PLANT.fmu OUT.csv
#![deny(unsafe_code)]

use anyhow::{bail, Context, Result};
use cosim::master::{Simulation, Trajectory};
use std::path::PathBuf;

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [plant_fmu, out_csv] = args.as_slice() else {
        bail!("usage: fly_paper_with_plant PLANT.fmu OUT.csv");
    };
    let mut system = lander::scenarios::load("paper")?;
    system
        .instance_mut("plant")
        .context("the paper scenario has no instance 'plant'")?
        .fmu = PathBuf::from(plant_fmu).canonicalize()?;
    let mut simulation = Simulation::new(system, &interop_tests::fmu_dir())?;
    let mut trajectory = Trajectory {
        names: simulation.column_names().to_vec(),
        ..Default::default()
    };
    let end = simulation.run(&mut trajectory)?;
    cosim::results::write_csv(out_csv.as_ref(), &trajectory)?;
    println!("fly_paper_with_plant: {} rows, {end:?}", trajectory.len());
    Ok(())
}
