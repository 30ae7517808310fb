//! The Windows binaries of the `--all-platforms` FMUs as Windows masters call them, under
//! Wine, through tests/c/closed_loop_master.c compiled with x86_64-w64-mingw32-gcc:
//!
//! - the resource locations Windows masters pass (a `file:` URI with a drive letter and a
//!   percent-encoded space, one with backslashes; FMI 3.0's native path) are accepted and
//!   reach the FMU as written, and the flight is unchanged;
//! - an instance name in non-ASCII UTF-8 comes back to the logger byte for byte;
//! - a panic inside a model is caught at the C boundary: the call returns fmi2Fatal with a
//!   log line naming the panic, and the master lives on to free its instances (checked on
//!   the three platforms, with the test-only FMU of tests/panic-fmu, never packaged).
//!
//! That the DLLs export exactly the standard's functions is all_platforms.rs's
//! `every_binary_exports_exactly_the_standard_functions_and_needs_only_system_libraries`.
//!
//! Not in the default suite: it needs Wine and the cross toolchains.
//!
//!     cargo xtask fmus --all-platforms
//!     cargo test -p system-tests --test main windows_users:: -- --ignored
use crate::cross;

use cross::{first_difference, fly, require, run_ok, scratch, Fmu, Plan, Platform, UnitPlan};
use std::path::{Path, PathBuf};
use std::process::Command;
use system_tests::{target_dir, workspace_root, Fmi};

const WINDOWS: Platform = Platform::WindowsX86_64;

/// The log lines of a run whose status is above fmi2Warning / fmi3Warning.
fn errors(log: &str) -> Vec<&str> {
    log.lines()
        .filter(|l| matches!(l.split('|').nth(1), Some("2" | "3" | "4")))
        .collect()
}

/// A resource location as a function of the FMU's model identifier.
type Location = fn(&str) -> String;

/// The paper flight with every unit's resource location set by `location(model identifier)`.
fn paper_with(version: Fmi, location: impl Fn(&str) -> String) -> Plan {
    let mut plan = Plan::scenario("paper", version);
    for unit in &mut plan.units {
        unit.resources = Some(location(&unit.fmu.model_identifier));
    }
    plan
}

/// Where the FMU's own resources folder is, as a Windows master names it under Wine.
fn own_location(version: Fmi, id: &str) -> String {
    let root = Fmu::open(version, id).root;
    let native = WINDOWS.path(&root.join("resources"));
    match version {
        Fmi::V2 => format!("file:///{}", native.replace('\\', "/")),
        Fmi::V3 => format!("{native}\\"),
    }
}

#[test]
#[ignore = "needs `cargo xtask fmus --all-platforms` and Wine"]
fn windows_resource_locations_are_accepted_and_change_no_bit_of_the_flight() {
    let forms: [(Fmi, &str, Location); 4] = [
        (Fmi::V2, "fmi2-drive-uri", |id| {
            format!("file:///C:/Users/J%20Doe/{id}/resources")
        }),
        (Fmi::V2, "fmi2-backslash-uri", |_| {
            "file:///C:\\dir\\resources".to_owned()
        }),
        (Fmi::V2, "fmi2-short-uri", |id| {
            format!("file:/C:/Users/J%20Doe/{id}/resources")
        }),
        (Fmi::V3, "fmi3-drive-path", |id| {
            format!("C:\\Users\\J Doe\\{id}\\resources\\")
        }),
    ];
    for version in Fmi::ALL {
        let reference = fly(
            WINDOWS,
            &paper_with(version, |id| own_location(version, id)),
            &format!("resources-own-{version:?}").to_lowercase(),
        );
        reference.assert_clean("the paper flight with the FMU's own resource location");
        for (form_version, name, location) in forms {
            if form_version != version {
                continue;
            }
            let mut plan = paper_with(version, location);
            let run = fly(WINDOWS, &plan, &format!("resources-{name}"));
            run.assert_clean(name);
            assert!(
                errors(&run.log_text()).is_empty(),
                "{name}: {:?}",
                errors(&run.log_text())
            );
            if let Some(difference) = first_difference(&reference, &run) {
                panic!("{name} changed the flight: {difference}");
            }
            // The location reaches the FMU as written: its call trace quotes it.
            plan.logging = true;
            plan.stop = 2.0 * plan.step;
            let traced = fly(WINDOWS, &plan, &format!("resources-{name}-trace"));
            traced.assert_clean(name);
            let log = traced.log_text();
            for unit in &plan.units {
                let written = unit.resources.as_deref().unwrap();
                let argument = match version {
                    Fmi::V2 => format!("fmuResourceLocation=\"{written}\""),
                    Fmi::V3 => format!("resourcePath=\"{written}\""),
                };
                assert!(
                    log.contains(&argument),
                    "{name}: no trace with {argument} in\n{log}"
                );
            }
        }
    }
}

#[test]
#[ignore = "needs `cargo xtask fmus --all-platforms` and Wine"]
fn a_non_ascii_instance_name_reaches_the_logger_byte_for_byte() {
    let names = ["Landegerät-ü-月", "Pflanze-ß-😀"];
    for version in Fmi::ALL {
        let mut plan = Plan::scenario("paper", version);
        plan.logging = true;
        plan.stop = 2.0 * plan.step;
        for (unit, name) in plan.units.iter_mut().zip(names) {
            unit.instance_name = Some(name.to_owned());
        }
        for platform in [Platform::LinuxX86_64, WINDOWS] {
            let tag = format!("instance-name-{version:?}").to_lowercase();
            let run = fly(platform, &plan, &tag);
            run.assert_clean("non-ASCII instance names");
            let lines: Vec<&[u8]> = run
                .log
                .split(|&b| b == b'\n')
                .filter(|l| !l.is_empty())
                .collect();
            // FMI 2.0 hands the logger the instance name: every line must begin with one of
            // the two names, byte for byte. FMI 3.0's logger has no instance name (the
            // master's own unit name is printed there); its call trace quotes it.
            if version == Fmi::V2 {
                let strangers: Vec<String> = lines
                    .iter()
                    .filter(|l| {
                        !names
                            .iter()
                            .any(|n| l.starts_with(format!("{n}|").as_bytes()))
                    })
                    .map(|l| String::from_utf8_lossy(l).into_owned())
                    .collect();
                assert!(
                    strangers.is_empty(),
                    "{}: log lines without either instance name: {strangers:?}",
                    platform.name()
                );
            }
            for (unit, name) in plan.units.iter().zip(names) {
                let argument = format!("instanceName=\"{name}\"");
                let own = lines
                    .iter()
                    .filter(|l| version == Fmi::V3 || l.starts_with(format!("{name}|").as_bytes()))
                    .filter(|l| contains(l, argument.as_bytes()))
                    .count();
                assert!(
                    own > 0,
                    "{}: {version:?} {}: no log line with {argument}:\n{}",
                    platform.name(),
                    unit.name,
                    run.log_text()
                );
            }
        }
    }
}

fn contains(haystack: &[u8], needle: &[u8]) -> bool {
    haystack.windows(needle.len()).any(|w| w == needle)
}

// ---- the panic guard ---------------------------------------------------------------------

/// Builds the test-only panicking FMU for `platform` the way `cargo xtask fmus
/// --all-platforms` builds the shipped ones (xtask/src/cross.rs), in the same target
/// directories so that std and the export core are not built again; returns the library.
fn build_panicky(platform: Platform) -> PathBuf {
    let target = target_dir();
    let (mut cmd, library) = match platform {
        Platform::LinuxX86_64 => {
            let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
            let mut cmd = Command::new(cargo);
            cmd.env("CARGO_TARGET_DIR", &target)
                .args(["build", "--release", "--lib"]);
            (cmd, target.join("release/libpanicky.so"))
        }
        Platform::LinuxAarch64 | Platform::WindowsX86_64 => {
            let (triple, linker, package, file) = match platform {
                Platform::LinuxAarch64 => (
                    "aarch64-unknown-linux-gnu",
                    "aarch64-linux-gnu-gcc",
                    "gcc-aarch64-linux-gnu",
                    "libpanicky.so",
                ),
                _ => (
                    "x86_64-pc-windows-gnu",
                    "x86_64-w64-mingw32-gcc",
                    "gcc-mingw-w64-x86-64",
                    "panicky.dll",
                ),
            };
            require(linker, package);
            assert!(
                Path::new("/usr/bin/cargo").is_file(),
                "/usr/bin/cargo is missing: run `cargo xtask fmus --all-platforms`, which \
                 installs Debian's cargo-web and rustc-web"
            );
            let dir = target.join("cross").join(triple);
            let mut cmd = Command::new("/usr/bin/cargo");
            cmd.env("RUSTC", "/usr/bin/rustc")
                .env("CARGO_TARGET_DIR", &dir)
                .env(
                    format!(
                        "CARGO_TARGET_{}_LINKER",
                        triple.to_ascii_uppercase().replace('-', "_")
                    ),
                    linker,
                )
                .env_remove("RUSTUP_TOOLCHAIN")
                .env_remove("RUSTC_WRAPPER")
                .env_remove("RUSTC_WORKSPACE_WRAPPER")
                .args(["build", "--release", "--lib", "--target", triple]);
            if platform == WINDOWS {
                cmd.env("RUSTC_BOOTSTRAP", "1")
                    .args(["-Z", "build-std=std,panic_unwind"]);
            }
            (cmd, dir.join(triple).join("release").join(file))
        }
    };
    cmd.current_dir(workspace_root()).args(["-p", "panic-fmu"]);
    run_ok(
        &mut cmd,
        &format!("building panic-fmu for {}", platform.name()),
    );
    library
}

/// The panicking FMU as an unpacked FMU folder holding the library built for `platform`.
fn panicky(platform: Platform) -> Fmu {
    let library = build_panicky(platform);
    let root = scratch().join("fmus/panicky");
    let folder = platform.folder(Fmi::V2).unwrap_or("aarch64-linux");
    let extension = if platform == WINDOWS { "dll" } else { "so" };
    let binaries = root.join("binaries").join(folder);
    std::fs::create_dir_all(&binaries).unwrap();
    std::fs::copy(&library, binaries.join(format!("Panicky.{extension}"))).unwrap();
    Fmu {
        version: Fmi::V2,
        model_identifier: "Panicky".into(),
        root,
        token: panicky::guid(),
        variables: vec![
            cross::Variable {
                name: "panic_at".into(),
                vr: 0,
                causality: "parameter".into(),
                kind: 'R',
                len: 1,
                start: vec![f64::MAX],
            },
            cross::Variable {
                name: "time".into(),
                vr: 1,
                causality: "output".into(),
                kind: 'R',
                len: 1,
                start: vec![0.0],
            },
        ],
    }
}

#[test]
#[ignore = "needs the cross toolchains of `cargo xtask fmus --all-platforms`, qemu-user and Wine"]
fn a_panic_in_the_model_is_caught_at_the_c_boundary_on_every_platform() {
    for platform in Platform::ALL {
        let fmu = panicky(platform);
        // aarch64 Linux has no FMI 2.0 folder: the master loads the library by path anyway.
        let fmu = if platform == Platform::LinuxAarch64 {
            Fmu {
                version: Fmi::V3,
                ..fmu
            }
        } else {
            fmu
        };
        let plan = Plan {
            version: Fmi::V2,
            step: 0.1,
            stop: 1.0,
            logging: false,
            units: vec![UnitPlan {
                name: "panicky".into(),
                fmu,
                resources: None,
                instance_name: None,
                // Panics in the step from t = 0.5 (after five good ones).
                params: vec![('R', 0, vec![0.45])],
                inputs: Vec::new(),
            }],
        };
        let run = fly(platform, &plan, "panic");
        let what = format!("the panicking FMU on {}", platform.name());
        let lines: Vec<&str> = run.lines().collect();
        let rows = lines
            .iter()
            .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
            .count();
        assert_eq!(
            (run.exit_code, rows, &lines[lines.len().saturating_sub(2)..]),
            (Some(1), 6, &["end error panicky fmi2DoStep 4", "freed"][..]),
            "{what}: the step at t = 0.5 must return fmi2Fatal (4) and the master live on \
             to free the instance\nstderr: {}\nrun again: {}",
            run.stderr,
            run.command
        );
        let log = run.log_text();
        let expected = format!(
            "panicky|4|logStatusFatal|fmi2DoStep: internal error, instance unusable: {}",
            panicky::PANIC_MESSAGE
        );
        assert_eq!(
            log.lines().last(),
            Some(expected.as_str()),
            "{what}: log\n{log}"
        );
        eprintln!("{what}: {expected}");
    }
}
