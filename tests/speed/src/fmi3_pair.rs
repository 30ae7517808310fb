//! The paper flight's two FMUs through their FMI 3.0 Co-Simulation entry points, loaded
//! from their binaries into the test kit's FMI 3.0 table (`Fmi3Functions::load`) and driven
//! by its instance, as the FMI 2.0 pair is by the kit's FMI 2.0 one: the same exchange, with
//! the vector variables set and read as arrays (5 value references for the 14 navigation
//! values). Each exchange is one FMI call through a function pointer, as from a C master.
use crate::call_orders::{Binaries, Exchange, PAPER_STEPS, PHI_CMD_RAD, Q0_BODY_TO_NUE, STEP_S};
use anyhow::{anyhow, Context, Result};
use fmi_abi::fmi3::*;
use fmi_model::Model;
use fmi_testkit::{CoSimulationOptions, Fmi3Functions, Fmi3Instance};
use std::path::Path;

/// One loaded FMU's instance.
struct Side {
    // Field order is drop order: the instance is freed before its library is unloaded.
    instance: Fmi3Instance,
    _library: libloading::Library,
    _unpacked: fmi_abi::unpack::Unpacked,
}

/// A master's status check: inline, its error built out of line.
#[inline(always)]
fn check(status: fmi3Status, what: &str, side: &Side) -> Result<()> {
    if status == fmi3OK {
        Ok(())
    } else {
        Err(failed(status, what, side))
    }
}

#[cold]
#[inline(never)]
fn failed(status: fmi3Status, what: &str, side: &Side) -> anyhow::Error {
    anyhow!("{what}: {status:?}, {:?}", side.instance.messages())
}

/// The value references of `names` among the model's declarations (FMI 3.0 keeps one
/// reference per array).
fn references<M: Model, const N: usize>(names: [&str; N]) -> Result<[u32; N]> {
    let mut vrs = [0; N];
    for (vr, name) in vrs.iter_mut().zip(names) {
        *vr = M::declarations()
            .iter()
            .find(|d| d.name == name)
            .ok_or_else(|| anyhow!("{} declares no {name}", M::MODEL_NAME))?
            .value_reference;
    }
    Ok(vrs)
}

impl Side {
    fn load<M: Model>(fmu_dir: &Path, binaries: Binaries, name: &str) -> Result<Side> {
        let identifier = M::MODEL_IDENTIFIER;
        let fmu = fmu_dir.join(format!("{identifier}.fmu"));
        let unpacked = fmi_abi::unpack::Unpacked::open(&fmu)
            .with_context(|| format!("unpacking {}", fmu.display()))?;
        let binary = match binaries {
            None => unpacked
                .root()
                .join(format!("binaries/x86_64-linux/{identifier}.so")),
            Some(dir) => dir.join(match identifier {
                "LanderGnc" => "libfmu_gnc.so",
                _ => "libfmu_plant.so",
            }),
        };
        // SAFETY: our own FMU's binary; its fmi3* symbols have the standard's signatures.
        let library = unsafe { libloading::Library::new(&binary) }
            .with_context(|| format!("loading {}", binary.display()))?;
        // SAFETY: as above.
        let functions = unsafe { Fmi3Functions::load(&library) }?;
        let token = fmi3_export::instantiation_token::<M>();
        let resources = format!("file://{}/resources/", unpacked.root().display());
        let instance = Fmi3Instance::co_simulation_in(
            &functions,
            name,
            &token,
            Some(&resources),
            CoSimulationOptions::default(),
        )
        .map_err(|log| {
            anyhow!("{identifier}: fmi3InstantiateCoSimulation returned NULL: {log:?}")
        })?;
        let side = Side {
            instance,
            _library: library,
            _unpacked: unpacked,
        };
        let stop = PAPER_STEPS as f64 * STEP_S;
        check(
            side.instance.enter_initialization_mode(0.0, Some(stop)),
            "enter init",
            &side,
        )?;
        Ok(side)
    }

    #[inline(always)]
    fn set(&self, vrs: &[u32], values: &[f64], what: &str) -> Result<()> {
        check(self.instance.set_float64(vrs, values), what, self)
    }

    #[inline(always)]
    fn get(&self, vrs: &[u32], values: &mut [f64], what: &str) -> Result<()> {
        check(self.instance.get_float64_into(vrs, values), what, self)
    }

    #[inline(always)]
    fn step(&self, t: f64, h: f64, what: &str) -> Result<()> {
        check(self.instance.do_step(t, h).status, what, self)
    }
}

const NAVIGATION: [&str; 5] = ["r_nue", "v_nue", "q_body_to_nue", "omega_body", "mass"];
const COMMANDS: [&str; 2] = ["thrust_cmd", "torque_cmd_body"];

/// Both FMUs through FMI 3.0, initialized for the paper flight.
pub struct Fmi3Pair {
    gnc: Side,
    plant: Side,
    nav_in_gnc: [u32; 5],
    nav_out_plant: [u32; 5],
    cmd_out_gnc: [u32; 2],
    cmd_in_plant: [u32; 2],
}

impl Fmi3Pair {
    pub fn new(fmu_dir: &Path, binaries: Binaries) -> Result<Self> {
        use fmu_gnc::LanderGnc;
        use fmu_plant::LanderPlant;
        let gnc = Side::load::<LanderGnc>(fmu_dir, binaries, "gnc")?;
        let plant = Side::load::<LanderPlant>(fmu_dir, binaries, "plant")?;
        let law = references::<LanderGnc, 1>(["control_law"])?;
        check(gnc.instance.set_int32(&law, &[2]), "control_law", &gnc)?;
        let phi = references::<LanderGnc, 2>(["phi_cmd", "phi_cmd_time"])?;
        gnc.set(&phi, &[PHI_CMD_RAD, 0.0], "phi_cmd")?;
        let initial = references::<LanderPlant, 3>(["r0_nue", "q0_body_to_nue", "m0"])?;
        let q = Q0_BODY_TO_NUE;
        let values = [0.0, 800.0, 0.0, q[0], q[1], q[2], q[3], 900.0];
        plant.set(&initial, &values, "plant initial state")?;
        for (side, what) in [(&gnc, "gnc"), (&plant, "plant")] {
            check(side.instance.exit_initialization_mode(), what, side)?;
        }
        Ok(Fmi3Pair {
            nav_in_gnc: references::<LanderGnc, 5>(NAVIGATION)?,
            nav_out_plant: references::<LanderPlant, 5>(NAVIGATION)?,
            cmd_out_gnc: references::<LanderGnc, 2>(COMMANDS)?,
            cmd_in_plant: references::<LanderPlant, 2>(COMMANDS)?,
            gnc,
            plant,
        })
    }
}

impl Exchange for Fmi3Pair {
    #[inline(always)]
    fn set_navigation(&mut self, nav: &[f64; 14]) -> Result<()> {
        self.gnc.set(&self.nav_in_gnc, nav, "gnc set")
    }
    #[inline(always)]
    fn get_commands(&mut self, cmd: &mut [f64; 4]) -> Result<()> {
        self.gnc.get(&self.cmd_out_gnc, cmd, "gnc get")
    }
    #[inline(always)]
    fn set_commands(&mut self, cmd: &[f64; 4]) -> Result<()> {
        self.plant.set(&self.cmd_in_plant, cmd, "plant set")
    }
    #[inline(always)]
    fn get_navigation(&mut self, nav: &mut [f64; 14]) -> Result<()> {
        self.plant.get(&self.nav_out_plant, nav, "plant get")
    }
    #[inline(always)]
    fn step_gnc(&mut self, t: f64, h: f64) -> Result<()> {
        self.gnc.step(t, h, "gnc step")
    }
    #[inline(always)]
    fn step_plant(&mut self, t: f64, h: f64) -> Result<()> {
        self.plant.step(t, h, "plant step")
    }
}
