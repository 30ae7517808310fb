//! `harness` on archives the importer refuses: exit code 1, the archive and the entry named,
//! no panic, nothing left in the temporary directory; the unpacked-size bound from the
//! environment. The archives are the importer's test fixtures (fmi-import/tests/archives.rs).
use crate::archives::{
    duplicate_fmu, entity_bomb, lying_fmu, one_entity, symlink_fmu, wide_entity_bomb,
    write_archive, zeros_fmu, STUB_DESCRIPTION,
};
use std::ffi::OsStr;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use tempfile::TempDir;
use zip::write::SimpleFileOptions;

/// `harness` with TMPDIR a fresh directory: (exit code, stderr, what it left in TMPDIR).
fn harness(args: &[&OsStr], env: &[(&str, &str)]) -> (Option<i32>, String, Vec<PathBuf>) {
    let tmp = TempDir::new().unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_harness"))
        .args(args)
        .env("TMPDIR", tmp.path())
        .env("RUST_BACKTRACE", "1")
        .envs(env.iter().copied())
        .output()
        .unwrap();
    let left = fs::read_dir(tmp.path())
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .collect();
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
        left,
    )
}

fn assert_refused_cleanly(args: &[&OsStr], env: &[(&str, &str)], expected: &[&str]) {
    let (code, stderr, left) = harness(args, env);
    assert_eq!(code, Some(1), "{args:?}: {stderr}");
    for text in expected {
        assert!(stderr.contains(text), "{args:?}: no {text:?} in\n{stderr}");
    }
    let lower = stderr.to_lowercase();
    assert!(
        !lower.contains("panicked") && !lower.contains("backtrace"),
        "{args:?}: {stderr}"
    );
    assert!(left.is_empty(), "{args:?} left {left:?}");
}

/// An archive's file name, the environment of the run and what its error must say.
type Case<'a> = (&'a str, &'a [(&'a str, &'a str)], &'a [&'a str]);

#[test]
fn refused_fmus_end_the_harness_with_exit_code_1_and_leave_nothing_behind() {
    let out = TempDir::new().unwrap();
    let path = |name: &str| out.path().join(name);
    symlink_fmu(&path("Link.fmu"));
    duplicate_fmu(&path("Twice.fmu"));
    write_archive(
        &path("Bomb.fmu"),
        &[("modelDescription.xml", entity_bomb().as_bytes())],
    );
    write_archive(
        &path("Doctype.fmu"),
        &[("modelDescription.xml", one_entity().as_bytes())],
    );
    write_archive(
        &path("Slip.fmu"),
        &[
            ("modelDescription.xml", STUB_DESCRIPTION.as_bytes()),
            ("../escaped.txt", b"outside"),
        ],
    );
    write_archive(
        &path("Wide.fmu"),
        &[("modelDescription.xml", wide_entity_bomb().as_bytes())],
    );
    zeros_fmu(&path("Zeros.fmu"));
    lying_fmu(&path("Lying.fmu"));
    let bound = [("HARNESS_MAX_UNPACKED_BYTES", "10M")];
    let cases: [Case; 8] = [
        ("Link.fmu", &[], &["'resources/link'", "symbolic link"]),
        ("Twice.fmu", &[], &["'modelDescription.xml'", "named twice"]),
        (
            "Bomb.fmu",
            &[],
            &["Bomb.fmu/modelDescription.xml", "<!DOCTYPE"],
        ),
        (
            "Wide.fmu",
            &[],
            &["Wide.fmu/modelDescription.xml", "<!DOCTYPE"],
        ),
        (
            "Doctype.fmu",
            &[],
            &["Doctype.fmu/modelDescription.xml", "<!DOCTYPE"],
        ),
        ("Slip.fmu", &[], &["'../escaped.txt'", "outside"]),
        (
            "Zeros.fmu",
            &bound,
            &["'resources/zeros'", "limit of 10000000 bytes"],
        ),
        (
            "Lying.fmu",
            &bound,
            &["'resources/zeros'", "1000 bytes its header declares"],
        ),
    ];
    for (name, env, expected) in cases {
        let archive = path(name);
        let mut expected = expected.to_vec();
        let shown = archive.display().to_string();
        expected.push(&shown);
        assert_refused_cleanly(&[OsStr::new("vars"), archive.as_os_str()], env, &expected);
    }
    // The bound is the environment's: the same archive unpacks under the default.
    let (code, stderr, left) = harness(&[OsStr::new("vars"), path("Zeros.fmu").as_os_str()], &[]);
    assert!(!stderr.contains("resources/zeros"), "{code:?}: {stderr}");
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn a_bound_that_is_not_a_size_is_an_error_naming_the_variable() {
    let out = TempDir::new().unwrap();
    let archive = out.path().join("Small.fmu");
    write_archive(
        &archive,
        &[("modelDescription.xml", STUB_DESCRIPTION.as_bytes())],
    );
    assert_refused_cleanly(
        &[OsStr::new("vars"), archive.as_os_str()],
        &[("HARNESS_MAX_UNPACKED_BYTES", "lots")],
        &["HARNESS_MAX_UNPACKED_BYTES=lots", "not a byte count"],
    );
}

#[test]
fn refused_ssp_packages_end_the_harness_with_exit_code_1_and_leave_nothing_behind() {
    let out = TempDir::new().unwrap();
    let ssd = r#"<?xml version="1.0" encoding="UTF-8"?>
<!DOCTYPE ssd:SystemStructureDescription [<!ENTITY n "expanded">]>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" version="1.0" name="&n;">
  <ssd:System name="s"/>
  <ssd:DefaultExperiment startTime="0" stopTime="1"/>
</ssd:SystemStructureDescription>
"#;
    let doctype = out.path().join("Doctype.ssp");
    write_archive(&doctype, &[("SystemStructure.ssd", ssd.as_bytes())]);
    let link = out.path().join("Link.ssp");
    let mut zip = zip::ZipWriter::new(fs::File::create(&link).unwrap());
    zip.start_file("SystemStructure.ssd", SimpleFileOptions::default())
        .unwrap();
    zip.write_all(ssd.as_bytes()).unwrap();
    zip.add_symlink(
        "resources/A.fmu",
        "/etc/passwd",
        SimpleFileOptions::default(),
    )
    .unwrap();
    zip.finish().unwrap();

    let run = |ssp: &Path| [OsStr::new("run").to_owned(), ssp.as_os_str().to_owned()];
    let shown = doctype.display().to_string();
    assert_refused_cleanly(
        &run(&doctype).each_ref().map(|a| a.as_os_str()),
        &[],
        &[&shown, "SystemStructure.ssd: line 2: <!DOCTYPE"],
    );
    let shown = link.display().to_string();
    assert_refused_cleanly(
        &run(&link).each_ref().map(|a| a.as_os_str()),
        &[],
        &[&shown, "'resources/A.fmu'", "symbolic link"],
    );
}
