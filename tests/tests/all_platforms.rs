//! The multi-platform FMUs of `cargo xtask fmus --all-platforms` (target/fmu),
//! checked the way an importer on each platform sees them: the binaries folders each
//! standard names, the object format and architecture of every binary, fmpy's validation
//! and its list of supported platforms, and the exports and imports of every library.
//!
//! Not in the default suite (`#[ignore]`): the cross builds need Debian's second Rust
//! toolchain and two cross compilers (the packages xtask installs) and take minutes cold,
//! and the system tests never build anything themselves. Run them with
//!
//!     cargo xtask fmus --all-platforms
//!     cargo test -p system-tests --test main all_platforms:: -- --ignored
//!
//! A missing FMU or tool fails these tests; nothing is skipped.
use crate::exports;

use exports::{dynamic_symbols, expected_exports};
use fmi_abi::unpack::Unpacked;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;
use system_tests::{fmu_crates, target_dir, workspace_root, Fmi, FmuCrate};

/// An object format and machine a binary must have.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Object {
    ElfX86_64,
    ElfAarch64,
    PeX86_64,
}

/// The binaries folders of an `--all-platforms` FMU of each version: FMI 2.0 names no
/// folder for aarch64 Linux.
fn platforms(version: Fmi) -> &'static [(&'static str, &'static str, Object)] {
    match version {
        Fmi::V2 => &[
            ("linux64", "so", Object::ElfX86_64),
            ("win64", "dll", Object::PeX86_64),
        ],
        Fmi::V3 => &[
            ("x86_64-linux", "so", Object::ElfX86_64),
            ("aarch64-linux", "so", Object::ElfAarch64),
            ("x86_64-windows", "dll", Object::PeX86_64),
        ],
    }
}

fn fmu_path(version: Fmi, model_identifier: &str) -> PathBuf {
    let dir = target_dir().join("fmu");
    let path = match version {
        Fmi::V2 => dir.join(format!("{model_identifier}.fmu")),
        Fmi::V3 => dir.join("fmi3").join(format!("{model_identifier}.fmu")),
    };
    assert!(
        path.is_file(),
        "{} is missing: run `cargo xtask fmus --all-platforms` first",
        path.display()
    );
    path
}

/// Every (FMU crate, version) that is packaged, with the path of its multi-platform FMU.
fn packaged() -> Vec<(FmuCrate, Fmi, PathBuf)> {
    let mut all = Vec::new();
    for fmu in fmu_crates() {
        for version in Fmi::ALL {
            if fmu.ships(version) {
                let path = fmu_path(version, &fmu.model_identifier);
                all.push((fmu.clone(), version, path));
            }
        }
    }
    assert!(!all.is_empty(), "the metadata lists no packaged FMU");
    all
}

/// The object format and machine of a binary, from its header.
fn object_of(bytes: &[u8]) -> Option<Object> {
    if bytes.starts_with(b"\x7fELF") && bytes.len() > 20 {
        return match u16::from_le_bytes([bytes[18], bytes[19]]) {
            0x3e => Some(Object::ElfX86_64),
            0xb7 => Some(Object::ElfAarch64),
            _ => None,
        };
    }
    if bytes.starts_with(b"MZ") && bytes.len() > 0x40 {
        let pe = u32::from_le_bytes(bytes[0x3c..0x40].try_into().unwrap()) as usize;
        let header = bytes.get(pe..pe + 6)?;
        if &header[..4] == b"PE\0\0" && u16::from_le_bytes([header[4], header[5]]) == 0x8664 {
            return Some(Object::PeX86_64);
        }
    }
    None
}

/// The folders under `binaries/` of an unpacked FMU.
fn binaries_folders(root: &Path) -> BTreeSet<String> {
    std::fs::read_dir(root.join("binaries"))
        .unwrap_or_else(|e| panic!("no binaries/ in {}: {e}", root.display()))
        .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
#[ignore = "needs `cargo xtask fmus --all-platforms` (Debian's cross toolchains)"]
fn every_fmu_carries_a_binary_for_each_platform_folder_of_its_standard() {
    for (fmu, version, path) in packaged() {
        let id = &fmu.model_identifier;
        let unpacked = Unpacked::open(&path).unwrap_or_else(|e| panic!("{e}"));
        let expected: BTreeSet<String> = platforms(version)
            .iter()
            .map(|(folder, _, _)| folder.to_string())
            .collect();
        assert_eq!(
            binaries_folders(unpacked.root()),
            expected,
            "{version} {id}"
        );
        for (folder, extension, object) in platforms(version) {
            let binary = unpacked
                .root()
                .join("binaries")
                .join(folder)
                .join(format!("{id}.{extension}"));
            let bytes = std::fs::read(&binary)
                .unwrap_or_else(|e| panic!("{version} {id}: {}: {e}", binary.display()));
            assert_eq!(
                object_of(&bytes),
                Some(*object),
                "{version} {id}: binaries/{folder}"
            );
        }
    }
}

fn venv_python() -> PathBuf {
    let python = workspace_root().join(".venv/bin/python");
    assert!(
        python.is_file(),
        "{} is missing: run `cargo xtask python-env`",
        python.display()
    );
    python
}

#[test]
#[ignore = "needs `cargo xtask fmus --all-platforms` (Debian's cross toolchains)"]
fn fmpy_validates_every_fmu_and_lists_every_platform() {
    let all = packaged();
    let paths: Vec<&PathBuf> = all.iter().map(|(_, _, path)| path).collect();
    let script = workspace_root().join("tests/python/fmpy_validate.py");
    let output = Command::new(venv_python())
        .arg(&script)
        .args(&paths)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "fmpy_validate.py failed:\n{stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // fmpy's own reading of the binaries folders: the platforms it would load on.
    let listing = Command::new(venv_python())
        .args([
            "-c",
            "import sys\nfrom fmpy import supported_platforms\nfor p in sys.argv[1:]:\n    \
             print(' '.join(sorted(supported_platforms(p))))",
        ])
        .args(&paths)
        .output()
        .unwrap();
    assert!(
        listing.status.success(),
        "fmpy.supported_platforms failed: {}",
        String::from_utf8_lossy(&listing.stderr)
    );
    let lines: Vec<String> = String::from_utf8_lossy(&listing.stdout)
        .lines()
        .map(str::to_owned)
        .collect();
    assert_eq!(lines.len(), all.len());
    // fmpy 0.3.32 names platforms the FMI 2.0 way in both versions and knows no Linux on ARM
    // (its supported_platforms looks for i686/x86_64 Linux, x86/x86_64 Windows and macOS
    // only), so the aarch64-linux binary of the FMI 3.0 FMUs is not in its list; the folder
    // and object checks above cover it.
    for ((fmu, version, _), line) in all.iter().zip(&lines) {
        assert_eq!(line, "linux64 win64", "{version} {}", fmu.model_identifier);
    }
}

/// A section of `objdump -p` output: the lines after the one starting with `heading` up
/// to the next blank line.
fn objdump_section<'a>(text: &'a str, heading: &str) -> Vec<&'a str> {
    text.lines()
        .skip_while(|line| !line.trim_start().starts_with(heading))
        .skip(1)
        .take_while(|line| !line.trim().is_empty())
        .collect()
}

/// `objdump -p` of `file`; `objdump` is the program, optionally followed by the package
/// that provides it in parentheses (for the message when it cannot run).
fn objdump_headers(objdump: &str, file: &Path) -> String {
    let program = objdump.split(' ').next().unwrap_or(objdump);
    let output = Command::new(program)
        .arg("-p")
        .arg(file)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {objdump}: {e}"));
    assert!(
        output.status.success(),
        "{program} failed on {}",
        file.display()
    );
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// The exported names and the imported DLLs of a PE file, from `objdump -p`.
fn pe_exports_and_imports(dll: &Path) -> (BTreeSet<String>, BTreeSet<String>) {
    let text = objdump_headers("x86_64-w64-mingw32-objdump (gcc-mingw-w64-x86-64)", dll);
    // "[Ordinal/Name Pointer] Table" lines read "\t[   0] fmi2CancelStep".
    let exports = objdump_section(&text, "[Ordinal/Name Pointer] Table")
        .iter()
        .filter_map(|line| line.split(']').nth(1))
        .map(|name| name.trim().to_owned())
        .collect();
    let imports = text
        .lines()
        .filter_map(|line| line.trim().strip_prefix("DLL Name: "))
        .map(|name| name.trim().to_ascii_lowercase())
        .collect();
    (exports, imports)
}

/// The shared objects an ELF library needs (`NEEDED` entries of `objdump -p`).
fn elf_needed(objdump: &str, library: &Path) -> BTreeSet<String> {
    objdump_headers(objdump, library)
        .lines()
        .filter_map(|line| line.trim().strip_prefix("NEEDED"))
        .map(|name| name.trim().to_owned())
        .collect()
}

/// DLLs every Windows installation (8 and later) has, the ones Rust's std links: no MinGW
/// runtime DLL (libgcc_s_seh-1, libwinpthread-1) may be needed beside the FMU. The
/// `api-ms-win-*` name is an API set of the system, resolved by the loader.
const WINDOWS_SYSTEM_DLLS: [&str; 7] = [
    "kernel32.dll",
    "ntdll.dll",
    "msvcrt.dll",
    "ws2_32.dll",
    "userenv.dll",
    "bcryptprimitives.dll",
    "api-ms-win-core-synch-l1-2-0.dll",
];

/// The C runtime every glibc Linux has (with each architecture's loader); libgcc_s for
/// unwinding.
const LINUX_SYSTEM_LIBRARIES: [&str; 5] = [
    "libc.so.6",
    "libm.so.6",
    "libgcc_s.so.1",
    "ld-linux-x86-64.so.2",
    "ld-linux-aarch64.so.1",
];

#[test]
#[ignore = "needs `cargo xtask fmus --all-platforms` (Debian's cross toolchains)"]
fn every_binary_exports_exactly_the_standard_functions_and_needs_only_system_libraries() {
    let mut checked = 0;
    for (fmu, version, path) in packaged() {
        let id = &fmu.model_identifier;
        let expected = expected_exports(&fmu);
        let unpacked = Unpacked::open(&path).unwrap_or_else(|e| panic!("{e}"));
        for (folder, extension, object) in platforms(version) {
            let binary = unpacked
                .root()
                .join("binaries")
                .join(folder)
                .join(format!("{id}.{extension}"));
            let what = format!("{version} {id}: binaries/{folder}");
            let (exports, needed, system): (_, _, &[&str]) = match object {
                Object::ElfX86_64 => (
                    dynamic_symbols("nm", &binary),
                    elf_needed("objdump", &binary),
                    &LINUX_SYSTEM_LIBRARIES,
                ),
                Object::ElfAarch64 => (
                    dynamic_symbols("aarch64-linux-gnu-nm", &binary),
                    elf_needed("aarch64-linux-gnu-objdump", &binary),
                    &LINUX_SYSTEM_LIBRARIES,
                ),
                Object::PeX86_64 => {
                    let (exports, imports) = pe_exports_and_imports(&binary);
                    (exports, imports, &WINDOWS_SYSTEM_DLLS)
                }
            };
            assert_eq!(exports, expected, "exports of {what}");
            let foreign: Vec<&String> = needed
                .iter()
                .filter(|name| !system.contains(&name.as_str()))
                .collect();
            assert!(
                foreign.is_empty(),
                "{what} needs {foreign:?}, not a system library (all: {needed:?})"
            );
            checked += 1;
        }
    }
    assert!(checked > 0);
}

#[test]
fn objdump_sections_and_pe_object_headers_are_read() {
    let text = "head\n[Ordinal/Name Pointer] Table\n\t[   0] fmi2A\n\t[   1] fmi3B\n\nafter\n";
    assert_eq!(
        objdump_section(text, "[Ordinal/Name Pointer] Table"),
        ["\t[   0] fmi2A", "\t[   1] fmi3B"]
    );
    let mut pe = vec![0u8; 0x90];
    pe[..2].copy_from_slice(b"MZ");
    pe[0x3c] = 0x80;
    pe[0x80..0x86].copy_from_slice(b"PE\0\0\x64\x86");
    assert_eq!(object_of(&pe), Some(Object::PeX86_64));
    let mut elf = vec![0u8; 24];
    elf[..4].copy_from_slice(b"\x7fELF");
    elf[18] = 0xb7;
    assert_eq!(object_of(&elf), Some(Object::ElfAarch64));
    assert_eq!(object_of(b"junk"), None);
}
