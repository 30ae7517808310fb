//! Loading from a `.fmu` zip: the archive is unpacked into a temporary directory that lives
//! exactly as long as the FMU, and broken archives get errors that say what is wrong.
mod common;

use common::{zip_dir, StubFmu, STUB_DESCRIPTION};
use fmi_import::{Fmu, LoadError};
use std::ffi::OsStr;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use tempfile::TempDir;
use zip::write::SimpleFileOptions;
use zip::CompressionMethod;

#[test]
fn a_zipped_fmu_loads_runs_and_cleans_up_after_itself() {
    let stub = StubFmu::standard();
    let out = TempDir::new().unwrap();
    let archive = out.path().join("Stub.fmu");
    zip_dir(&stub.dir, &archive);

    let fmu = Fmu::load(&archive).unwrap();
    let unpacked = fmu.unpacked_dir().to_path_buf();
    assert_ne!(unpacked, stub.dir);
    assert!(unpacked.join("modelDescription.xml").is_file());
    assert!(fmu.binary_path().starts_with(&unpacked));

    let mut instance = fmu.instantiate("zipped", false).unwrap();
    instance.set_real_by_name("x", 0.75).unwrap();
    assert_eq!(instance.get_real_by_name("x").unwrap(), 0.75);

    // The unpacked files stay while any instance lives, and go with the last one.
    drop(fmu);
    assert!(unpacked.is_dir());
    drop(instance);
    assert!(!unpacked.exists());
}

#[test]
fn a_file_that_is_not_a_zip_is_refused_as_such() {
    let out = TempDir::new().unwrap();
    let archive = out.path().join("garbage.fmu");
    fs::write(&archive, b"this is not a zip archive").unwrap();
    let error = Fmu::load(&archive).unwrap_err();
    assert!(matches!(error, LoadError::Zip { .. }), "{error:?}");
    assert!(
        error
            .to_string()
            .contains("garbage.fmu is not a readable zip archive"),
        "{error}"
    );
}

#[test]
fn a_missing_file_is_an_io_error_naming_it() {
    let error = Fmu::load("/nonexistent/Missing.fmu").unwrap_err();
    assert!(matches!(error, LoadError::Io { .. }), "{error:?}");
    assert!(
        error.to_string().contains("/nonexistent/Missing.fmu"),
        "{error}"
    );
}

#[test]
fn an_archive_without_a_model_description_is_refused() {
    let out = TempDir::new().unwrap();
    let archive = out.path().join("NoDescription.fmu");
    let mut zip = zip::ZipWriter::new(fs::File::create(&archive).unwrap());
    zip.start_file(
        "binaries/linux64/Stub.so",
        zip::write::SimpleFileOptions::default(),
    )
    .unwrap();
    zip.write_all(b"\x7fELF").unwrap();
    zip.finish().unwrap();

    let error = Fmu::load(&archive).unwrap_err();
    assert!(
        matches!(error, LoadError::MissingModelDescription { .. }),
        "{error:?}"
    );
    assert!(
        error.to_string().contains("no modelDescription.xml"),
        "{error}"
    );
}

#[test]
fn a_directory_without_a_model_description_is_refused() {
    let empty = TempDir::new().unwrap();
    let error = Fmu::load(empty.path()).unwrap_err();
    assert!(
        matches!(error, LoadError::MissingModelDescription { .. }),
        "{error:?}"
    );
}

#[test]
fn an_entry_escaping_the_archive_is_not_written_outside_it() {
    let out = TempDir::new().unwrap();
    let archive = out.path().join("Slip.fmu");
    let mut zip = zip::ZipWriter::new(fs::File::create(&archive).unwrap());
    zip.start_file("../escaped.txt", zip::write::SimpleFileOptions::default())
        .unwrap();
    zip.write_all(b"outside").unwrap();
    zip.finish().unwrap();

    // Refused either as a bad archive or for its missing description; never written out.
    assert!(Fmu::load(&archive).is_err());
    assert!(!std::env::temp_dir().join("escaped.txt").exists());
}

/// Writes a zip of `entries` (deflated) to `path`.
fn write_archive(path: &Path, entries: &[(&str, &[u8])]) {
    let mut zip = zip::ZipWriter::new(fs::File::create(path).unwrap());
    let options = SimpleFileOptions::default().compression_method(CompressionMethod::Deflated);
    for (name, data) in entries {
        zip.start_file(*name, options).unwrap();
        zip.write_all(data).unwrap();
    }
    zip.finish().unwrap();
}

/// An FMU whose `resources/link` is a symbolic link to `/etc/passwd`.
fn symlink_fmu(path: &Path) {
    let mut zip = zip::ZipWriter::new(fs::File::create(path).unwrap());
    let options = SimpleFileOptions::default();
    zip.start_file("modelDescription.xml", options).unwrap();
    zip.write_all(STUB_DESCRIPTION.as_bytes()).unwrap();
    zip.add_symlink("resources/link", "/etc/passwd", options)
        .unwrap();
    zip.finish().unwrap();
}

/// An FMU with two `modelDescription.xml` entries, the second another model's. The zip crate
/// writes no duplicate name, so the second is written under a name of the same length and
/// renamed in the bytes (its local header and its central directory record).
fn duplicate_fmu(path: &Path) {
    let other = STUB_DESCRIPTION.replace("modelName=\"Stub\"", "modelName=\"Other\"");
    write_archive(
        path,
        &[
            ("modelDescription.xml", STUB_DESCRIPTION.as_bytes()),
            ("modelDescription.xmX", other.as_bytes()),
        ],
    );
    let renamed = replace_all(
        &fs::read(path).unwrap(),
        b"modelDescription.xmX",
        b"modelDescription.xml",
    );
    fs::write(path, renamed.0).unwrap();
    assert_eq!(renamed.1, 2, "local header and central record");
}

fn replace_all(bytes: &[u8], from: &[u8], to: &[u8]) -> (Vec<u8>, usize) {
    assert_eq!(from.len(), to.len());
    let mut out = bytes.to_vec();
    let mut count = 0;
    for at in 0..=out.len() - from.len() {
        if &out[at..at + from.len()] == from {
            out[at..at + from.len()].copy_from_slice(to);
            count += 1;
        }
    }
    (out, count)
}

/// Ten nested entities of ten references each: the model name expands to 3 GB of "lol".
fn entity_bomb() -> String {
    let mut entities = String::from("<!ENTITY lol0 \"lol\">\n");
    for level in 1..10 {
        let previous = format!("&lol{};", level - 1).repeat(10);
        entities.push_str(&format!("<!ENTITY lol{level} \"{previous}\">\n"));
    }
    STUB_DESCRIPTION
        .replacen(
            "?>\n",
            &format!("?>\n<!DOCTYPE fmiModelDescription [\n{entities}]>\n"),
            1,
        )
        .replacen("modelName=\"Stub\"", "modelName=\"&lol9;\"", 1)
}

/// One entity of a megabyte referenced a thousand times: a gigabyte once expanded (without
/// the refusal, `harness vars` took 18 s and 2 GB of memory on it).
fn wide_entity_bomb() -> String {
    STUB_DESCRIPTION
        .replacen(
            "?>\n",
            &format!(
                "?>\n<!DOCTYPE fmiModelDescription [<!ENTITY big \"{}\">]>\n",
                "x".repeat(1_000_000)
            ),
            1,
        )
        .replacen(
            "modelName=\"Stub\"",
            &format!("modelName=\"{}\"", "&big;".repeat(1000)),
            1,
        )
}

/// One entity, which a reader would expand once without a word.
fn one_entity() -> String {
    STUB_DESCRIPTION
        .replacen(
            "?>\n",
            "?>\n<!DOCTYPE fmiModelDescription [<!ENTITY name \"Expanded\">]>\n",
            1,
        )
        .replacen("modelName=\"Stub\"", "modelName=\"&name;\"", 1)
}

/// An FMU of `modelDescription.xml` and `resources/zeros`, 100 MB of zeros (about 100 kB
/// deflated).
fn zeros_fmu(path: &Path) {
    let zeros = vec![0u8; ZEROS];
    write_archive(
        path,
        &[
            ("modelDescription.xml", STUB_DESCRIPTION.as_bytes()),
            ("resources/zeros", &zeros),
        ],
    );
}

const ZEROS: usize = 100_000_000;

/// [`zeros_fmu`] with both headers of `resources/zeros` declaring 1000 bytes; the CRC is the
/// true data's, so only the count of bytes written tells.
fn lying_fmu(path: &Path) {
    zeros_fmu(path);
    let (bytes, count) = replace_all(
        &fs::read(path).unwrap(),
        &(ZEROS as u32).to_le_bytes(),
        &1000u32.to_le_bytes(),
    );
    assert_eq!(count, 2, "local header and central record");
    fs::write(path, bytes).unwrap();
}

fn load_error(path: &Path) -> String {
    let error = Fmu::load(path).unwrap_err();
    format!("{:#}", anyhow::Error::new(error))
}

#[test]
fn a_symlink_entry_is_refused_naming_archive_and_entry() {
    let out = TempDir::new().unwrap();
    let archive = out.path().join("Link.fmu");
    symlink_fmu(&archive);
    let error = Fmu::load(&archive).unwrap_err();
    assert!(matches!(error, LoadError::Unpack(_)), "{error:?}");
    let text = error.to_string();
    assert!(text.contains(&archive.display().to_string()), "{text}");
    assert!(text.contains("'resources/link'"), "{text}");
    assert!(text.contains("symbolic link (to '/etc/passwd')"), "{text}");
}

#[test]
fn an_entry_name_given_twice_is_refused_naming_archive_and_entry() {
    let out = TempDir::new().unwrap();
    let archive = out.path().join("Twice.fmu");
    duplicate_fmu(&archive);
    let text = load_error(&archive);
    assert!(text.contains(&archive.display().to_string()), "{text}");
    assert!(
        text.contains("entry 'modelDescription.xml' is named twice"),
        "{text}"
    );
}

#[test]
fn an_entry_escaping_the_archive_is_refused_naming_it() {
    let out = TempDir::new().unwrap();
    let archive = out.path().join("Slip.fmu");
    write_archive(
        &archive,
        &[
            ("modelDescription.xml", STUB_DESCRIPTION.as_bytes()),
            ("resources/../../escaped.txt", b"outside"),
        ],
    );
    let text = load_error(&archive);
    assert!(
        text.contains("entry 'resources/../../escaped.txt' would be written outside"),
        "{text}"
    );
}

#[test]
fn a_model_description_with_an_entity_is_refused_naming_archive_and_entry() {
    let out = TempDir::new().unwrap();
    for (name, description) in [("Entity.fmu", one_entity()), ("Bomb.fmu", entity_bomb())] {
        let archive = out.path().join(name);
        write_archive(
            &archive,
            &[("modelDescription.xml", description.as_bytes())],
        );
        let error = Fmu::load(&archive).unwrap_err();
        assert!(
            matches!(error, LoadError::ModelDescription { .. }),
            "{error:?}"
        );
        let text = format!("{:#}", anyhow::Error::new(error));
        assert!(
            text.contains(&format!("{name}/modelDescription.xml")),
            "{text}"
        );
        assert!(text.contains("line 2: <!DOCTYPE"), "{text}");
    }
}

#[test]
fn a_header_that_declares_fewer_bytes_than_its_data_is_refused() {
    let out = TempDir::new().unwrap();
    let archive = out.path().join("Lying.fmu");
    lying_fmu(&archive);
    let text = load_error(&archive);
    assert!(
        text.contains(
            "entry 'resources/zeros' unpacks to more than the 1000 bytes its header declares"
        ),
        "{text}"
    );
}

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
