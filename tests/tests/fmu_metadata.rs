//! The `[package.metadata.fmu]` of each FMU crate agrees with what the crate exports and
//! what xtask packaged:
//!
//! - its `src/lib.rs` invokes `export_fmi2!`/`export_fmi3!` for exactly the versions the
//!   metadata offers, with `model_exchange` exactly when it lists Model Exchange (a version
//!   marked `awaiting-export` has no macro yet; once it has one the marker must go);
//! - each packaged FMU's modelDescription.xml names the metadata's `model-identifier` and
//!   declares `<ModelExchange>` exactly when the metadata lists it.
//!
//! The exported symbols of each packaged library are checked against the same metadata in
//! abi_conformance.rs.
use fmi_abi::unpack::Unpacked;
use system_tests::{fmi3_fmu_path, fmu_crates, workspace_root, Fmi, UnpackedFmu};

#[test]
fn each_crates_export_macros_agree_with_its_metadata() {
    let fmus = fmu_crates();
    assert!(
        !fmus.is_empty(),
        "no workspace member has [package.metadata.fmu]"
    );
    let mut problems = Vec::new();
    for fmu in &fmus {
        let lib_rs = workspace_root().join(&fmu.dir).join("src/lib.rs");
        let source = std::fs::read_to_string(&lib_rs)
            .unwrap_or_else(|e| panic!("{}: {e}", lib_rs.display()));
        let exports = fmu_metadata::exports_in_source(&source)
            .unwrap_or_else(|e| panic!("{}: {e}", lib_rs.display()));
        problems.extend(fmu_metadata::check_exports(fmu, &exports));
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn each_packaged_description_declares_the_interfaces_of_its_metadata() {
    for fmu in fmu_crates() {
        let id = &fmu.model_identifier;
        if fmu.ships(Fmi::V2) {
            let unpacked = UnpackedFmu::open(id);
            assert_eq!(
                unpacked.description.model_exchange.is_some(),
                fmu.ships_model_exchange(Fmi::V2),
                "<ModelExchange> in the FMI 2.0 {id}"
            );
        }
        if fmu.ships(Fmi::V3) {
            let unpacked = Unpacked::open(&fmi3_fmu_path(id)).unwrap_or_else(|e| panic!("{e}"));
            let xml = std::fs::read_to_string(unpacked.model_description_path()).unwrap();
            assert!(xml.contains("fmiVersion=\"3.0\""), "FMI 3.0 {id}");
            assert!(
                xml.contains(&format!("<CoSimulation modelIdentifier=\"{id}\"")),
                "<CoSimulation modelIdentifier=\"{id}\"> in the FMI 3.0 {id}"
            );
            assert_eq!(
                xml.contains(&format!("<ModelExchange modelIdentifier=\"{id}\"")),
                fmu.ships_model_exchange(Fmi::V3),
                "<ModelExchange modelIdentifier=\"{id}\"> in the FMI 3.0 {id}"
            );
        }
    }
}

/// `YYYY-MM-DDThh:mm:ssZ`, the form FMI's `generationDateAndTime` takes (xs:dateTime, UTC).
fn is_utc_date_time(text: &str) -> bool {
    let b = text.as_bytes();
    b.len() == 20
        && b.iter().enumerate().all(|(i, c)| match i {
            4 | 7 => *c == b'-',
            10 => *c == b'T',
            13 | 16 => *c == b':',
            19 => *c == b'Z',
            _ => c.is_ascii_digit(),
        })
}

#[test]
fn each_packaged_description_says_when_and_by_whom_under_which_license() {
    for fmu in fmu_crates() {
        let id = &fmu.model_identifier;
        let mut descriptions = Vec::new();
        if fmu.ships(Fmi::V2) {
            let unpacked = UnpackedFmu::open(id);
            let md = &unpacked.description;
            descriptions.push(("FMI 2.0", md.generation_date_and_time.clone()));
            assert_eq!(
                md.license.as_deref(),
                Some("MIT OR Apache-2.0"),
                "FMI 2.0 {id}"
            );
            assert!(
                md.author.is_some() && md.copyright.is_some(),
                "FMI 2.0 {id}"
            );
        }
        if fmu.ships(Fmi::V3) {
            let unpacked = Unpacked::open(&fmi3_fmu_path(id)).unwrap_or_else(|e| panic!("{e}"));
            let xml = std::fs::read_to_string(unpacked.model_description_path()).unwrap();
            let time = xml
                .split("generationDateAndTime=\"")
                .nth(1)
                .and_then(|rest| rest.split('"').next())
                .map(str::to_owned);
            descriptions.push(("FMI 3.0", time));
            assert!(
                xml.contains(r#"license="MIT OR Apache-2.0""#),
                "FMI 3.0 {id}"
            );
        }
        // Packaged from a git checkout (the workspace is one): the commit's time, the same
        // in both versions.
        let times: Vec<_> = descriptions.iter().map(|(_, t)| t.clone()).collect();
        for (version, time) in &descriptions {
            let time = time
                .as_deref()
                .unwrap_or_else(|| panic!("{version} {id}: no time"));
            assert!(is_utc_date_time(time), "{version} {id}: {time}");
        }
        assert!(times.windows(2).all(|w| w[0] == w[1]), "{id}: {times:?}");
    }
}
