//! The paper flight's two FMUs through their FMI 3.0 Co-Simulation entry points, declared
//! here by hand as any C master would: the same exchange as the FMI 2.0 pair, with the
//! vector variables set and read as arrays (5 value references for the 14 navigation values).
use crate::call_orders::{Binaries, Exchange, PAPER_STEPS, PHI_CMD_RAD, Q0_BODY_TO_NUE, STEP_S};
use anyhow::{anyhow, Context, Result};
use fmi_abi::fmi3::*;
use fmi_model::Model;
use std::ffi::{c_char, CString};
use std::path::Path;

type Instantiate = unsafe extern "C" fn(
    *const c_char,
    *const c_char,
    *const c_char,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    *const fmi3ValueReference,
    usize,
    fmi3InstanceEnvironment,
    fmi3LogMessageCallback,
    fmi3IntermediateUpdateCallback,
) -> fmi3Instance;
type EnterInit = unsafe extern "C" fn(
    fmi3Instance,
    fmi3Boolean,
    fmi3Float64,
    fmi3Float64,
    fmi3Boolean,
    fmi3Float64,
) -> fmi3Status;
type InstanceOnly = unsafe extern "C" fn(fmi3Instance) -> fmi3Status;
type Free = unsafe extern "C" fn(fmi3Instance);
type SetFloat64 = unsafe extern "C" fn(
    fmi3Instance,
    *const fmi3ValueReference,
    usize,
    *const fmi3Float64,
    usize,
) -> fmi3Status;
type GetFloat64 = unsafe extern "C" fn(
    fmi3Instance,
    *const fmi3ValueReference,
    usize,
    *mut fmi3Float64,
    usize,
) -> fmi3Status;
type SetInt32 = unsafe extern "C" fn(
    fmi3Instance,
    *const fmi3ValueReference,
    usize,
    *const i32,
    usize,
) -> fmi3Status;
type DoStep = unsafe extern "C" fn(
    fmi3Instance,
    fmi3Float64,
    fmi3Float64,
    fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Float64,
) -> fmi3Status;

/// One loaded FMU's functions and instance.
struct Side {
    instance: fmi3Instance,
    set_float64: SetFloat64,
    get_float64: GetFloat64,
    do_step: DoStep,
    free: Free,
    _library: libloading::Library,
    _unpacked: fmi_abi::unpack::Unpacked,
}

impl Drop for Side {
    fn drop(&mut self) {
        // SAFETY: our live instance, freed once, before its library is unloaded.
        unsafe { (self.free)(self.instance) };
    }
}

fn check(status: fmi3Status, what: &str) -> Result<()> {
    if status == fmi3OK {
        Ok(())
    } else {
        Err(anyhow!("{what}: {status:?}"))
    }
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
        // SAFETY: our own FMU's binary; the symbols below have the standard's signatures.
        let library = unsafe { libloading::Library::new(&binary) }
            .with_context(|| format!("loading {}", binary.display()))?;
        macro_rules! symbol {
            ($t:ty, $name:literal) => {
                // SAFETY: as above.
                *unsafe { library.get::<$t>(concat!($name, "\0").as_bytes()) }?
            };
        }
        let instantiate = symbol!(Instantiate, "fmi3InstantiateCoSimulation");
        let enter: EnterInit = symbol!(EnterInit, "fmi3EnterInitializationMode");
        let token = CString::new(fmi3_export::instantiation_token::<M>())?;
        let name = CString::new(name)?;
        let resources = CString::new(format!("file://{}/resources/", unpacked.root().display()))?;
        // SAFETY: valid strings; no callbacks.
        let instance = unsafe {
            instantiate(
                name.as_ptr(),
                token.as_ptr(),
                resources.as_ptr(),
                false,
                false,
                false,
                false,
                std::ptr::null(),
                0,
                std::ptr::null_mut(),
                None,
                None,
            )
        };
        if instance.is_null() {
            return Err(anyhow!(
                "{identifier}: fmi3InstantiateCoSimulation returned NULL"
            ));
        }
        let side = Side {
            instance,
            set_float64: symbol!(SetFloat64, "fmi3SetFloat64"),
            get_float64: symbol!(GetFloat64, "fmi3GetFloat64"),
            do_step: symbol!(DoStep, "fmi3DoStep"),
            free: symbol!(Free, "fmi3FreeInstance"),
            _library: library,
            _unpacked: unpacked,
        };
        let stop = PAPER_STEPS as f64 * STEP_S;
        // SAFETY: our live instance.
        check(
            unsafe { enter(instance, false, 0.0, 0.0, true, stop) },
            "enter init",
        )?;
        Ok(side)
    }

    #[inline(always)]
    fn set(&self, vrs: &[u32], values: &[f64], what: &str) -> Result<()> {
        // SAFETY: arrays of the lengths passed; a live instance.
        let status = unsafe {
            (self.set_float64)(
                self.instance,
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        };
        check(status, what)
    }

    #[inline(always)]
    fn get(&self, vrs: &[u32], values: &mut [f64], what: &str) -> Result<()> {
        // SAFETY: as in `set`.
        let status = unsafe {
            (self.get_float64)(
                self.instance,
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                values.len(),
            )
        };
        check(status, what)
    }

    #[inline(always)]
    fn step(&self, t: f64, h: f64, what: &str) -> Result<()> {
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
        // SAFETY: a live instance; the out-pointers are ours.
        let status = unsafe {
            (self.do_step)(
                self.instance,
                t,
                h,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
        };
        check(status, what)
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
        let set_int32: SetInt32 = {
            // SAFETY: the standard's signature.
            *unsafe { gnc._library.get::<SetInt32>(b"fmi3SetInt32\0") }?
        };
        let law = references::<LanderGnc, 1>(["control_law"])?;
        // SAFETY: a live instance, arrays of the lengths passed.
        check(
            unsafe { set_int32(gnc.instance, law.as_ptr(), 1, [2].as_ptr(), 1) },
            "control_law",
        )?;
        let phi = references::<LanderGnc, 2>(["phi_cmd", "phi_cmd_time"])?;
        gnc.set(&phi, &[PHI_CMD_RAD, 0.0], "phi_cmd")?;
        let initial = references::<LanderPlant, 3>(["r0_nue", "q0_body_to_nue", "m0"])?;
        let q = Q0_BODY_TO_NUE;
        let values = [0.0, 800.0, 0.0, q[0], q[1], q[2], q[3], 900.0];
        plant.set(&initial, &values, "plant initial state")?;
        for (side, what) in [(&gnc, "gnc"), (&plant, "plant")] {
            let exit: InstanceOnly = {
                // SAFETY: the standard's signature.
                *unsafe {
                    side._library
                        .get::<InstanceOnly>(b"fmi3ExitInitializationMode\0")
                }?
            };
            // SAFETY: a live instance.
            check(unsafe { exit(side.instance) }, what)?;
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
