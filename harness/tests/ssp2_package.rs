//! The paper scenario with the FMI 3.0 pair as an SSP 2.0 package: its SSD
//! (`harness/scenarios/paper-fmi3.ssd`) is generated from paper.toml against the FMI 3.0 FMUs
//! (never hand-edited), `cargo xtask fmus` packages it as `target/fmu/fmi3/LanderDescent.ssp`,
//! and the harness flies the package as it flies the TOML. Regenerate after changing the TOML
//! with `UPDATE_SSD=1 cargo test -p harness --test main ssp2_package::`.
use crate::common;

use lander::scenarios;
use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};

fn checked_in() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/paper-fmi3.ssd")
}

fn package() -> PathBuf {
    let path = common::fmu_dir().join("fmi3/LanderDescent.ssp");
    assert!(
        path.is_file(),
        "{} is missing: run `cargo xtask fmus` first",
        path.display()
    );
    path
}

/// paper.toml with its FMUs the FMI 3.0 twins.
fn fmi3_paper_toml() -> String {
    let text =
        fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/paper.toml"))
            .unwrap();
    let out = text.replace("fmu = \"", "fmu = \"fmi3/");
    assert_eq!(out.matches("fmu = \"fmi3/").count(), 2);
    out
}

#[test]
fn the_checked_in_ssp2_ssd_is_generated_from_the_toml() {
    let generated = scenarios::ssd2_for(&fmi3_paper(), &common::fmu_dir()).unwrap();
    if std::env::var_os("UPDATE_SSD").is_some() {
        fs::write(checked_in(), &generated).unwrap();
    }
    let shipped = fs::read_to_string(checked_in()).unwrap_or_default();
    assert!(
        shipped == generated,
        "{} drifted from paper.toml: regenerate with UPDATE_SSD=1",
        checked_in().display()
    );
    // What makes it SSP 2.0: the version, one connector per array with its FMI 3.0 type and
    // dimension, the connection of whole arrays, and the scenario's three element values
    // written as the one list.
    assert!(generated.contains(r#" version="2.0" name="paper">"#));
    assert!(generated.contains(
        r#"<ssd:Connector name="r_nue" kind="output"><ssc:Float64/><ssc:Dimension size="3"/></ssd:Connector>"#
    ));
    assert!(generated.contains(
        r#"<ssd:Connection startElement="plant" startConnector="r_nue" endElement="gnc" endConnector="r_nue"/>"#
    ));
    assert!(generated.contains(
        r#"<ssv:Parameter name="r0_nue"><ssv:Float64 value="0.0 800.0 0.0"/><ssc:Dimension size="3"/></ssv:Parameter>"#
    ));
    assert!(generated.contains(r#"<ssv:ParameterSet version="2.0" name="initialValues">"#));
    assert!(!generated.contains("r_nue[1]"), "no element connectors");
}

#[test]
fn the_package_holds_the_ssd_and_the_fmi3_fmus() {
    let mut archive = zip::ZipArchive::new(fs::File::open(package()).unwrap()).unwrap();
    let mut names: Vec<_> = archive.file_names().map(str::to_owned).collect();
    names.sort();
    assert_eq!(
        names,
        [
            "SystemStructure.ssd",
            "resources/LanderGnc.fmu",
            "resources/LanderPlant.fmu"
        ]
    );
    let mut entry = |name: &str| {
        let mut bytes = Vec::new();
        archive
            .by_name(name)
            .unwrap()
            .read_to_end(&mut bytes)
            .unwrap();
        bytes
    };
    assert!(entry("SystemStructure.ssd") == fs::read(checked_in()).unwrap());
    for fmu in ["LanderGnc", "LanderPlant"] {
        let shipped = fs::read(common::fmu_dir().join(format!("fmi3/{fmu}.fmu"))).unwrap();
        assert!(
            entry(&format!("resources/{fmu}.fmu")) == shipped,
            "resources/{fmu}.fmu is not target/fmu/fmi3/{fmu}.fmu"
        );
    }
}

/// `harness run SCENARIO -o X.csv`: its stdout (the CSV path masked) and the CSV.
fn run(scenario: &Path, csv: &Path) -> (String, String) {
    let output = common::harness(&[
        "run",
        scenario.to_str().unwrap(),
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "harness run {}: {}",
        scenario.display(),
        String::from_utf8_lossy(&output.stderr)
    );
    let stdout = String::from_utf8_lossy(&output.stdout).replace(csv.to_str().unwrap(), "OUT");
    (stdout, fs::read_to_string(csv).unwrap())
}

#[test]
fn harness_run_of_the_ssp2_package_flies_the_fmi3_paper_trajectory_bit_for_bit() {
    // GIVEN the SSP 2.0 package and paper.toml pointed at the same FMI 3.0 FMUs
    let temp = tempfile::tempdir().unwrap();
    let toml = temp.path().join("paper-fmi3.toml");
    fs::write(&toml, fmi3_paper_toml()).unwrap();
    // WHEN both are flown by `harness run`
    let (verdict_toml, csv_toml) = run(&toml, &temp.path().join("toml.csv"));
    let (verdict_ssp, csv_ssp) = run(&package(), &temp.path().join("ssp.csv"));
    // THEN the same verdict and every recorded value the same (the CSV holds the shortest
    // round-trip text of each double, so equal text is equal bits)
    assert!(
        verdict_toml.contains("verdict: completed at t = 172.00 s"),
        "{verdict_toml}"
    );
    assert_eq!(csv_ssp.lines().count(), 17_202, "header and 17,201 rows");
    assert!(csv_ssp.starts_with("time,gnc.thrust_cmd,gnc.torque_cmd_body[1],"));
    assert!(csv_ssp == csv_toml, "the package's trajectory differs");
    // (the TOML's requirements are not in an SSD: the package's verdict lists none)
    assert!(
        verdict_ssp.contains("verdict: completed at t = 172.00 s"),
        "{verdict_ssp}"
    );
}

/// `harness run` of the package's SSD beside the FMI 3.0 FMUs with `edit` applied.
fn run_edited(edit: impl Fn(String) -> String) -> std::process::Output {
    let temp = tempfile::tempdir().unwrap();
    let resources = temp.path().join("resources");
    fs::create_dir(&resources).unwrap();
    for fmu in ["LanderGnc.fmu", "LanderPlant.fmu"] {
        fs::copy(
            common::fmu_dir().join("fmi3").join(fmu),
            resources.join(fmu),
        )
        .unwrap();
    }
    let ssd = temp.path().join("broken.ssd");
    let text = fs::read_to_string(checked_in()).unwrap();
    let edited = edit(text.clone());
    assert_ne!(edited, text, "the edit changed nothing");
    fs::write(&ssd, edited).unwrap();
    common::harness(&["run", ssd.to_str().unwrap(), "--stop-time", "1"])
}

/// What `harness run` says of the edited SSD, which it must refuse.
fn refusal_of(edit: impl Fn(String) -> String) -> String {
    let output = run_edited(edit);
    assert!(!output.status.success(), "the edited SSD was flown");
    String::from_utf8_lossy(&output.stderr).into_owned()
}

#[test]
fn ssp1_type_names_real_and_integer_stand_for_float64_and_int32() {
    let output = run_edited(|ssd| {
        ssd.replace(
            r#"<ssd:Connector name="r_nue" kind="input"><ssc:Float64/>"#,
            r#"<ssd:Connector name="r_nue" kind="input"><ssc:Real/>"#,
        )
        .replace(
            r#"<ssv:Parameter name="control_law"><ssv:Int32 "#,
            r#"<ssv:Parameter name="control_law"><ssv:Integer "#,
        )
    });
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

#[test]
fn a_connector_whose_dimension_or_type_is_not_the_fmus_is_refused_by_name() {
    let error = refusal_of(|ssd| {
        ssd.replacen(
            r#"<ssd:Connector name="r_nue" kind="input"><ssc:Float64/><ssc:Dimension size="3"/>"#,
            r#"<ssd:Connector name="r_nue" kind="input"><ssc:Float64/><ssc:Dimension size="4"/>"#,
            1,
        )
    });
    assert!(
        error.contains("component 'gnc': connector 'r_nue' is declared with dimensions [4]")
            && error.contains("[3]"),
        "{error}"
    );
    let error = refusal_of(|ssd| {
        ssd.replacen(
            r#"<ssd:Connector name="mass" kind="input"><ssc:Float64/>"#,
            r#"<ssd:Connector name="mass" kind="input"><ssc:Int32/>"#,
            1,
        )
    });
    assert!(
        error.contains("connector 'mass' is declared Int32 but the FMU's variable is Float64"),
        "{error}"
    );
}

#[test]
fn a_list_value_that_does_not_fit_its_dimension_is_refused_naming_file_parameter_and_value() {
    let error =
        refusal_of(|ssd| ssd.replacen(r#"value="0.0 800.0 0.0""#, r#"value="0.0 800.0""#, 1));
    assert!(
        error.contains("broken.ssd")
            && error
                .contains("component 'plant': parameter 'r0_nue': value '0.0 800.0' has 2 values"),
        "{error}"
    );
}

#[test]
fn the_ssp2_ssd_against_the_fmi2_fmus_is_refused_saying_they_are_fmi2() {
    // The shipped SSD alone finds its FMUs by file name in the FMU directory: target/fmu holds
    // the FMI 2.0 twins, whose variables are scalars.
    let output = common::harness(&["run", checked_in().to_str().unwrap(), "--stop-time", "1"]);
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        error.contains(
            "component 'plant': connector 'r_nue' (Float64 [3]) is SSP 2.0's, of an FMI 3.0 \
             variable, but model 'LanderPlant' is an FMI 2.0 FMU"
        ),
        "{error}"
    );
}

/// paper.toml's system with its FMUs the FMI 3.0 twins.
fn fmi3_paper() -> cosim::system::SystemDescription {
    let mut system = scenarios::load("paper").unwrap();
    for instance in &mut system.instances {
        instance.fmu = Path::new("fmi3").join(&instance.fmu);
    }
    system
}

#[test]
fn elements_the_scenario_does_not_set_are_written_from_the_fmus_start_values() {
    // GIVEN the paper scenario setting r0_nue[2] alone (to 650 m, not the FMU's start), and
    // the plant's start values of r0_nue
    let mut system = fmi3_paper();
    let plant = system.instance_mut("plant").unwrap();
    plant
        .parameters
        .retain(|(name, _)| name != "r0_nue[1]" && name != "r0_nue[3]");
    system.set_parameter("plant", "r0_nue[2]", cosim::system::ParamValue::Real(650.0));
    let fmu = fmi_import::Fmu::load(common::fmu_dir().join("fmi3/LanderPlant.fmu")).unwrap();
    let start: Vec<f64> = fmu
        .fmi3_description()
        .unwrap()
        .variables
        .iter()
        .find(|v| v.name == "r0_nue")
        .unwrap()
        .start
        .iter()
        .map(|s| s.parse().unwrap())
        .collect();
    assert_eq!(start.len(), 3);
    assert_ne!(start[1], 650.0);
    // WHEN its SSP 2.0 SSD is written
    let ssd = scenarios::ssd2_for(&system, &common::fmu_dir()).unwrap();
    // THEN r0_nue is the whole array: the FMU's first and third elements, the scenario's second
    let list = format!("{:?} 650.0 {:?}", start[0], start[2]);
    assert!(
        ssd.contains(&format!(
            r#"<ssv:Parameter name="r0_nue"><ssv:Float64 value="{list}"/><ssc:Dimension size="3"/></ssv:Parameter>"#
        )),
        "{ssd}"
    );
    // and read back, the harness sets all three.
    let back = cosim::system::ssp::parse(&ssd, Path::new("x.ssd")).unwrap();
    let plant = back.instance("plant").unwrap();
    for (k, expected) in [start[0], 650.0, start[2]].into_iter().enumerate() {
        let name = format!("r0_nue[{}]", k + 1);
        let value = plant.parameters.iter().find(|(n, _)| *n == name).unwrap();
        assert_eq!(value.1, cosim::system::ParamValue::Real(expected), "{name}");
    }
}

#[test]
fn a_connection_of_array_elements_is_refused_by_the_ssp2_writer_by_name() {
    let mut system = fmi3_paper();
    let connection = system
        .connections
        .iter_mut()
        .find(|c| c.from == "plant.r_nue")
        .unwrap();
    connection.from = "plant.r_nue[1]".into();
    connection.to = "gnc.r_nue[1]".into();
    let error = scenarios::ssd2_for(&system, &common::fmu_dir())
        .unwrap_err()
        .to_string();
    assert!(
        error.contains(
            "connection plant.r_nue[1] -> gnc.r_nue[1]: 'plant.r_nue[1]' is not a whole \
             variable of an FMI 3.0 component"
        ),
        "{error}"
    );
}
