//! Loading from a `.fmu` zip: the archive is unpacked into a temporary directory that lives
//! exactly as long as the FMU, and broken archives get errors that say what is wrong.
use crate::archives::{
    duplicate_fmu, entity_bomb, lying_fmu, one_entity, symlink_fmu, write_archive, STUB_DESCRIPTION,
};
use crate::common::{zip_dir, StubFmu};
use fmi_import::{Fmu, LoadError};
use std::fs;
use std::io::Write;
use std::path::Path;
use tempfile::TempDir;

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
