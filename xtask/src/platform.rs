//! Rust target triples to the FMI standard's binary folders, and the merge of FMUs that
//! carry binaries for different platforms into one FMU.
//!
//! FMI 2.0 names a folder by system and pointer width (`linux64`, `win64`, `darwin64`, ...);
//! FMI 3.0 by `<architecture>-<system>` (`x86_64-linux`, `aarch64-darwin`, ...). Only Linux
//! x86_64 can be built on the development machine; the mapping and the merge are tested here
//! without foreign binaries.
use crate::fmu_zip::Entry;
use anyhow::{bail, Context, Result};
use std::collections::BTreeMap;
use std::io::Read;

/// The FMI version whose folder naming applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FmiVersion {
    V2,
    V3,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum System {
    Linux,
    Windows,
    Darwin,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Architecture {
    X86,
    X86_64,
    Aarch32,
    Aarch64,
}

/// A Rust target the FMUs can be built for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Platform {
    pub triple: String,
    system: System,
    architecture: Architecture,
}

impl Platform {
    /// Parses `<arch>-<vendor>-<system>[-<abi>]` as rustc spells it.
    pub fn from_triple(triple: &str) -> Result<Self> {
        let parts: Vec<&str> = triple.split('-').collect();
        if parts.len() < 3 {
            bail!("{triple:?} is not a Rust target triple (<arch>-<vendor>-<system>[-<abi>])");
        }
        let architecture = match parts[0] {
            "x86_64" => Architecture::X86_64,
            "i586" | "i686" => Architecture::X86,
            "aarch64" | "arm64" => Architecture::Aarch64,
            arch if arch.starts_with("armv7") || arch.starts_with("thumbv7") || arch == "arm" => {
                Architecture::Aarch32
            }
            other => bail!(
                "target {triple:?}: architecture {other:?} has no FMI platform folder \
                 (supported: x86_64, i686, aarch64, armv7)"
            ),
        };
        let system = match parts[2] {
            "linux" => System::Linux,
            "windows" => System::Windows,
            "darwin" => System::Darwin,
            other => bail!(
                "target {triple:?}: system {other:?} has no FMI platform folder \
                 (supported: linux, windows, darwin)"
            ),
        };
        Ok(Self {
            triple: triple.to_owned(),
            system,
            architecture,
        })
    }

    /// The platform xtask itself runs on: what `cargo build` without `--target` produces.
    pub fn host() -> Result<Self> {
        let arch = std::env::consts::ARCH;
        let triple = match std::env::consts::OS {
            "linux" => format!("{arch}-unknown-linux-gnu"),
            "windows" => format!("{arch}-pc-windows-msvc"),
            "macos" => format!("{arch}-apple-darwin"),
            other => bail!("the host system {other:?} has no FMI platform folder"),
        };
        Self::from_triple(&triple)
    }

    /// The folder under `binaries/` for this platform in an FMU of `version`.
    pub fn folder(&self, version: FmiVersion) -> Result<String> {
        match version {
            FmiVersion::V2 => self.fmi2_folder().map(str::to_owned),
            FmiVersion::V3 => Ok(self.fmi3_folder()),
        }
    }

    fn fmi2_folder(&self) -> Result<&'static str> {
        use {Architecture::*, System::*};
        Ok(match (self.system, self.architecture) {
            (Linux, X86_64) => "linux64",
            (Linux, X86) => "linux32",
            (Windows, X86_64) => "win64",
            (Windows, X86) => "win32",
            // FMI 2.0 predates Apple silicon; importers (fmpy among them) look in darwin64 on
            // both Mac architectures, so the two cannot share one FMI 2.0 FMU (a merge of
            // both refuses the clash; a universal binary would be needed).
            (Darwin, X86_64 | Aarch64) => "darwin64",
            _ => bail!(
                "target {:?}: FMI 2.0 defines no binaries folder for this platform \
                 (only linux32/64, win32/64, darwin64); package it as FMI 3.0",
                self.triple
            ),
        })
    }

    fn fmi3_folder(&self) -> String {
        let arch = match self.architecture {
            Architecture::X86 => "x86",
            Architecture::X86_64 => "x86_64",
            Architecture::Aarch32 => "aarch32",
            Architecture::Aarch64 => "aarch64",
        };
        let system = match self.system {
            System::Linux => "linux",
            System::Windows => "windows",
            System::Darwin => "darwin",
        };
        format!("{arch}-{system}")
    }

    /// The file cargo writes for a cdylib named `lib_name` on this platform.
    pub fn cargo_library_file(&self, lib_name: &str) -> String {
        match self.system {
            System::Linux => format!("lib{lib_name}.so"),
            System::Windows => format!("{lib_name}.dll"),
            System::Darwin => format!("lib{lib_name}.dylib"),
        }
    }

    /// The binary's name inside the FMU: the model identifier with the system's extension.
    pub fn fmu_binary_file(&self, model_identifier: &str) -> String {
        let extension = match self.system {
            System::Linux => "so",
            System::Windows => "dll",
            System::Darwin => "dylib",
        };
        format!("{model_identifier}.{extension}")
    }
}

/// The entries of an FMU archive, by path (directory entries dropped).
fn read_entries(name: &str, bytes: &[u8]) -> Result<BTreeMap<String, Entry>> {
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes))
        .with_context(|| format!("{name} is not a zip archive"))?;
    let mut entries = BTreeMap::new();
    for i in 0..zip.len() {
        let mut file = zip.by_index(i)?;
        if file.is_dir() {
            continue;
        }
        let path = file.name().to_owned();
        let unix_mode = file.unix_mode().map_or(0o644, |m| m & 0o777);
        let mut contents = Vec::new();
        file.read_to_end(&mut contents)
            .with_context(|| format!("cannot read {path} in {name}"))?;
        entries.insert(
            path.clone(),
            Entry {
                path,
                bytes: contents,
                unix_mode,
            },
        );
    }
    Ok(entries)
}

/// Merges FMUs of one model built for different platforms: the union of their `binaries/`
/// folders, everything else required to be identical (the same model description and
/// documentation). Every conflict is reported, not only the first. `fmus` are (name, bytes).
pub fn merge(fmus: &[(String, Vec<u8>)]) -> Result<Vec<u8>> {
    let Some(((first_name, first), rest)) = fmus.split_first() else {
        bail!("nothing to merge: no FMU given");
    };
    let mut merged = read_entries(first_name, first)?;
    let mut origin: BTreeMap<String, String> = merged
        .keys()
        .map(|path| (path.clone(), first_name.clone()))
        .collect();
    let mut problems = Vec::new();
    for (name, bytes) in rest {
        let entries = read_entries(name, bytes)?;
        for path in merged.keys() {
            if !path.starts_with("binaries/") && !entries.contains_key(path) {
                problems.push(format!("{path} is in {} but not in {name}", origin[path]));
            }
        }
        for (path, entry) in entries {
            match merged.get(&path) {
                None if path.starts_with("binaries/") => {
                    origin.insert(path.clone(), name.clone());
                    merged.insert(path, entry);
                }
                None => problems.push(format!("{path} is in {name} but not in {}", first_name)),
                Some(existing) if existing.bytes != entry.bytes => problems.push(format!(
                    "{path} differs between {} and {name}{}",
                    origin[&path],
                    if path.starts_with("binaries/") {
                        " (two builds for the same platform folder)"
                    } else {
                        ""
                    }
                )),
                Some(_) => {}
            }
        }
    }
    if !problems.is_empty() {
        bail!("cannot merge the FMUs:\n  {}", problems.join("\n  "));
    }
    crate::fmu_zip::archive(merged.into_values().collect())
}

/// `cargo xtask merge-fmus --out OUT IN...`: [`merge`] on files.
pub fn merge_files(out: &std::path::Path, inputs: &[std::path::PathBuf]) -> Result<()> {
    let mut fmus = Vec::new();
    let mut problems = Vec::new();
    for path in inputs {
        match std::fs::read(path) {
            Ok(bytes) => fmus.push((path.display().to_string(), bytes)),
            Err(error) => problems.push(format!("cannot read {}: {error}", path.display())),
        }
    }
    if !problems.is_empty() {
        bail!("{}", problems.join("\n"));
    }
    let merged = merge(&fmus)?;
    std::fs::write(out, merged).with_context(|| format!("cannot write {}", out.display()))?;
    println!("xtask merge-fmus: wrote {}", out.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmu_zip::archive;

    fn folders(triple: &str) -> (Result<String>, String) {
        let p = Platform::from_triple(triple).unwrap();
        (p.folder(FmiVersion::V2), p.folder(FmiVersion::V3).unwrap())
    }

    #[test]
    fn triples_map_to_the_folders_the_standards_name() {
        for (triple, fmi2, fmi3) in [
            ("x86_64-unknown-linux-gnu", "linux64", "x86_64-linux"),
            ("x86_64-unknown-linux-musl", "linux64", "x86_64-linux"),
            ("i686-unknown-linux-gnu", "linux32", "x86-linux"),
            ("x86_64-pc-windows-msvc", "win64", "x86_64-windows"),
            ("x86_64-pc-windows-gnu", "win64", "x86_64-windows"),
            ("i686-pc-windows-msvc", "win32", "x86-windows"),
            ("x86_64-apple-darwin", "darwin64", "x86_64-darwin"),
            ("aarch64-apple-darwin", "darwin64", "aarch64-darwin"),
        ] {
            let (v2, v3) = folders(triple);
            assert_eq!(v2.unwrap(), fmi2, "{triple}");
            assert_eq!(v3, fmi3, "{triple}");
        }
    }

    #[test]
    fn platforms_without_an_fmi2_folder_are_refused_for_fmi2_only() {
        for (triple, fmi3) in [
            ("aarch64-unknown-linux-gnu", "aarch64-linux"),
            ("armv7-unknown-linux-gnueabihf", "aarch32-linux"),
            ("aarch64-pc-windows-msvc", "aarch64-windows"),
        ] {
            let (v2, v3) = folders(triple);
            let message = v2.unwrap_err().to_string();
            assert!(
                message.contains(triple) && message.contains("FMI 3.0"),
                "{message}"
            );
            assert_eq!(v3, fmi3);
        }
    }

    #[test]
    fn unknown_triples_are_refused_naming_the_part_that_is_wrong() {
        for (triple, part) in [
            ("x86_64", "not a Rust target triple"),
            ("riscv64gc-unknown-linux-gnu", "\"riscv64gc\""),
            ("wasm32-unknown-unknown", "\"wasm32\""),
            ("x86_64-unknown-freebsd", "\"freebsd\""),
        ] {
            let message = Platform::from_triple(triple).unwrap_err().to_string();
            assert!(message.contains(part), "{triple}: {message}");
        }
    }

    #[test]
    fn library_names_follow_each_system() {
        let linux = Platform::from_triple("x86_64-unknown-linux-gnu").unwrap();
        let windows = Platform::from_triple("x86_64-pc-windows-msvc").unwrap();
        let mac = Platform::from_triple("aarch64-apple-darwin").unwrap();
        assert_eq!(linux.cargo_library_file("fmu_plant"), "libfmu_plant.so");
        assert_eq!(windows.cargo_library_file("fmu_plant"), "fmu_plant.dll");
        assert_eq!(mac.cargo_library_file("fmu_plant"), "libfmu_plant.dylib");
        assert_eq!(windows.fmu_binary_file("LanderPlant"), "LanderPlant.dll");
        assert_eq!(mac.fmu_binary_file("LanderPlant"), "LanderPlant.dylib");
    }

    #[test]
    fn the_host_is_a_platform_with_both_folders() {
        let host = Platform::host().unwrap();
        assert!(host.folder(FmiVersion::V3).is_ok());
    }

    fn fmu(binary_path: &str, binary: &[u8], description: &[u8]) -> Vec<u8> {
        archive(vec![
            Entry::file("modelDescription.xml", description.to_vec()),
            Entry::file("documentation/index.html", b"<html/>".to_vec()),
            Entry::executable(binary_path, binary.to_vec()),
        ])
        .unwrap()
    }

    #[test]
    fn merge_unions_the_binaries_and_keeps_the_rest() {
        // GIVEN the real-looking Linux FMU and one with a fake Windows binary
        let linux = fmu("binaries/x86_64-linux/M.so", b"\x7fELF linux", b"<fmi/>");
        let windows = fmu("binaries/x86_64-windows/M.dll", b"MZ windows", b"<fmi/>");
        // WHEN merged
        let merged = merge(&[("linux.fmu".into(), linux), ("win.fmu".into(), windows)]).unwrap();
        // THEN both binaries are there with their modes, and the shared files once
        let entries = read_entries("merged", &merged).unwrap();
        let paths: Vec<_> = entries.keys().map(String::as_str).collect();
        assert_eq!(
            paths,
            [
                "binaries/x86_64-linux/M.so",
                "binaries/x86_64-windows/M.dll",
                "documentation/index.html",
                "modelDescription.xml"
            ]
        );
        assert_eq!(
            entries["binaries/x86_64-windows/M.dll"].bytes,
            b"MZ windows"
        );
        assert_eq!(entries["binaries/x86_64-windows/M.dll"].unix_mode, 0o755);
        assert_eq!(
            entries["binaries/x86_64-linux/M.so"].bytes,
            b"\x7fELF linux"
        );
        assert_eq!(entries["modelDescription.xml"].bytes, b"<fmi/>");
    }

    #[test]
    fn merge_refuses_different_models_and_clashing_binaries_listing_every_problem() {
        let a = fmu("binaries/darwin64/M.dylib", b"x86_64 build", b"<fmi a/>");
        let b = fmu("binaries/darwin64/M.dylib", b"arm64 build", b"<fmi b/>");
        let message = merge(&[("a.fmu".into(), a), ("b.fmu".into(), b)])
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("modelDescription.xml differs between a.fmu and b.fmu"),
            "{message}"
        );
        assert!(
            message.contains("binaries/darwin64/M.dylib differs")
                && message.contains("same platform"),
            "{message}"
        );
    }

    #[test]
    fn merge_refuses_a_missing_shared_file_and_an_empty_list_and_garbage() {
        let full = fmu("binaries/linux64/M.so", b"so", b"<fmi/>");
        let bare = archive(vec![
            Entry::file("modelDescription.xml", b"<fmi/>".to_vec()),
            Entry::executable("binaries/win64/M.dll", b"dll".to_vec()),
        ])
        .unwrap();
        let message = merge(&[("full.fmu".into(), full.clone()), ("bare.fmu".into(), bare)])
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("documentation/index.html is in full.fmu but not in bare.fmu"),
            "{message}"
        );
        assert!(merge(&[]).is_err());
        let garbage = merge(&[
            ("x.fmu".into(), full),
            ("junk.fmu".into(), b"junk".to_vec()),
        ]);
        assert!(garbage.unwrap_err().to_string().contains("junk.fmu"));
    }

    #[test]
    fn merging_one_fmu_gives_the_same_archive() {
        let one = fmu("binaries/linux64/M.so", b"so", b"<fmi/>");
        assert_eq!(merge(&[("one.fmu".into(), one.clone())]).unwrap(), one);
    }
}
