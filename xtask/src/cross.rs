//! The foreign builds of `cargo xtask fmus --all-platforms`, with Debian's own Rust toolchain.
//!
//! rustup cannot add targets without its servers, but Debian ships a second toolchain
//! (`rustc-web`/`cargo-web`, installed as /usr/bin/rustc and /usr/bin/cargo) with an aarch64
//! standard library (`libstd-rust-web-dev:arm64`) and the standard library's source
//! (`rust-web-src`). So:
//!
//! - aarch64-unknown-linux-gnu is an ordinary cross build, linked by `aarch64-linux-gnu-gcc`;
//! - x86_64-pc-windows-gnu has no matching prebuilt std in Debian (only 1.63), so std is
//!   compiled from source with `-Z build-std` (allowed on a stable compiler by
//!   `RUSTC_BOOTSTRAP=1`), linked by `x86_64-w64-mingw32-gcc`.
//!
//! rustup's proxies come first on PATH, so both programs are named by absolute path. Each
//! target has its own target directory (`<target>/cross/<triple>`): two compilers in one
//! directory would keep two copies of every host artifact side by side, and two targets in
//! one would rebuild the shared host artifacts (proc macros, build scripts) at every switch,
//! since `RUSTC_BOOTSTRAP`, which only the Windows build sets, changes what some build
//! scripts detect. So std (Windows) and every dependency are built once per target.
use crate::workspace::{self, Workspace};
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Debian's cargo and rustc (packages cargo-web, rustc-web).
const DEBIAN_CARGO: &str = "/usr/bin/cargo";
const DEBIAN_RUSTC: &str = "/usr/bin/rustc";

/// A foreign target of `--all-platforms` and how it is built.
pub struct CrossTarget {
    pub triple: &'static str,
    /// The C compiler that links the cdylib.
    linker: &'static str,
    /// The binutils `strip` that knows the target's object format.
    pub strip: &'static str,
    /// Build std from source: Debian has no std of the toolchain's version for the target.
    build_std: bool,
}

/// The foreign targets every `--all-platforms` FMU carries besides the host's binaries.
pub const TARGETS: [CrossTarget; 2] = [
    CrossTarget {
        triple: "aarch64-unknown-linux-gnu",
        linker: "aarch64-linux-gnu-gcc",
        strip: "aarch64-linux-gnu-strip",
        build_std: false,
    },
    CrossTarget {
        triple: "x86_64-pc-windows-gnu",
        linker: "x86_64-w64-mingw32-gcc",
        strip: "x86_64-w64-mingw32-strip",
        build_std: true,
    },
];

/// The target directory of the cross build for `target`.
pub fn target_dir(ws: &Workspace, target: &CrossTarget) -> PathBuf {
    ws.target_dir.join("cross").join(target.triple)
}

/// Where the build of `target` puts its release libraries.
pub fn release_dir(ws: &Workspace, target: &CrossTarget) -> PathBuf {
    target_dir(ws, target).join(target.triple).join("release")
}

/// The `CARGO_TARGET_<TRIPLE>_LINKER` variable of a triple.
fn linker_variable(triple: &str) -> String {
    format!(
        "CARGO_TARGET_{}_LINKER",
        triple.to_ascii_uppercase().replace(['-', '.'], "_")
    )
}

/// Checks that Debian's toolchain and `target`'s linker are there, with the reason when not.
fn check_tools(target: &CrossTarget) -> Result<()> {
    for program in [DEBIAN_CARGO, DEBIAN_RUSTC] {
        if !Path::new(program).is_file() {
            bail!("{program} is missing (Debian packages rustc-web, cargo-web)");
        }
    }
    if !workspace::on_path(target.linker) {
        bail!(
            "{} (the linker for {}) is not on PATH",
            target.linker,
            target.triple
        );
    }
    if target.build_std {
        let sysroot = workspace::output(Command::new(DEBIAN_RUSTC).args(["--print", "sysroot"]))?;
        let library = Path::new(sysroot.trim()).join("lib/rustlib/src/rust/library");
        if !library.join("std").is_dir() {
            bail!(
                "the standard library's source is not at {} (Debian package rust-web-src); \
                 {} builds std from it",
                library.display(),
                target.triple
            );
        }
    }
    Ok(())
}

/// What a cross build makes: the FMU crates' libraries, or one program of one package.
#[derive(Debug, Clone, Copy)]
pub enum Artifact<'a> {
    Libraries(&'a [&'a str]),
    Program { package: &'a str, bin: &'a str },
}

/// The release `cargo build` of `artifact` for `target` with Debian's toolchain.
pub fn artifact_command(ws: &Workspace, target: &CrossTarget, artifact: Artifact) -> Command {
    let mut cmd = Command::new(DEBIAN_CARGO);
    cmd.current_dir(&ws.root)
        .env("RUSTC", DEBIAN_RUSTC)
        .env("CARGO_TARGET_DIR", target_dir(ws, target))
        .env(linker_variable(target.triple), target.linker)
        // Set by rustup's proxy for `cargo xtask`; they would steer nothing here, but a
        // rustc wrapper or a rustup toolchain override must not reach Debian's cargo.
        .env_remove("RUSTUP_TOOLCHAIN")
        .env_remove("RUSTC_WRAPPER")
        .env_remove("RUSTC_WORKSPACE_WRAPPER")
        .args(["build", "--release", "--target", target.triple]);
    if target.build_std {
        cmd.env("RUSTC_BOOTSTRAP", "1")
            .args(["-Z", "build-std=std,panic_unwind"]);
    }
    match artifact {
        Artifact::Libraries(packages) => {
            cmd.arg("--lib");
            for package in packages {
                cmd.args(["-p", package]);
            }
        }
        Artifact::Program { package, bin } => {
            cmd.args(["-p", package, "--bin", bin]);
        }
    }
    cmd
}

/// Builds `packages` for `target`; returns where the libraries are.
pub fn build(ws: &Workspace, target: &CrossTarget, packages: &[&str]) -> Result<PathBuf> {
    build_artifact(ws, target, Artifact::Libraries(packages))
}

/// Builds `artifact` for `target`; returns the directory it is in.
pub fn build_artifact(ws: &Workspace, target: &CrossTarget, artifact: Artifact) -> Result<PathBuf> {
    check_tools(target).with_context(|| format!("cannot build for {}", target.triple))?;
    workspace::run(&mut artifact_command(ws, target, artifact))
        .with_context(|| format!("building for {} with Debian's Rust", target.triple))?;
    Ok(release_dir(ws, target))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::platform::{FmiVersion, Platform};

    #[test]
    fn linker_variables_are_cargos_spelling() {
        assert_eq!(
            linker_variable("aarch64-unknown-linux-gnu"),
            "CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER"
        );
        assert_eq!(
            linker_variable("x86_64-pc-windows-gnu"),
            "CARGO_TARGET_X86_64_PC_WINDOWS_GNU_LINKER"
        );
    }

    #[test]
    fn every_target_has_an_fmi3_folder_and_only_aarch64_lacks_an_fmi2_one() {
        let folders: Vec<_> = TARGETS
            .iter()
            .map(|t| {
                let p = Platform::from_triple(t.triple).unwrap();
                (
                    p.folder(FmiVersion::V2).ok(),
                    p.folder(FmiVersion::V3).unwrap(),
                )
            })
            .collect();
        assert_eq!(
            folders,
            [
                (None, "aarch64-linux".to_owned()),
                (Some("win64".to_owned()), "x86_64-windows".to_owned())
            ]
        );
    }

    #[test]
    fn only_windows_builds_std_and_the_command_names_debians_programs() {
        let ws = Workspace {
            root: "/ws".into(),
            target_dir: "/ws/target".into(),
        };
        let windows = workspace::describe(&artifact_command(
            &ws,
            &TARGETS[1],
            Artifact::Libraries(&["fmu-plant"]),
        ));
        assert_eq!(
            windows,
            "/usr/bin/cargo build --release --target x86_64-pc-windows-gnu \
             -Z build-std=std,panic_unwind --lib -p fmu-plant"
        );
        let harness = Artifact::Program {
            package: "harness",
            bin: "harness",
        };
        assert_eq!(
            workspace::describe(&artifact_command(&ws, &TARGETS[0], harness)),
            "/usr/bin/cargo build --release --target aarch64-unknown-linux-gnu -p harness \
             --bin harness"
        );
        let arm = workspace::describe(&artifact_command(
            &ws,
            &TARGETS[0],
            Artifact::Libraries(&["fmu-plant"]),
        ));
        assert!(!arm.contains("build-std"), "{arm}");
        assert_eq!(
            release_dir(&ws, &TARGETS[0]),
            Path::new(
                "/ws/target/cross/aarch64-unknown-linux-gnu/aarch64-unknown-linux-gnu/release"
            )
        );
    }
}
