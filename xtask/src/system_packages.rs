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

/// What `cargo xtask demo` needs beyond cargo: nothing, since the figures carry their own
/// font (`report/fonts/`) and no crate of the demo binds a system library.
const DEMO: &[Package] = &[];

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
    Package {
        name: "chromium",
        why: "the report tests render report.html headless (harness/tests/report_browser.rs)",
    },
];

/// What `cargo xtask fmus --all-platforms` needs on top of the host build: Debian's second
/// Rust toolchain (rustup cannot add targets without its own servers), its aarch64 standard
/// library and std source, and a C toolchain per foreign target for linking.
const ALL_PLATFORMS: &[Package] = &[
    Package {
        name: "rustc-web",
        why: "Debian's rustc (/usr/bin/rustc), whose standard libraries the cross builds use",
    },
    Package {
        name: "cargo-web",
        why: "Debian's cargo (/usr/bin/cargo), matching that rustc, for -Z build-std",
    },
    Package {
        name: "libstd-rust-web-dev",
        why: "the host standard library of Debian's rustc (build scripts, proc macros)",
    },
    Package {
        name: "libstd-rust-web-dev:arm64",
        why: "the aarch64-unknown-linux-gnu standard library",
    },
    Package {
        name: "rust-web-src",
        why: "the standard library's source: Windows std is built from it (-Z build-std)",
    },
    Package {
        name: "gcc-aarch64-linux-gnu",
        why: "the linker for aarch64-unknown-linux-gnu",
    },
    Package {
        name: "libc6-dev-arm64-cross",
        why: "the aarch64 C library the linker links against",
    },
    Package {
        name: "gcc-mingw-w64-x86-64",
        why: "the linker, CRT and objdump for x86_64-pc-windows-gnu",
    },
];

/// What the platform tests of `cargo xtask test` run the foreign binaries with.
const PLATFORM_TESTS: &[Package] = &[
    Package {
        name: "qemu-user",
        why: "runs the aarch64 Linux test master and FMU binaries (qemu-aarch64)",
    },
    Package {
        name: "wine",
        why: "runs the Windows test master and FMU DLLs",
    },
    Package {
        name: "wine64",
        why: "the 64-bit Wine loader for the x86_64 Windows DLLs",
    },
];

/// The foreign dpkg architectures [`ALL_PLATFORMS`] installs packages of (`name:arch`).
const ALL_PLATFORMS_ARCHITECTURES: &[&str] = &["arm64"];

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

/// Everything the host-only checks need (`cargo xtask bench`).
pub fn for_test() -> Vec<&'static Package> {
    let mut all: Vec<&Package> = DEMO.iter().chain(TEST.iter()).collect();
    if !python_can_make_venvs() {
        all.push(&PYTHON_VENV);
    }
    all
}

/// Everything `cargo xtask test` needs (it builds and runs every platform), and the foreign
/// dpkg architectures its packages come from.
pub fn for_test_all_platforms() -> (Vec<&'static Package>, &'static [&'static str]) {
    let mut all = for_test();
    all.extend(ALL_PLATFORMS.iter().chain(PLATFORM_TESTS.iter()));
    (all, ALL_PLATFORMS_ARCHITECTURES)
}

/// Everything `cargo xtask fmus --all-platforms` needs beyond the host build, and the
/// foreign dpkg architectures its packages come from.
pub fn for_all_platforms() -> (Vec<&'static Package>, &'static [&'static str]) {
    (ALL_PLATFORMS.iter().collect(), ALL_PLATFORMS_ARCHITECTURES)
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

/// The architectures dpkg installs packages for: its own and the added foreign ones.
fn dpkg_architectures() -> Vec<String> {
    ["--print-architecture", "--print-foreign-architectures"]
        .iter()
        .filter_map(|flag| Command::new("dpkg").arg(flag).output().ok())
        .flat_map(|out| {
            String::from_utf8_lossy(&out.stdout)
                .split_whitespace()
                .map(str::to_owned)
                .collect::<Vec<_>>()
        })
        .collect()
}

/// The commands that add `architectures` to dpkg and install `names`, for a user to run.
fn manual_commands(architectures: &[&str], names: &[&str]) -> String {
    let mut steps: Vec<String> = architectures
        .iter()
        .map(|arch| format!("sudo dpkg --add-architecture {arch}"))
        .collect();
    steps.push("sudo apt-get update".into());
    if !names.is_empty() {
        steps.push(format!(
            "sudo apt-get install -y --no-install-recommends {}",
            names.join(" ")
        ));
    }
    steps.join(" && ")
}

/// Install every missing package of `wanted`, or stop with the command that would.
pub fn ensure(wanted: &[&Package]) -> Result<()> {
    ensure_with_architectures(wanted, &[])
}

/// As [`ensure`], first adding each of `architectures` (Debian names: `arm64`) that dpkg does
/// not know yet, so that `name:arch` packages of `wanted` can be installed.
pub fn ensure_with_architectures(wanted: &[&Package], architectures: &[&str]) -> Result<()> {
    if !crate::workspace::on_path("dpkg-query") {
        println!("xtask: not a Debian system (no dpkg-query); assuming the packages are there");
        return Ok(());
    }
    let known = dpkg_architectures();
    let new_architectures: Vec<&str> = architectures
        .iter()
        .copied()
        .filter(|arch| !known.iter().any(|k| k == arch))
        .collect();
    let missing: Vec<&Package> = wanted
        .iter()
        .copied()
        .filter(|p| !installed(p.name))
        .collect();
    if missing.is_empty() && new_architectures.is_empty() {
        return Ok(());
    }
    let names: Vec<&str> = missing.iter().map(|p| p.name).collect();
    for arch in &new_architectures {
        println!("xtask: dpkg does not install {arch} packages yet (dpkg --add-architecture)");
    }
    if !missing.is_empty() {
        println!("xtask: missing Debian packages:");
    }
    for p in &missing {
        println!("  {:<26} {}", p.name, p.why);
    }
    let prefix: &[&str] = if is_root() {
        &[]
    } else if has_passwordless_sudo() {
        &["sudo"]
    } else {
        bail!(
            "not root and no password-less sudo; install them with\n\n    {}\n",
            manual_commands(&new_architectures, &names)
        );
    };
    let privileged = |program: &str, args: &[&str]| -> Result<()> {
        let mut cmd = Command::new(prefix.first().copied().unwrap_or(program));
        if !prefix.is_empty() {
            cmd.arg(program);
        }
        cmd.args(args).env("DEBIAN_FRONTEND", "noninteractive");
        crate::workspace::run(&mut cmd)
    };
    for arch in &new_architectures {
        println!("xtask: adding the dpkg architecture {arch}");
        privileged("dpkg", &["--add-architecture", arch])?;
    }
    // Another apt-get (an unattended upgrade, a second checkout) may hold the lock: wait.
    let apt = |args: &[&str]| -> Result<()> {
        let mut all = vec!["-o", "DPkg::Lock::Timeout=600"];
        all.extend(args);
        privileged("apt-get", &all)
    };
    apt(&["update", "-q"])?;
    if names.is_empty() {
        return Ok(());
    }
    println!("xtask: installing {}", names.join(" "));
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_manual_commands_add_the_architecture_before_updating_and_installing() {
        assert_eq!(
            manual_commands(
                &["arm64"],
                &["gcc-aarch64-linux-gnu", "libstd-rust-web-dev:arm64"]
            ),
            "sudo dpkg --add-architecture arm64 && sudo apt-get update && sudo apt-get install \
             -y --no-install-recommends gcc-aarch64-linux-gnu libstd-rust-web-dev:arm64"
        );
        assert_eq!(
            manual_commands(&["arm64"], &[]),
            "sudo dpkg --add-architecture arm64 && sudo apt-get update"
        );
    }

    #[test]
    fn every_foreign_package_names_an_architecture_that_is_added() {
        let (packages, architectures) = for_all_platforms();
        for p in packages {
            if let Some((_, arch)) = p.name.split_once(':') {
                assert!(architectures.contains(&arch), "{}", p.name);
            }
        }
    }
}
