//! The paper flight's closed loop (LanderGnc + LanderPlant, 17,200 steps of 0.01 s), flown
//! in the call orders masters use, and the same math as a plain Rust loop with no FMI: the
//! floor the FMUs are measured against (instruction counts, `src/bin/call_orders.rs`).
//!
//! The loops allocate nothing and do nothing but the exchange, so what callgrind counts in
//! [`measured_flight`] is the FMUs' cost (C ABI, layers, models) plus a few copies.
use anyhow::{anyhow, Context, Result};
use fmi_abi::fmi2::{fmi2OK, fmi2Status};
use fmi_abi::unpack::Unpacked;
use fmi_testkit::{Fmi2Functions, Instance};
use fmu_gnc::actuation::PwpfBank;
use fmu_gnc::attitude::profile::PhiProfile;
use fmu_gnc::attitude::GuidanceReference;
use fmu_gnc::controller::{
    actuate, gnc_advance, gnc_outputs_keeping_reference, GncOutputs, NavigationInputs,
};
use fmu_gnc::guidance::sequencer::GuidanceState;
use fmu_gnc::params::{GncDesign, GncParameters};
use fmu_plant::physics::continuous::unit_attitude;
use fmu_plant::physics::frames::quaternion_to_scalar_first;
use fmu_plant::physics::parameters::PlantParameters;
use fmu_plant::physics::plant::{Commands, Plant, PlantRun};
use model_description::ModelDescription;
use nalgebra::Vector3;
use std::path::Path;

use crate::record::{COMMANDS, NAVIGATION};

pub use crate::fmi3_pair::Fmi3Pair;

pub const STEP_S: f64 = 0.01;
/// The paper flight: 172 s.
pub const PAPER_STEPS: usize = 17_200;

/// How a master sequences the calls of one communication step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Order {
    /// No FMI: the GNC sample and the plant step called as Rust functions.
    Plain,
    /// Read the plant, set the GNC's inputs, read its commands, then step both (the
    /// harness's Gauss-Seidel: the commands at t are a function of the state at t).
    ReadThenStep,
    /// Set the GNC's inputs, step it, then read its commands (fmpy's loop and most
    /// masters): the read after the step sees t + h with the inputs of t.
    StepThenRead,
    /// Set every input, step both, read every output.
    Jacobi,
}

impl Order {
    pub const ALL: [Order; 4] = [
        Order::Plain,
        Order::ReadThenStep,
        Order::StepThenRead,
        Order::Jacobi,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Order::Plain => "plain",
            Order::ReadThenStep => "read-then-step",
            Order::StepThenRead => "step-then-read",
            Order::Jacobi => "jacobi",
        }
    }

    pub fn describe(self) -> &'static str {
        match self {
            Order::Plain => "plain Rust loop of the same math, no FMI (the floor)",
            Order::ReadThenStep => "read the GNC, then step it (Gauss-Seidel with feedthrough)",
            Order::StepThenRead => "step the GNC, then read it (fmpy's loop)",
            Order::Jacobi => "Jacobi: set every input, step both, read every output",
        }
    }
}

/// The paper scenario's parameters (harness/scenarios/paper.toml).
pub(crate) const PHI_CMD_RAD: f64 = 150.0 * std::f64::consts::PI / 180.0;
pub(crate) const Q0_BODY_TO_NUE: [f64; 4] = [0.9914448613738104, 0.0, 0.0, -0.13052619222005157];

pub fn gnc_parameters() -> GncParameters {
    GncParameters {
        control_law: 2,
        phi_cmd_rad: PHI_CMD_RAD,
        phi_cmd_time_s: 0.0,
        ..GncParameters::default()
    }
}

pub fn plant_parameters() -> PlantParameters {
    PlantParameters {
        r0_nue_m: Vector3::new(0.0, 800.0, 0.0),
        q0_body_to_nue: Q0_BODY_TO_NUE,
        m0_kg: 900.0,
        ..PlantParameters::default()
    }
}

/// One FMU loaded from its archive, instantiated, with the references of the exchange.
struct Loaded {
    // Field order is drop order: the instance is freed before its library is unloaded.
    instance: Instance,
    _library: libloading::Library,
    _unpacked: Unpacked,
}

/// Where each FMU's binary comes from: the archive, or (`Some(dir)`) the same build's
/// unstripped library in `dir` (`libfmu_gnc.so`, `libfmu_plant.so`), so that a profile names
/// the functions.
pub type Binaries<'a> = Option<&'a Path>;

fn load(
    path: &Path,
    instance_name: &str,
    binaries: Binaries,
) -> Result<(Loaded, ModelDescription)> {
    let unpacked = Unpacked::open(path).with_context(|| format!("unpacking {}", path.display()))?;
    let md = ModelDescription::from_file(unpacked.model_description_path())?;
    let identifier = md
        .co_simulation
        .as_ref()
        .map(|cs| cs.model_identifier.clone())
        .ok_or_else(|| anyhow!("{} has no Co-Simulation interface", path.display()))?;
    let binary = match binaries {
        None => unpacked.binary_path(&identifier),
        // The unstripped twin is the crate's own cdylib, named after its [lib] (the
        // FMU crates' metadata says which crate builds which FMU).
        Some(dir) => {
            let fmus = fmu_metadata::fmus_around(env!("CARGO_MANIFEST_DIR"))
                .map_err(|e| anyhow!("[package.metadata.fmu]: {e}"))?;
            let fmu = fmus
                .iter()
                .find(|f| f.model_identifier == identifier)
                .ok_or_else(|| anyhow!("no unstripped twin known for {identifier}"))?;
            dir.join(format!("lib{}.so", fmu.lib_name))
        }
    };
    // SAFETY: our own FMU's binary, whose fmi2* symbols have the standard's signatures.
    let library = unsafe { libloading::Library::new(&binary) }
        .with_context(|| format!("loading {}", binary.display()))?;
    // SAFETY: as above.
    let functions = unsafe { Fmi2Functions::load(&library) }?;
    let instance = Instance::new(&functions, instance_name, &md.guid, false)
        .map_err(|log| anyhow!("instantiating {instance_name}: {log:?}"))?;
    Ok((
        Loaded {
            instance,
            _library: library,
            _unpacked: unpacked,
        },
        md,
    ))
}

pub(crate) fn references<const N: usize>(
    md: &ModelDescription,
    names: [&str; N],
) -> Result<[u32; N]> {
    let mut vrs = [0; N];
    for (vr, name) in vrs.iter_mut().zip(names) {
        *vr = md
            .variable(name)
            .ok_or_else(|| anyhow!("{} has no variable {name}", md.model_name))?
            .value_reference;
    }
    Ok(vrs)
}

/// A master's status check: inline, its error built out of line.
#[inline(always)]
fn ok(status: fmi2Status, what: &str, instance: &Instance) -> Result<()> {
    if status == fmi2OK {
        Ok(())
    } else {
        Err(failed(status, what, instance))
    }
}

#[cold]
#[inline(never)]
fn failed(status: fmi2Status, what: &str, instance: &Instance) -> anyhow::Error {
    anyhow!("{what}: status {status:?}, {:?}", instance.messages())
}

/// Both FMUs through their C ABI, initialized for the paper flight.
pub struct FmuPair {
    gnc: Loaded,
    plant: Loaded,
    nav_in_gnc: [u32; 14],
    nav_out_plant: [u32; 14],
    cmd_out_gnc: [u32; 4],
    cmd_in_plant: [u32; 4],
}

impl FmuPair {
    pub fn new(fmu_dir: &Path, binaries: Binaries) -> Result<Self> {
        let (gnc, gnc_md) = load(&fmu_dir.join("LanderGnc.fmu"), "gnc", binaries)?;
        let (plant, plant_md) = load(&fmu_dir.join("LanderPlant.fmu"), "plant", binaries)?;
        let pair = FmuPair {
            nav_in_gnc: references(&gnc_md, NAVIGATION)?,
            nav_out_plant: references(&plant_md, NAVIGATION)?,
            cmd_out_gnc: references(&gnc_md, COMMANDS)?,
            cmd_in_plant: references(&plant_md, COMMANDS)?,
            gnc,
            plant,
        };
        let (g, p) = (&pair.gnc.instance, &pair.plant.instance);
        let stop = Some(PAPER_STEPS as f64 * STEP_S);
        ok(g.setup_experiment(0.0, stop), "gnc setup", g)?;
        ok(p.setup_experiment(0.0, stop), "plant setup", p)?;
        ok(g.enter_initialization_mode(), "gnc init", g)?;
        ok(p.enter_initialization_mode(), "plant init", p)?;
        let law = references(&gnc_md, ["control_law"])?;
        ok(g.set_integers(&law, &[2]), "control_law", g)?;
        let gnc_reals = references(&gnc_md, ["phi_cmd", "phi_cmd_time"])?;
        ok(g.set_reals(&gnc_reals, &[PHI_CMD_RAD, 0.0]), "gnc", g)?;
        let plant_reals = references(
            &plant_md,
            [
                "r0_nue[1]",
                "r0_nue[2]",
                "r0_nue[3]",
                "q0_body_to_nue[1]",
                "q0_body_to_nue[2]",
                "q0_body_to_nue[3]",
                "q0_body_to_nue[4]",
                "m0",
            ],
        )?;
        let q = Q0_BODY_TO_NUE;
        let values = [0.0, 800.0, 0.0, q[0], q[1], q[2], q[3], 900.0];
        ok(p.set_reals(&plant_reals, &values), "plant", p)?;
        ok(g.exit_initialization_mode(), "gnc exit init", g)?;
        ok(p.exit_initialization_mode(), "plant exit init", p)?;
        Ok(pair)
    }
}

/// The plain loop's state: the GNC's memory and the plant's run.
pub struct PlainPair {
    design: GncDesign,
    guidance: GuidanceState,
    profile: PhiProfile,
    pwpf: PwpfBank,
    outputs: GncOutputs,
    /// The reference attitude of the guidance command, kept as the FMU keeps it.
    reference: Option<GuidanceReference>,
    plant: Plant,
    run: PlantRun,
}

impl PlainPair {
    pub fn new() -> Result<Self> {
        let design = gnc_parameters()
            .design()
            .map_err(|e| anyhow!("GNC parameters: {e}"))?;
        let (plant, run, _) =
            Plant::new(&plant_parameters()).map_err(|e| anyhow!("plant parameters: {e}"))?;
        Ok(PlainPair {
            guidance: GuidanceState::initial(design.params.gravity_mps2),
            profile: PhiProfile::default(),
            pwpf: PwpfBank::default(),
            outputs: GncOutputs::default(),
            reference: None,
            design,
            plant,
            run,
        })
    }

    /// The plant's navigation outputs, as the FMU computes them.
    fn navigation(&self) -> NavigationInputs {
        let x = &self.run.state;
        let (r_nue, v_nue) = self.plant.translation.to_nue(&x.translation);
        NavigationInputs {
            r_nue_m: r_nue.to_array(),
            v_nue_mps: v_nue.to_array(),
            q_body_to_nue: quaternion_to_scalar_first(&unit_attitude(&x.q_body_to_nue)),
            omega_body_radps: x.omega_body.to_array(),
            mass_kg: x.mass_kg,
        }
    }

    fn navigation_array(&self) -> [f64; 14] {
        let n = self.navigation();
        let mut y = [0.0; 14];
        y[0..3].copy_from_slice(&n.r_nue_m);
        y[3..6].copy_from_slice(&n.v_nue_mps);
        y[6..10].copy_from_slice(&n.q_body_to_nue);
        y[10..13].copy_from_slice(&n.omega_body_radps);
        y[13] = n.mass_kg;
        y
    }
}

/// Either pair, ready to fly.
pub enum Pair {
    Plain(Box<PlainPair>),
    Fmi2(Box<FmuPair>),
    Fmi3(Box<Fmi3Pair>),
}

impl Pair {
    /// The plain pair for [`Order::Plain`], otherwise the FMUs of FMI `version` (2 or 3).
    pub fn new(order: Order, version: u8, fmu_dir: &Path, binaries: Binaries) -> Result<Self> {
        Ok(match (order, version) {
            (Order::Plain, _) => Pair::Plain(Box::new(PlainPair::new()?)),
            (_, 2) => Pair::Fmi2(Box::new(FmuPair::new(fmu_dir, binaries)?)),
            (_, 3) => Pair::Fmi3(Box::new(Fmi3Pair::new(&fmu_dir.join("fmi3"), binaries)?)),
            (_, other) => return Err(anyhow!("FMI {other}: only 2 and 3 exist")),
        })
    }
}

/// The plant's 14 navigation outputs after `steps` steps flown in `order`; the first
/// failing status ends the flight with an error. Kept out of line so callgrind can count
/// it alone (`--toggle-collect`).
#[inline(never)]
pub fn measured_flight(pair: &mut Pair, order: Order, steps: usize) -> Result<[f64; 14]> {
    match pair {
        Pair::Plain(p) => Ok(plain(p, steps)),
        Pair::Fmi2(f) => through_c_abi(f.as_mut(), order, steps),
        Pair::Fmi3(f) => through_c_abi(f.as_mut(), order, steps),
    }
}

fn plain(p: &mut PlainPair, steps: usize) -> [f64; 14] {
    for k in 0..steps {
        let t = k as f64 * STEP_S;
        let nav = p.navigation();
        // `gnc_sample` in its two parts, the outputs kept in place as the FMU keeps them.
        let advance = gnc_advance(&p.design, 0.0, &p.guidance, &p.profile, &nav, t);
        gnc_outputs_keeping_reference(
            &p.design,
            &advance,
            &p.guidance,
            &nav,
            &mut p.outputs,
            &mut p.reference,
        );
        p.pwpf = actuate(&p.design, &mut p.outputs, &p.pwpf);
        p.guidance = advance.guidance;
        p.profile = advance.profile;
        let commands = Commands {
            thrust_cmd_n: p.outputs.thrust_cmd_n,
            torque_cmd_body_nm: Vector3::from(p.outputs.torque_cmd_body_nm),
        };
        p.plant
            .advance_with_duty(&mut p.run, &commands, &p.outputs.rcs_duty, t, STEP_S);
    }
    p.navigation_array()
}

/// One FMI version's exchange between the two FMUs of a pair, as a master calls it.
pub trait Exchange {
    fn set_navigation(&mut self, nav: &[f64; 14]) -> Result<()>;
    fn get_commands(&mut self, cmd: &mut [f64; 4]) -> Result<()>;
    fn set_commands(&mut self, cmd: &[f64; 4]) -> Result<()>;
    fn get_navigation(&mut self, nav: &mut [f64; 14]) -> Result<()>;
    fn step_gnc(&mut self, t: f64, h: f64) -> Result<()>;
    fn step_plant(&mut self, t: f64, h: f64) -> Result<()>;
}

impl Exchange for FmuPair {
    #[inline(always)]
    fn set_navigation(&mut self, nav: &[f64; 14]) -> Result<()> {
        let g = &self.gnc.instance;
        ok(g.set_reals(&self.nav_in_gnc, nav), "gnc set", g)
    }
    #[inline(always)]
    fn get_commands(&mut self, cmd: &mut [f64; 4]) -> Result<()> {
        let g = &self.gnc.instance;
        ok(g.get_reals_into(&self.cmd_out_gnc, cmd), "gnc get", g)
    }
    #[inline(always)]
    fn set_commands(&mut self, cmd: &[f64; 4]) -> Result<()> {
        let p = &self.plant.instance;
        ok(p.set_reals(&self.cmd_in_plant, cmd), "plant set", p)
    }
    #[inline(always)]
    fn get_navigation(&mut self, nav: &mut [f64; 14]) -> Result<()> {
        let p = &self.plant.instance;
        ok(p.get_reals_into(&self.nav_out_plant, nav), "plant get", p)
    }
    #[inline(always)]
    fn step_gnc(&mut self, t: f64, h: f64) -> Result<()> {
        let g = &self.gnc.instance;
        ok(g.do_step(t, h), "gnc step", g)
    }
    #[inline(always)]
    fn step_plant(&mut self, t: f64, h: f64) -> Result<()> {
        let p = &self.plant.instance;
        ok(p.do_step(t, h), "plant step", p)
    }
}

fn through_c_abi(f: &mut impl Exchange, order: Order, steps: usize) -> Result<[f64; 14]> {
    let (mut nav, mut cmd) = ([0.0; 14], [0.0; 4]);
    f.get_navigation(&mut nav)?;
    if order != Order::ReadThenStep {
        f.set_navigation(&nav)?;
        f.get_commands(&mut cmd)?;
    }
    for k in 0..steps {
        let t = k as f64 * STEP_S;
        match order {
            Order::ReadThenStep => {
                f.set_navigation(&nav)?;
                f.get_commands(&mut cmd)?;
                f.set_commands(&cmd)?;
                f.step_gnc(t, STEP_S)?;
                f.step_plant(t, STEP_S)?;
                f.get_navigation(&mut nav)?;
            }
            Order::StepThenRead => {
                f.set_navigation(&nav)?;
                f.step_gnc(t, STEP_S)?;
                f.get_commands(&mut cmd)?;
                f.set_commands(&cmd)?;
                f.step_plant(t, STEP_S)?;
                f.get_navigation(&mut nav)?;
            }
            Order::Jacobi => {
                f.set_navigation(&nav)?;
                f.set_commands(&cmd)?;
                f.step_gnc(t, STEP_S)?;
                f.step_plant(t, STEP_S)?;
                f.get_commands(&mut cmd)?;
                f.get_navigation(&mut nav)?;
            }
            Order::Plain => unreachable!("the plain pair has no C ABI"),
        }
    }
    Ok(nav)
}
