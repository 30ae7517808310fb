//! The Debian packages the build and the tests need, installed before anything is built.
//!
//! A fresh Debian machine has cargo, gcc and Python but not the C libraries some crates bind
//! to. Rather than let the build fail deep inside a build script ("Unable to find libclang"),
//! each command checks its packages first: missing ones are installed with apt-get when we
//! are root or have password-less sudo; otherwise the command stops at once and prints the
//! exact command to run.
use anyhow::{bail, Result};
use std::process::{Command, Stdio};

/// One package and the reason we need it, printed when it is missing.
pub struct Package {
    pub name: &'static str,
    pub why: &'static str,
}

/// What `cargo xtask demo` needs: the harness draws PNG plots through fontconfig/FreeType.
const DEMO: &[Package] = &[
    Package {
        name: "pkg-config",
        why: "finds fontconfig for the plotting crate",
    },
    Package {
        name: "libfontconfig1-dev",
        why: "the harness's PNG plots render text through fontconfig",
    },
    Package {
        name: "fonts-dejavu-core",
        why: "a font for the plot labels",
    },
];

/// What `cargo xtask test` needs on top of [`DEMO`].
const TEST: &[Package] = &[
    Package {
        name: "libclang-dev",
        why:
            "bindgen in fmi-sys (the official FMI headers for the ABI check and the `fmi` importer)",
    },
    Package {
        name: "zip",
        why: "the FMU archive tests inspect archives with zip/unzip",
    },
    Package {
        name: "unzip",
        why: "the FMU archive tests inspect archives with zip/unzip",
    },
    Package {
        name: "valgrind",
        why: "leak and instruction-count checks",
    },
    Package {
        name: "binutils",
        why: "nm (exported-symbol check) and strip (library size)",
    },
    Package {
        name: "libtbb12",
        why: "Ecos (ecospy's libecosc.so links libtbb.so.12) for the SSP interop test",
    },
];

/// Needed only when the system Python cannot make a venv by itself (Debian splits
/// `venv`/`ensurepip` out of python3; a pyenv or python.org build has them).
const PYTHON_VENV: Package = Package {
    name: "python3-venv",
    why: "the pinned fmpy/libcosim/Ecos environment in .venv",
};

fn python_can_make_venvs() -> bool {
    Command::new("python3")
        .args(["-c", "import venv, ensurepip"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .map(|s| s.success())
        .unwrap_or(false)
}

/// Everything `cargo xtask test` needs.
pub fn for_test() -> Vec<&'static Package> {
    let mut all: Vec<&Package> = DEMO.iter().chain(TEST.iter()).collect();
    if !python_can_make_venvs() {
        all.push(&PYTHON_VENV);
    }
    all
}

/// Everything `cargo xtask demo` needs.
pub fn for_demo() -> Vec<&'static Package> {
    DEMO.iter().collect()
}

fn installed(name: &str) -> bool {
    Command::new("dpkg-query")
        .args(["-W", "-f=${Status}", name])
        .stderr(Stdio::null())
        .output()
        .map(|out| String::from_utf8_lossy(&out.stdout).contains("install ok installed"))
        .unwrap_or(false)
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|out| String::from_utf8_lossy(&out.stdout).trim() == "0")
        .unwrap_or(false)
}

/// `sudo -n true` succeeds only when sudo exists and needs no password.
fn has_passwordless_sudo() -> bool {
    Command::new("sudo")
        .args(["-n", "true"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .map(|s| s.success())
        .unwrap_or(false)
}

/// Install every missing package of `wanted`, or stop with the command that would.
pub fn ensure(wanted: &[&Package]) -> Result<()> {
    if !crate::workspace::on_path("dpkg-query") {
        println!("xtask: not a Debian system (no dpkg-query); assuming the packages are there");
        return Ok(());
    }
    let missing: Vec<&Package> = wanted
        .iter()
        .copied()
        .filter(|p| !installed(p.name))
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    let names: Vec<&str> = missing.iter().map(|p| p.name).collect();
    println!("xtask: missing Debian packages:");
    for p in &missing {
        println!("  {:<20} {}", p.name, p.why);
    }
    let prefix: &[&str] = if is_root() {
        &[]
    } else if has_passwordless_sudo() {
        &["sudo"]
    } else {
        bail!(
            "not root and no password-less sudo; install them with\n\n    sudo apt-get update && sudo apt-get install -y --no-install-recommends {}\n",
            names.join(" ")
        );
    };
    let apt = |args: &[&str]| -> Result<()> {
        let mut cmd = Command::new(prefix.first().copied().unwrap_or("apt-get"));
        if !prefix.is_empty() {
            cmd.arg("apt-get");
        }
        cmd.args(args).env("DEBIAN_FRONTEND", "noninteractive");
        crate::workspace::run(&mut cmd)
    };
    println!("xtask: installing {}", names.join(" "));
    apt(&["update", "-q"])?;
    let mut install = vec!["install", "-y", "-q", "--no-install-recommends"];
    install.extend(&names);
    apt(&install)?;
    let still: Vec<&str> = names.iter().copied().filter(|n| !installed(n)).collect();
    if !still.is_empty() {
        bail!(
            "apt-get finished but {} is still not installed",
            still.join(" ")
        );
    }
    Ok(())
}
