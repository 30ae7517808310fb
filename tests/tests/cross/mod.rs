//! Running the `--all-platforms` FMUs on each platform they carry a binary for: x86_64 Linux
//! natively, aarch64 Linux under `qemu-aarch64`, x86_64 Windows under Wine, each through
//! `tests/c/closed_loop_master.c` compiled by that platform's C compiler. Used by
//! `same_bits.rs` and `windows_users.rs`.
//!
//! Everything goes to one scratch directory, `<target>/cross-runs`: the unpacked FMUs, the
//! compiled masters, the Wine prefix, the plans and the outputs, so that a failed run can be
//! repeated by hand with the command the failure prints.
#![allow(dead_code)]

use model_description::{ModelDescription, StartValue, VariableKind};
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};
use system_tests::{target_dir, workspace_root, Fmi};

pub fn scratch() -> PathBuf {
    target_dir().join("cross-runs")
}

/// A platform of the `--all-platforms` FMUs and how this machine runs its programs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Platform {
    LinuxX86_64,
    LinuxAarch64,
    WindowsX86_64,
}

impl Platform {
    pub const ALL: [Platform; 3] = [
        Platform::LinuxX86_64,
        Platform::LinuxAarch64,
        Platform::WindowsX86_64,
    ];

    /// The binaries folder of this platform in an FMU of `version`; FMI 2.0 has none for
    /// Linux on ARM.
    pub fn folder(self, version: Fmi) -> Option<&'static str> {
        match (self, version) {
            (Platform::LinuxX86_64, Fmi::V2) => Some("linux64"),
            (Platform::LinuxAarch64, Fmi::V2) => None,
            (Platform::WindowsX86_64, Fmi::V2) => Some("win64"),
            (Platform::LinuxX86_64, Fmi::V3) => Some("x86_64-linux"),
            (Platform::LinuxAarch64, Fmi::V3) => Some("aarch64-linux"),
            (Platform::WindowsX86_64, Fmi::V3) => Some("x86_64-windows"),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Platform::LinuxX86_64 => "x86_64 Linux",
            Platform::LinuxAarch64 => "aarch64 Linux (qemu-aarch64)",
            Platform::WindowsX86_64 => "x86_64 Windows (Wine)",
        }
    }

    fn extension(self) -> &'static str {
        match self {
            Platform::WindowsX86_64 => "dll",
            _ => "so",
        }
    }

    /// The C compiler, its libraries and the Debian package that has it.
    fn compiler(self) -> (&'static str, &'static [&'static str], &'static str) {
        match self {
            Platform::LinuxX86_64 => ("gcc", &["-ldl"], "gcc"),
            Platform::LinuxAarch64 => ("aarch64-linux-gnu-gcc", &["-ldl"], "gcc-aarch64-linux-gnu"),
            Platform::WindowsX86_64 => ("x86_64-w64-mingw32-gcc", &[], "gcc-mingw-w64-x86-64"),
        }
    }

    fn program_name(self) -> &'static str {
        match self {
            Platform::LinuxX86_64 => "closed_loop_master-x86_64-linux",
            Platform::LinuxAarch64 => "closed_loop_master-aarch64-linux",
            Platform::WindowsX86_64 => "closed_loop_master-x86_64-windows.exe",
        }
    }

    /// A path as a program of this platform names it: Wine maps the Unix root to drive Z:.
    pub fn path(self, path: &Path) -> String {
        let text = path.to_string_lossy();
        match self {
            Platform::WindowsX86_64 => format!("Z:{}", text.replace('/', "\\")),
            _ => text.into_owned(),
        }
    }
}

fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .map(|paths| std::env::split_paths(&paths).any(|dir| dir.join(program).is_file()))
        .unwrap_or(false)
}

/// Panics with the command that installs `package` unless `program` is on PATH.
pub fn require(program: &str, package: &str) {
    assert!(
        on_path(program),
        "{program} is not on PATH: run `sudo apt-get install {package}`"
    );
}

/// Runs `cmd`, panicking with its output (and `what` it was for) unless it succeeds.
pub fn run_ok(cmd: &mut Command, what: &str) -> Output {
    let output = cmd
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot run {cmd:?}: {e}"));
    assert!(
        output.status.success(),
        "{what}: {cmd:?} failed ({}):\n{}{}",
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// Compiles a C source of tests/c for `platform` into `output`, every warning an error: the
/// C must stay clean on all three compilers.
fn compile(platform: Platform, source: &str, output: &Path, extra: &[&str]) {
    let (compiler, libraries, package) = platform.compiler();
    require(compiler, package);
    std::fs::create_dir_all(output.parent().unwrap()).unwrap();
    run_ok(
        Command::new(compiler)
            .args(["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-o"])
            .arg(output)
            .arg(workspace_root().join("tests/c").join(source))
            .args(extra)
            .args(libraries),
        &format!("compiling tests/c/{source} for {}", platform.name()),
    );
}

/// The master compiled for `platform`, once per test process.
pub fn master(platform: Platform) -> PathBuf {
    static BUILT: Mutex<Vec<Platform>> = Mutex::new(Vec::new());
    let program = scratch().join("bin").join(platform.program_name());
    let mut built = BUILT.lock().unwrap_or_else(|e| e.into_inner());
    if !built.contains(&platform) {
        compile(platform, "closed_loop_master.c", &program, &[]);
        built.push(platform);
    }
    program
}

/// Compiles the master for `platform` and, for Windows, makes the Wine prefix: the parts
/// of a run that must not happen in two threads at once.
pub fn prepare(platform: Platform) {
    master(platform);
    if platform == Platform::WindowsX86_64 {
        wine_prefix();
    }
}

/// The private Wine prefix, made once, with the test-only `bcryptprimitives.dll` in its
/// system32: Rust's std (1.78+) imports `ProcessPrng` from it, which Wine 8 lacks.
fn wine_prefix() -> PathBuf {
    static PREFIX: OnceLock<PathBuf> = OnceLock::new();
    PREFIX
        .get_or_init(|| {
            require("wine", "wine");
            let prefix = scratch().join("wine-prefix");
            let system32 = prefix.join("drive_c/windows/system32");
            if !system32.join("kernel32.dll").is_file() {
                run_ok(
                    wine_env(Command::new("wineboot").arg("--init"), &prefix),
                    "creating the Wine prefix",
                );
                // wineboot returns before the prefix's server has written everything.
                run_ok(
                    wine_env(Command::new("wineserver").arg("-w"), &prefix),
                    "waiting for wineserver",
                );
            }
            compile(
                Platform::WindowsX86_64,
                "wine_bcryptprimitives.c",
                &system32.join("bcryptprimitives.dll"),
                &["-shared", "-lbcrypt"],
            );
            prefix
        })
        .clone()
}

fn wine_env<'a>(cmd: &'a mut Command, prefix: &Path) -> &'a mut Command {
    cmd.env("WINEPREFIX", prefix)
        .env("WINEDEBUG", "-all")
        // No Mono or Gecko installer dialogs for a prefix that needs neither.
        .env("WINEDLLOVERRIDES", "mscoree,mshtml=")
}

/// The command that runs `program` (built for `platform`) with `args`.
pub fn command(platform: Platform, program: &Path, args: &[String]) -> Command {
    match platform {
        Platform::LinuxX86_64 => {
            let mut cmd = Command::new(program);
            cmd.args(args);
            cmd
        }
        Platform::LinuxAarch64 => {
            require("qemu-aarch64", "qemu-user");
            // The aarch64 loader and libc of the multiarch packages, found by the program's
            // own interpreter path; `-L` at the cross sysroot mixes two C libraries and
            // hangs every program that starts a thread.
            assert!(
                Path::new("/lib/ld-linux-aarch64.so.1").exists(),
                "/lib/ld-linux-aarch64.so.1 is missing: run `sudo dpkg --add-architecture arm64 \
                 && sudo apt-get update && sudo apt-get install libc6:arm64`"
            );
            let mut cmd = Command::new("qemu-aarch64");
            cmd.arg(program).args(args);
            cmd
        }
        Platform::WindowsX86_64 => {
            let prefix = wine_prefix();
            let mut cmd = Command::new("wine");
            wine_env(&mut cmd, &prefix).arg(program).args(args);
            cmd
        }
    }
}

/// A finished run of the master.
pub struct Run {
    pub platform: Platform,
    pub exit_code: Option<i32>,
    pub out: String,
    pub log: Vec<u8>,
    pub stderr: String,
    pub seconds: f64,
    /// The command, for the report.
    pub command: String,
}

impl Run {
    pub fn lines(&self) -> std::str::Lines<'_> {
        self.out.lines()
    }

    pub fn log_text(&self) -> String {
        String::from_utf8_lossy(&self.log).into_owned()
    }

    /// Panics unless the master exited with 0 and freed every instance.
    pub fn assert_clean(&self, what: &str) {
        assert!(
            self.exit_code == Some(0) && self.out.ends_with("freed\n"),
            "{what} on {}: exit {:?}, last lines {:?}\nstderr: {}\nlog: {}\nrun again: {}",
            self.platform.name(),
            self.exit_code,
            self.out.lines().rev().take(3).collect::<Vec<_>>(),
            self.stderr,
            tail(&self.log_text(), 20),
            self.command
        );
    }
}

fn tail(text: &str, lines: usize) -> String {
    let all: Vec<&str> = text.lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}

/// Writes `plan` for `platform` as `<name>.plan` in the scratch directory, runs the master
/// on it and reads what it wrote.
pub fn fly(platform: Platform, plan: &Plan, name: &str) -> Run {
    let dir = scratch().join("runs");
    std::fs::create_dir_all(&dir).unwrap();
    let tag = format!(
        "{name}-{}",
        platform.program_name().trim_end_matches(".exe")
    );
    let (plan_file, out_file, log_file) = (
        dir.join(format!("{tag}.plan")),
        dir.join(format!("{tag}.out")),
        dir.join(format!("{tag}.log")),
    );
    std::fs::write(&plan_file, plan.text(platform)).unwrap();
    let _ = std::fs::remove_file(&out_file);
    let program = master(platform);
    let args: Vec<String> = [&plan_file, &out_file, &log_file]
        .iter()
        .map(|p| platform.path(p))
        .collect();
    let mut cmd = command(platform, &program, &args);
    let shown = format!(
        "{}{}",
        if platform == Platform::WindowsX86_64 {
            format!(
                "WINEPREFIX={} WINEDEBUG=-all ",
                scratch().join("wine-prefix").display()
            )
        } else {
            String::new()
        },
        std::iter::once(cmd.get_program())
            .chain(cmd.get_args())
            .map(|a| a.to_string_lossy().into_owned())
            .collect::<Vec<_>>()
            .join(" ")
    );
    let start = Instant::now();
    let output = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {shown}: {e}"));
    let seconds = start.elapsed().as_secs_f64();
    Run {
        platform,
        exit_code: output.status.code(),
        out: std::fs::read_to_string(&out_file).unwrap_or_default(),
        log: std::fs::read(&log_file).unwrap_or_default(),
        stderr: String::from_utf8_lossy(&output.stderr).into_owned(),
        seconds,
        command: shown,
    }
}

// ---- the FMUs and their variables ------------------------------------------------------

/// A variable as the master sees it: FMI 2.0 scalars have `len` 1, FMI 3.0 arrays more.
#[derive(Debug, Clone)]
pub struct Variable {
    pub name: String,
    pub vr: u32,
    pub causality: String,
    /// R, I, E or B (the master's letters); strings are left out.
    pub kind: char,
    pub len: usize,
    pub start: Vec<f64>,
}

/// An unpacked `--all-platforms` FMU of one version.
#[derive(Debug, Clone)]
pub struct Fmu {
    pub version: Fmi,
    pub model_identifier: String,
    pub root: PathBuf,
    pub token: String,
    pub variables: Vec<Variable>,
}

impl Fmu {
    /// `<target>/fmu/[fmi3/]<id>.fmu` (written by `cargo xtask fmus --all-platforms`), unpacked once per test process.
    pub fn open(version: Fmi, model_identifier: &str) -> Fmu {
        static OPENED: Mutex<Vec<Fmu>> = Mutex::new(Vec::new());
        let mut opened = OPENED.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(fmu) = opened
            .iter()
            .find(|f| f.version == version && f.model_identifier == model_identifier)
        {
            return fmu.clone();
        }
        let dir = target_dir().join("fmu");
        let (archive, sub) = match version {
            Fmi::V2 => (dir.join(format!("{model_identifier}.fmu")), "fmi2"),
            Fmi::V3 => (
                dir.join("fmi3").join(format!("{model_identifier}.fmu")),
                "fmi3",
            ),
        };
        assert!(
            archive.is_file(),
            "{} is missing: run `cargo xtask fmus --all-platforms` first",
            archive.display()
        );
        let root = scratch().join("fmus").join(sub).join(model_identifier);
        let _ = std::fs::remove_dir_all(&root);
        let file = std::fs::File::open(&archive).unwrap();
        zip::ZipArchive::new(file)
            .and_then(|mut zip| zip.extract(&root))
            .unwrap_or_else(|e| panic!("unpacking {}: {e}", archive.display()));
        let xml = std::fs::read_to_string(root.join("modelDescription.xml")).unwrap();
        let (token, variables) = match version {
            Fmi::V2 => fmi2_variables(&xml),
            Fmi::V3 => fmi3_variables(&xml),
        };
        let fmu = Fmu {
            version,
            model_identifier: model_identifier.to_owned(),
            root,
            token,
            variables,
        };
        opened.push(fmu.clone());
        fmu
    }

    pub fn library(&self, platform: Platform) -> PathBuf {
        let folder = platform
            .folder(self.version)
            .unwrap_or_else(|| panic!("{:?} has no folder for {}", self.version, platform.name()));
        self.root.join("binaries").join(folder).join(format!(
            "{}.{}",
            self.model_identifier,
            platform.extension()
        ))
    }

    pub fn variable(&self, name: &str) -> Option<&Variable> {
        self.variables.iter().find(|v| v.name == name)
    }

    /// The (variable, element) pairs a scenario's name stands for: a scalar, an FMI 3.0
    /// array or its element `name[i]`, or the FMI 2.0 scalars `name[1..]` of a vector.
    fn elements(&self, name: &str) -> Vec<(&Variable, usize)> {
        if let Some(v) = self.variable(name) {
            return (0..v.len).map(|i| (v, i)).collect();
        }
        if let Some((base, index)) = name
            .strip_suffix(']')
            .and_then(|n| n.split_once('['))
            .and_then(|(b, i)| Some((b, i.parse::<usize>().ok()?)))
        {
            if let Some(v) = self.variable(base) {
                assert!(
                    index >= 1 && index <= v.len,
                    "{name}: no such element of {}",
                    self.model_identifier
                );
                return vec![(v, index - 1)];
            }
        }
        let scalars: Vec<_> = (1..)
            .map_while(|i| self.variable(&format!("{name}[{i}]")))
            .map(|v| (v, 0))
            .collect();
        assert!(
            !scalars.is_empty(),
            "{}: no variable {name}",
            self.model_identifier
        );
        scalars
    }

    pub fn outputs(&self) -> impl Iterator<Item = &Variable> {
        self.variables.iter().filter(|v| v.causality == "output")
    }
}

fn fmi2_variables(xml: &str) -> (String, Vec<Variable>) {
    let description = ModelDescription::from_xml(xml).unwrap_or_else(|e| panic!("{e}"));
    let variables = description
        .variables()
        .filter_map(|v| {
            let kind = match v.kind()? {
                VariableKind::Real => 'R',
                VariableKind::Integer => 'I',
                VariableKind::Enumeration => 'E',
                VariableKind::Boolean => 'B',
                VariableKind::String => return None,
            };
            let start = match v.start() {
                Some(StartValue::Real(x)) => x,
                Some(StartValue::Integer(i) | StartValue::Enumeration(i)) => f64::from(i),
                Some(StartValue::Boolean(b)) => f64::from(u8::from(b)),
                _ => 0.0,
            };
            Some(Variable {
                name: v.name.clone(),
                vr: v.value_reference,
                causality: format!("{:?}", v.causality_or_default()).to_ascii_lowercase(),
                kind,
                len: 1,
                start: vec![start],
            })
        })
        .collect();
    (description.guid, variables)
}

/// The attribute `name` of one XML start tag.
fn attribute(tag: &str, name: &str) -> Option<String> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let end = start + tag[start..].find('"')?;
    Some(
        tag[start..end]
            .replace("&quot;", "\"")
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&amp;", "&"),
    )
}

/// The variables of an FMI 3.0 description as fmi3-export writes it: one element per
/// variable, with a `Dimension` child for an array. Enough for our own FMUs, not a general
/// FMI 3.0 reader.
fn fmi3_variables(xml: &str) -> (String, Vec<Variable>) {
    let token = attribute(xml, "instantiationToken").expect("no instantiationToken");
    let start = xml.find("<ModelVariables>").expect("no ModelVariables");
    let end = xml.find("</ModelVariables>").expect("no </ModelVariables>");
    let body = &xml[start..end];
    let mut variables = Vec::new();
    let mut rest = body;
    while let Some(open) = rest.find('<') {
        rest = &rest[open + 1..];
        let element: String = rest
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric())
            .collect();
        let kind = match element.as_str() {
            "Float64" => 'R',
            "Int32" => 'I',
            "Int64" | "Enumeration" => 'E',
            "Boolean" => 'B',
            _ => continue,
        };
        let close = rest.find('>').expect("unterminated tag");
        let tag = format!(" {}", &rest[..close]);
        let len = if tag.ends_with('/') {
            1
        } else {
            let inner = &rest[close..rest.find(&format!("</{element}>")).expect("no end tag")];
            inner
                .find("<Dimension")
                .map(|d| {
                    attribute(&inner[d..], "start")
                        .and_then(|n| n.parse().ok())
                        .expect("a Dimension without a start")
                })
                .unwrap_or(1)
        };
        let start = match attribute(&tag, "start") {
            Some(text) => text
                .split_whitespace()
                .map(|x| match x {
                    "true" => 1.0,
                    "false" => 0.0,
                    x => x.parse().unwrap_or_else(|_| panic!("start value {x}")),
                })
                .collect(),
            None => vec![0.0; len],
        };
        variables.push(Variable {
            name: attribute(&tag, "name").expect("a variable without a name"),
            vr: attribute(&tag, "valueReference")
                .and_then(|v| v.parse().ok())
                .expect("a variable without a valueReference"),
            causality: attribute(&tag, "causality").unwrap_or_else(|| "local".into()),
            kind,
            len,
            start,
        });
    }
    (token, variables)
}

// ---- plans: what the master flies --------------------------------------------------------

#[derive(Debug, Clone, Copy)]
pub enum Source {
    /// The `slot`-th output value of unit `unit`.
    Output {
        unit: usize,
        slot: usize,
    },
    Keep(f64),
}

#[derive(Debug, Clone)]
pub struct UnitPlan {
    pub name: String,
    pub fmu: Fmu,
    /// Platform-independent: a resource location is passed as written.
    pub resources: Option<String>,
    pub instance_name: Option<String>,
    pub params: Vec<(char, u32, Vec<f64>)>,
    pub inputs: Vec<(char, u32, Vec<Source>)>,
}

#[derive(Debug, Clone)]
pub struct Plan {
    pub version: Fmi,
    pub step: f64,
    pub stop: f64,
    pub logging: bool,
    pub units: Vec<UnitPlan>,
}

fn bits(x: f64) -> String {
    format!("{:016x}", x.to_bits())
}

impl Plan {
    /// The plan file of tests/c/closed_loop_master.c for `platform`.
    pub fn text(&self, platform: Platform) -> String {
        let mut text = String::new();
        let version = match self.version {
            Fmi::V2 => 2,
            Fmi::V3 => 3,
        };
        let _ = writeln!(text, "fmi {version}");
        let _ = writeln!(text, "step {}", bits(self.step));
        let _ = writeln!(text, "stop {}", bits(self.stop));
        let _ = writeln!(text, "logging {}", u8::from(self.logging));
        for unit in &self.units {
            let _ = writeln!(text, "unit {}", unit.name);
            let _ = writeln!(
                text,
                "library {}",
                platform.path(&unit.fmu.library(platform))
            );
            let _ = writeln!(text, "token {}", unit.fmu.token);
            if let Some(r) = &unit.resources {
                let _ = writeln!(text, "resources {r}");
            }
            if let Some(n) = &unit.instance_name {
                let _ = writeln!(text, "instance {n}");
            }
            for (kind, vr, values) in &unit.params {
                let values: Vec<String> = values.iter().map(|&x| bits(x)).collect();
                let _ = writeln!(
                    text,
                    "param {kind} {vr} {} {}",
                    values.len(),
                    values.join(" ")
                );
            }
            for v in unit.fmu.outputs() {
                let _ = writeln!(text, "output {} {} {} {}", v.kind, v.vr, v.len, v.name);
            }
            for (kind, vr, sources) in &unit.inputs {
                let sources: Vec<String> = sources
                    .iter()
                    .map(|s| match s {
                        Source::Output { unit, slot } => format!("{unit}:{slot}"),
                        Source::Keep(x) => format!("={}", bits(*x)),
                    })
                    .collect();
                let _ = writeln!(
                    text,
                    "input {kind} {vr} {} {}",
                    sources.len(),
                    sources.join(" ")
                );
            }
        }
        text
    }

    /// A harness scenario (harness/scenarios/NAME.toml) as the harness connects it: the
    /// instances in the file's order (its Gauss-Seidel order), their parameters, every
    /// connection with vector names expanded.
    pub fn scenario(name: &str, version: Fmi) -> Plan {
        let path = workspace_root()
            .join("harness/scenarios")
            .join(format!("{name}.toml"));
        let text =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let table: toml::Table = text
            .parse()
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let number = |key: &str| {
            table[key]
                .as_float()
                .unwrap_or_else(|| panic!("{name}: {key}"))
        };
        assert_eq!(table["start_time"].as_float(), Some(0.0), "{name}");
        assert_eq!(
            table["ordering"].as_str(),
            Some("gauss-seidel"),
            "{name}: the master flies Gauss-Seidel only"
        );
        let instances = table["instance"].as_array().expect("no [[instance]]");
        let mut units: Vec<UnitPlan> = Vec::new();
        for instance in instances {
            let unit_name = instance["name"].as_str().unwrap().to_owned();
            let id = instance["fmu"]
                .as_str()
                .unwrap()
                .trim_end_matches(".fmu")
                .to_owned();
            let fmu = Fmu::open(version, &id);
            let mut arrays: HashMap<String, Vec<f64>> = HashMap::new();
            let mut order = Vec::new();
            if let Some(parameters) = instance.get("parameters").and_then(|p| p.as_table()) {
                for (key, value) in parameters {
                    let value = match value {
                        toml::Value::Float(x) => *x,
                        toml::Value::Integer(i) => *i as f64,
                        toml::Value::Boolean(b) => f64::from(u8::from(*b)),
                        other => panic!("{name}: {unit_name}.{key} = {other}"),
                    };
                    for (v, i) in fmu.elements(key) {
                        let values = arrays.entry(v.name.clone()).or_insert_with(|| {
                            order.push(v.name.clone());
                            v.start.clone()
                        });
                        values[i] = value;
                    }
                }
            }
            let params = order
                .iter()
                .map(|n| {
                    let v = fmu.variable(n).unwrap();
                    (v.kind, v.vr, arrays[n].clone())
                })
                .collect();
            units.push(UnitPlan {
                name: unit_name,
                fmu,
                resources: None,
                instance_name: None,
                params,
                inputs: Vec::new(),
            });
        }
        let index = |unit: &str| {
            units
                .iter()
                .position(|u| u.name == unit)
                .unwrap_or_else(|| panic!("{name}: no instance {unit}"))
        };
        // Per destination unit: its input variables in first-connected order, each with the
        // source of every element.
        let mut wiring: Vec<Vec<(String, Vec<Source>)>> = vec![Vec::new(); units.len()];
        for connection in table["connection"].as_array().expect("no [[connection]]") {
            let (from, to) = (
                connection["from"].as_str().unwrap(),
                connection["to"].as_str().unwrap(),
            );
            let (from_unit, from_var) = from.split_once('.').unwrap();
            let (to_unit, to_var) = to.split_once('.').unwrap();
            let (fu, tu) = (index(from_unit), index(to_unit));
            let slots: Vec<usize> = {
                let fmu = &units[fu].fmu;
                fmu.elements(from_var)
                    .into_iter()
                    .map(|(v, i)| slot_of(fmu, &v.name) + i)
                    .collect()
            };
            let targets: Vec<(String, usize, Vec<f64>)> = units[tu]
                .fmu
                .elements(to_var)
                .into_iter()
                .map(|(v, i)| (v.name.clone(), i, v.start.clone()))
                .collect();
            assert_eq!(slots.len(), targets.len(), "{name}: {from} -> {to}");
            for (slot, (variable, element, start)) in slots.into_iter().zip(targets) {
                let list = &mut wiring[tu];
                let entry = match list.iter().position(|(n, _)| *n == variable) {
                    Some(k) => &mut list[k],
                    None => {
                        list.push((variable, start.into_iter().map(Source::Keep).collect()));
                        list.last_mut().unwrap()
                    }
                };
                entry.1[element] = Source::Output { unit: fu, slot };
            }
        }
        for (unit, list) in units.iter_mut().zip(wiring) {
            unit.inputs = list
                .into_iter()
                .map(|(n, sources)| {
                    let v = unit.fmu.variable(&n).unwrap();
                    (v.kind, v.vr, sources)
                })
                .collect();
        }
        Plan {
            version,
            step: number("step_size"),
            stop: number("stop_time"),
            logging: false,
            units,
        }
    }
}

/// The first output slot of `variable` (outputs in declaration order, arrays element-wise).
fn slot_of(fmu: &Fmu, variable: &str) -> usize {
    let mut slot = 0;
    for v in fmu.outputs() {
        if v.name == variable {
            return slot;
        }
        slot += v.len;
    }
    panic!("{}: {variable} is not an output", fmu.model_identifier)
}

// ---- comparing two runs ------------------------------------------------------------------

/// The first line where `b` differs from `a`, in words: line, step, time, unit, variable and
/// both values; `None` when they are identical.
pub fn first_difference(a: &Run, b: &Run) -> Option<String> {
    let columns = columns(&a.out);
    let (la, lb): (Vec<&str>, Vec<&str>) = (a.lines().collect(), b.lines().collect());
    for (n, (x, y)) in la.iter().zip(&lb).enumerate() {
        if x == y {
            continue;
        }
        let (fx, fy): (Vec<&str>, Vec<&str>) = (x.split(' ').collect(), y.split(' ').collect());
        let at = format!(
            "line {} ({} against {})",
            n + 1,
            b.platform.name(),
            a.platform.name()
        );
        if fx.len() < 3 || fx.len() != fy.len() || fx[2] != fy[2] || fx[0] != fy[0] {
            return Some(format!("{at}:\n  {x}\n  {y}"));
        }
        let unit = fx[2];
        let names = columns.get(unit).cloned().unwrap_or_default();
        let time = value(fx[1]);
        if fx[1] != fy[1] {
            return Some(format!(
                "{at}: step {}, the time differs: {} against {}",
                fx[0], fy[1], fx[1]
            ));
        }
        let k = (3..fx.len()).find(|&k| fx[k] != fy[k]).unwrap();
        let (vx, vy) = (value(fx[k]), value(fy[k]));
        return Some(format!(
            "{at}: step {} (t = {time} s), {unit}.{}: {} ({vy:e}) against {} ({vx:e}), \
             difference {:e}",
            fx[0],
            names.get(k - 3).map_or("?", |s| s.as_str()),
            fy[k],
            fx[k],
            vy - vx
        ));
    }
    (la.len() != lb.len()).then(|| {
        format!(
            "{} has {} lines, {} has {}",
            a.platform.name(),
            la.len(),
            b.platform.name(),
            lb.len()
        )
    })
}

fn value(hex: &str) -> f64 {
    f64::from_bits(u64::from_str_radix(hex, 16).unwrap_or(0))
}

fn columns(out: &str) -> HashMap<String, Vec<String>> {
    out.lines()
        .filter_map(|l| l.strip_prefix("columns "))
        .map(|l| {
            let mut words = l.split(' ');
            let unit = words.next().unwrap().to_owned();
            (unit, words.map(str::to_owned).collect())
        })
        .collect()
}

/// Every variable that differs between the runs: its first differing step, on how many
/// rows it differs, the largest difference and the largest relative to `a`'s value (large
/// where that value is near zero), in the order of their first difference.
pub fn differences(a: &Run, b: &Run) -> Vec<String> {
    let columns = columns(&a.out);
    // unit.variable -> (first step, first time, rows, largest |difference|, relative)
    let mut found: HashMap<String, (u64, f64, usize, f64, f64)> = HashMap::new();
    for (x, y) in a.lines().zip(b.lines()) {
        if x == y || x.starts_with("columns") || x.starts_with("end") {
            continue;
        }
        let (fx, fy): (Vec<&str>, Vec<&str>) = (x.split(' ').collect(), y.split(' ').collect());
        if fx.len() != fy.len() || fx.len() < 3 {
            continue;
        }
        let step: u64 = fx[0].parse().unwrap_or(u64::MAX);
        for k in 3..fx.len() {
            if fx[k] == fy[k] {
                continue;
            }
            let name = format!(
                "{}.{}",
                fx[2],
                columns
                    .get(fx[2])
                    .and_then(|c| c.get(k - 3))
                    .map_or("?", |s| s.as_str())
            );
            let (vx, vy) = (value(fx[k]), value(fy[k]));
            let d = (vy - vx).abs();
            let r = d / vx.abs().max(f64::MIN_POSITIVE);
            let e = found
                .entry(name)
                .or_insert((step, value(fx[1]), 0, 0.0, 0.0));
            e.2 += 1;
            e.3 = e.3.max(d);
            e.4 = e.4.max(r);
        }
    }
    let mut list: Vec<_> = found.into_iter().collect();
    list.sort_by(|a, b| (a.1 .0, &a.0).cmp(&(b.1 .0, &b.0)));
    list.into_iter()
        .map(|(name, (step, t, rows, d, r))| {
            format!(
                "{name}: from step {step} (t = {t} s), on {rows} rows, largest difference \
                 {d:.3e} (relative {r:.1e})"
            )
        })
        .collect()
}

/// How long a closure took, for the reports.
pub fn timed<T>(f: impl FnOnce() -> T) -> (T, Duration) {
    let start = Instant::now();
    let t = f();
    (t, start.elapsed())
}
