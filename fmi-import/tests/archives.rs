//! FMU archives built entry by entry, each broken in one way the unpacker refuses, and the
//! stub's model description they carry. Shared with the command line's tests
//! (harness/tests/import), which check that `harness` refuses the same archives cleanly.

use std::fs;
use std::io::Write;
use std::path::Path;
use zip::write::SimpleFileOptions;
use zip::CompressionMethod;

pub const STUB_DESCRIPTION: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="Stub" guid="{stub}">
  <CoSimulation modelIdentifier="Stub" canGetAndSetFMUstate="true" canSerializeFMUstate="true"/>
  <ModelVariables>
    <ScalarVariable name="x" valueReference="0" causality="parameter" variability="tunable">
      <Real start="0"/>
    </ScalarVariable>
    <ScalarVariable name="n" valueReference="0" causality="parameter" variability="tunable">
      <Integer start="0"/>
    </ScalarVariable>
    <ScalarVariable name="flag" valueReference="0" causality="parameter" variability="tunable">
      <Boolean start="false"/>
    </ScalarVariable>
    <ScalarVariable name="label" valueReference="0" causality="parameter" variability="tunable">
      <String start=""/>
    </ScalarVariable>
  </ModelVariables>
  <ModelStructure/>
</fmiModelDescription>
"#;

/// Writes a zip of `entries` (deflated) to `path`.
pub fn write_archive(path: &Path, entries: &[(&str, &[u8])]) {
    let mut zip = zip::ZipWriter::new(fs::File::create(path).unwrap());
    let options = SimpleFileOptions::default().compression_method(CompressionMethod::Deflated);
    for (name, data) in entries {
        zip.start_file(*name, options).unwrap();
        zip.write_all(data).unwrap();
    }
    zip.finish().unwrap();
}

/// An FMU whose `resources/link` is a symbolic link to `/etc/passwd`.
pub fn symlink_fmu(path: &Path) {
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
pub fn duplicate_fmu(path: &Path) {
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

pub fn replace_all(bytes: &[u8], from: &[u8], to: &[u8]) -> (Vec<u8>, usize) {
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
pub fn entity_bomb() -> String {
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
#[allow(dead_code)] // the command line's case only (harness/tests/import)
pub fn wide_entity_bomb() -> String {
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
pub fn one_entity() -> String {
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
pub fn zeros_fmu(path: &Path) {
    let zeros = vec![0u8; ZEROS];
    write_archive(
        path,
        &[
            ("modelDescription.xml", STUB_DESCRIPTION.as_bytes()),
            ("resources/zeros", &zeros),
        ],
    );
}

pub const ZEROS: usize = 100_000_000;

/// [`zeros_fmu`] with both headers of `resources/zeros` declaring 1000 bytes; the CRC is the
/// true data's, so only the count of bytes written tells.
pub fn lying_fmu(path: &Path) {
    zeros_fmu(path);
    let (bytes, count) = replace_all(
        &fs::read(path).unwrap(),
        &(ZEROS as u32).to_le_bytes(),
        &1000u32.to_le_bytes(),
    );
    assert_eq!(count, 2, "local header and central record");
    fs::write(path, bytes).unwrap();
}
