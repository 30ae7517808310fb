//! The paper flight in a native C master that knows nothing of the project
//! (`c/list_orders_master.c`, compiled against the official FMI 2.0 and 3.0 headers), in
//! each call order and with the value references listed the ways users' masters list them:
//! the contract's order, sorted, reversed, shuffled (a fixed seed), a new order every step,
//! one variable per call. Counted with callgrind inside its `run_loop`.
use crate::c_floor;
use crate::call_orders::{references, Binaries, Order, PHI_CMD_RAD, Q0_BODY_TO_NUE, STEP_S};
use crate::callgrind::{self, Counts};
use crate::record::{COMMANDS, NAVIGATION};
use anyhow::{anyhow, ensure, Context, Result};
use fmi_abi::unpack::Unpacked;
use fmi_model::Model;
use model_description::ModelDescription;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The C source, built into the binary so the bench needs no source tree at run time.
pub const SOURCE: &str = include_str!("../c/list_orders_master.c");

/// How the master lists the value references of each exchange.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variant {
    Contract,
    Sorted,
    Reversed,
    Shuffled,
    Reshuffled,
    PerValue,
}

impl Variant {
    pub const ALL: [Variant; 6] = [
        Variant::Contract,
        Variant::Sorted,
        Variant::Reversed,
        Variant::Shuffled,
        Variant::Reshuffled,
        Variant::PerValue,
    ];

    /// The master's argument.
    pub fn name(self) -> &'static str {
        match self {
            Variant::Contract => "contract",
            Variant::Sorted => "sorted",
            Variant::Reversed => "reversed",
            Variant::Shuffled => "shuffled",
            Variant::Reshuffled => "reshuffled",
            Variant::PerValue => "per-value",
        }
    }

    pub fn describe(self) -> &'static str {
        match self {
            Variant::Contract => "contract order (r, v, q, omega, mass; thrust, torque)",
            Variant::Sorted => "sorted by value reference",
            Variant::Reversed => "contract order reversed",
            Variant::Shuffled => "shuffled (fixed seed)",
            Variant::Reshuffled => "a new shuffled order every step (64 in turn)",
            Variant::PerValue => "one variable per call",
        }
    }
}

/// The official headers' folders (`fmi-standard2/headers`, `fmi-standard3/headers` of the
/// fmi-sys crate the workspace's system tests depend on), found with `cargo metadata`.
pub fn official_headers() -> Result<[PathBuf; 2]> {
    let output = Command::new(env!("CARGO"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(["metadata", "--format-version", "1"])
        .output()
        .context("running cargo metadata")?;
    ensure!(output.status.success(), "cargo metadata failed");
    let metadata: serde_json::Value = serde_json::from_slice(&output.stdout)?;
    let manifest = metadata["packages"]
        .as_array()
        .and_then(|packages| packages.iter().find(|p| p["name"] == "fmi-sys"))
        .and_then(|p| p["manifest_path"].as_str())
        .ok_or_else(|| anyhow!("fmi-sys (the official headers) is not in the workspace"))?;
    let root = Path::new(manifest)
        .parent()
        .ok_or_else(|| anyhow!("{manifest} has no folder"))?;
    let folders = ["fmi-standard2", "fmi-standard3"].map(|f| root.join(f).join("headers"));
    for folder in &folders {
        ensure!(folder.is_dir(), "no {}", folder.display());
    }
    Ok(folders)
}

/// Compiles the master into `dir` with `$CC` (default `cc`) `-O2`, as the C floor.
pub fn compile(dir: &Path) -> Result<PathBuf> {
    let source = dir.join("list_orders_master.c");
    std::fs::write(&source, SOURCE)?;
    let exe = dir.join("list_orders_master");
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let [fmi2, fmi3] = official_headers()?;
    let output = Command::new(&cc)
        .args(["-O2", "-g", "-Wall", "-Wextra", "-Werror", "-o"])
        .arg(&exe)
        .arg("-I")
        .arg(&fmi2)
        .arg("-I")
        .arg(&fmi3)
        .arg(&source)
        .arg("-ldl")
        .output()
        .with_context(|| format!("running the C compiler {cc}"))?;
    ensure!(
        output.status.success(),
        "{cc} -O2 list_orders_master.c failed:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    Ok(exe)
}

fn joined<T: ToString>(items: impl IntoIterator<Item = T>) -> String {
    items
        .into_iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(",")
}

fn bits(values: &[f64]) -> String {
    joined(values.iter().map(|x| format!("{:016x}", x.to_bits())))
}

/// The value references of `names` among `M`'s declarations (FMI 3.0: one per array).
fn declared<M: Model>(names: &[&str]) -> Result<Vec<u32>> {
    names
        .iter()
        .map(|name| {
            M::declarations()
                .iter()
                .find(|d| d.name == *name)
                .map(|d| d.value_reference)
                .ok_or_else(|| anyhow!("{} declares no {name}", M::MODEL_NAME))
        })
        .collect()
}

/// Both FMUs unpacked, with the master's arguments for one FMI version (everything but
/// the order, the variant and the steps).
pub struct Plan {
    fmi: u8,
    args: Vec<String>,
    _unpacked: [Unpacked; 2],
}

impl Plan {
    pub fn new(fmu_dir: &Path, fmi: u8, binaries: Binaries) -> Result<Plan> {
        use fmu_gnc::LanderGnc;
        use fmu_plant::LanderPlant;
        let folder = if fmi == 3 {
            fmu_dir.join("fmi3")
        } else {
            fmu_dir.to_path_buf()
        };
        let open = |id: &str| {
            let path = folder.join(format!("{id}.fmu"));
            Unpacked::open(&path).with_context(|| format!("unpacking {}", path.display()))
        };
        let (gnc, plant) = (open("LanderGnc")?, open("LanderPlant")?);
        let binary = |unpacked: &Unpacked, id: &str, lib: &str| match binaries {
            Some(dir) => dir.join(lib),
            None if fmi == 3 => unpacked
                .root()
                .join(format!("binaries/x86_64-linux/{id}.so")),
            None => unpacked.binary_path(id),
        };
        let resources = |u: &Unpacked| format!("file://{}/resources/", u.root().display());
        let q = Q0_BODY_TO_NUE;
        let plant_values = [0.0, 800.0, 0.0, q[0], q[1], q[2], q[3], 900.0];
        let mut args = vec![
            format!("fmi={fmi}"),
            format!("step={:016x}", STEP_S.to_bits()),
            format!(
                "gnc={}",
                binary(&gnc, "LanderGnc", "libfmu_gnc.so").display()
            ),
            format!(
                "plant={}",
                binary(&plant, "LanderPlant", "libfmu_plant.so").display()
            ),
            format!("gnc_res={}", resources(&gnc)),
            format!("plant_res={}", resources(&plant)),
            format!("gnc_init_values={}", bits(&[PHI_CMD_RAD, 0.0])),
            format!("plant_init_values={}", bits(&plant_values)),
        ];
        if fmi == 2 {
            let md = |u: &Unpacked| ModelDescription::from_file(u.model_description_path());
            let (gnc_md, plant_md) = (md(&gnc)?, md(&plant)?);
            let plant_init = references(
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
            args.extend([
                format!("gnc_token={}", gnc_md.guid),
                format!("plant_token={}", plant_md.guid),
                format!("nav_gnc={}", joined(references(&gnc_md, NAVIGATION)?)),
                format!("nav_plant={}", joined(references(&plant_md, NAVIGATION)?)),
                format!("nav_sizes={}", joined([1; 14])),
                format!("cmd_gnc={}", joined(references(&gnc_md, COMMANDS)?)),
                format!("cmd_plant={}", joined(references(&plant_md, COMMANDS)?)),
                format!("cmd_sizes={}", joined([1; 4])),
                format!("law={}", references(&gnc_md, ["control_law"])?[0]),
                format!(
                    "gnc_init={}",
                    joined(references(&gnc_md, ["phi_cmd", "phi_cmd_time"])?)
                ),
                format!("plant_init={}", joined(plant_init)),
            ]);
        } else {
            const NAV: [&str; 5] = ["r_nue", "v_nue", "q_body_to_nue", "omega_body", "mass"];
            const CMD: [&str; 2] = ["thrust_cmd", "torque_cmd_body"];
            args.extend([
                format!(
                    "gnc_token={}",
                    fmi3_export::instantiation_token::<LanderGnc>()
                ),
                format!(
                    "plant_token={}",
                    fmi3_export::instantiation_token::<LanderPlant>()
                ),
                format!("nav_gnc={}", joined(declared::<LanderGnc>(&NAV)?)),
                format!("nav_plant={}", joined(declared::<LanderPlant>(&NAV)?)),
                "nav_sizes=3,3,4,3,1".into(),
                format!("cmd_gnc={}", joined(declared::<LanderGnc>(&CMD)?)),
                format!("cmd_plant={}", joined(declared::<LanderPlant>(&CMD)?)),
                "cmd_sizes=1,3".into(),
                format!("law={}", declared::<LanderGnc>(&["control_law"])?[0]),
                format!(
                    "gnc_init={}",
                    joined(declared::<LanderGnc>(&["phi_cmd", "phi_cmd_time"])?)
                ),
                format!(
                    "plant_init={}",
                    joined(declared::<LanderPlant>(&[
                        "r0_nue",
                        "q0_body_to_nue",
                        "m0"
                    ])?)
                ),
            ]);
        }
        Ok(Plan {
            fmi,
            args,
            _unpacked: [gnc, plant],
        })
    }

    fn args(&self, order: Order, variant: Variant, steps: usize) -> Vec<String> {
        let mut args = self.args.clone();
        args.extend([
            format!("order={}", order.name()),
            format!("variant={}", variant.name()),
            format!("steps={steps}"),
        ]);
        args
    }

    /// The plant's 14 navigation outputs after the flight, as the master prints them.
    pub fn fly(
        &self,
        exe: &Path,
        order: Order,
        variant: Variant,
        steps: usize,
    ) -> Result<[f64; 14]> {
        let output = Command::new(exe)
            .args(self.args(order, variant, steps))
            .output()
            .with_context(|| format!("running {}", exe.display()))?;
        ensure!(
            output.status.success(),
            "the C master ({} {}, FMI {}) failed: {}",
            order.name(),
            variant.name(),
            self.fmi,
            String::from_utf8_lossy(&output.stderr)
        );
        c_floor::parse_bits(&String::from_utf8_lossy(&output.stdout))
    }

    /// Instructions inside the master's `run_loop`.
    pub fn count(
        &self,
        exe: &Path,
        order: Order,
        variant: Variant,
        steps: usize,
        out_dir: &Path,
    ) -> Result<Counts> {
        callgrind::count(exe, &self.args(order, variant, steps), "run_loop", out_dir)
    }

    /// [`Plan::count`], keeping callgrind's file at `out`.
    pub fn profile(
        &self,
        exe: &Path,
        order: Order,
        variant: Variant,
        steps: usize,
        out: &Path,
    ) -> Result<Counts> {
        callgrind::count_into(exe, &self.args(order, variant, steps), "run_loop", out)
    }
}
