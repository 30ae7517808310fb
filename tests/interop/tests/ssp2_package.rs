//! `target/fmu/fmi3/LanderDescent.ssp`, the SSP 2.0 package `cargo xtask fmus` writes of the
//! FMI 3.0 paper loop, checked by tools we did not write: lxml against the SSP 2.0 schemas
//! pyssp-standard ships (the SSD, and each parameter set against the SSV schema), and
//! pyssp-standard's own SSD reader and compliance check (xmlschema, the XSD 1.1 variant). What
//! they read is what the harness reads; a broken copy is refused.
use cosim::system::ParamValue;
use interop_tests::{fmu_dir, python, scenario, workspace_root};
use std::path::PathBuf;
use std::process::Command;

fn package() -> PathBuf {
    let path = fmu_dir().join("fmi3/LanderDescent.ssp");
    assert!(
        path.is_file(),
        "{} is missing: run `cargo xtask fmus` first",
        path.display()
    );
    path
}

#[test]
fn the_ssp2_package_is_valid_and_pyssp_standard_reads_the_harness_system() {
    // GIVEN what the harness reads from the package
    let system = scenario(package().to_str().unwrap());

    // WHEN the SSD is validated against the SSP 2.0 schemas and read by pyssp-standard
    let report = python::run("ssp2_validate.py", [package()]);
    let lines: Vec<&str> = report.lines().collect();

    // THEN it is valid (both parameter sets too), SSP 2.0, with the harness's components,
    assert!(
        lines.contains(&"validated ssd and 2 parameter sets"),
        "{report}"
    );
    assert!(lines.contains(&"system paper version 2.0"), "{report}");
    for instance in &system.instances {
        let file = instance.fmu.file_name().unwrap().to_str().unwrap();
        let line = format!(
            "component {} application/x-fmu-sharedlibrary resources/{file}",
            instance.name
        );
        assert!(lines.contains(&line.as_str()), "{line}:\n{report}");
    }
    // the harness's connections, whole arrays from connector to connector,
    let mut read: Vec<&str> = lines
        .iter()
        .filter_map(|l| l.strip_prefix("connection "))
        .collect();
    let mut expected: Vec<String> = system
        .connections
        .iter()
        .map(|c| format!("{} -> {}", c.from, c.to))
        .collect();
    read.sort_unstable();
    expected.sort();
    assert_eq!(read, expected);
    assert_eq!(read.len(), 7, "5 navigation signals and 2 commands");
    // every declared connector with its FMI 3.0 type and dimension,
    for instance in &system.instances {
        for connector in instance.connectors.as_deref().unwrap_or_default() {
            let sizes: Vec<String> = connector.dimensions.iter().map(u64::to_string).collect();
            let line = format!(
                "typed {}.{} {} [{}]",
                instance.name,
                connector.name,
                connector.type_name.as_deref().unwrap_or("?"),
                sizes.join(" ")
            );
            assert!(lines.contains(&line.as_str()), "{line}:\n{report}");
        }
    }
    assert!(lines.contains(&"typed plant.r_nue Float64 [3]"), "{report}");
    // and every parameter value bit for bit, an array's list being its elements in order.
    let mut elements = 0;
    for line in lines.iter().filter_map(|l| l.strip_prefix("value ")) {
        let mut words = line.split(' ');
        let path = words.next().unwrap();
        let type_name = words.next().unwrap();
        let dimension = words.next().unwrap();
        let (instance, name) = path.split_once('.').unwrap();
        let parameters = &system.instance(instance).unwrap().parameters;
        for (k, text) in words.enumerate() {
            let element = match dimension {
                "[]" => name.to_owned(),
                _ => format!("{name}[{}]", k + 1),
            };
            let harness = parameters
                .iter()
                .find(|(n, _)| *n == element)
                .map(|(_, v)| v)
                .unwrap_or_else(|| panic!("the harness has no {instance}.{element}"));
            match (type_name, harness) {
                ("Float64", ParamValue::Real(x)) => {
                    assert_eq!(
                        text.parse::<f64>().unwrap().to_bits(),
                        x.to_bits(),
                        "{element}"
                    )
                }
                ("Int32", ParamValue::Integer(i)) => {
                    assert_eq!(text.parse::<i64>().unwrap(), *i, "{element}")
                }
                other => panic!("{instance}.{element}: {other:?}"),
            }
            elements += 1;
        }
    }
    let total: usize = system.instances.iter().map(|i| i.parameters.len()).sum();
    assert_eq!(
        elements, total,
        "every parameter the harness sets, no other"
    );
    assert_eq!(
        total, 11,
        "gnc: 3; plant: m0, q0_body_to_nue[1..4], r0_nue[1..3]"
    );
}

/// The validation script on a copy of the package's SSD with `edit` applied: its stderr.
fn refusal_of(edit: impl Fn(&str) -> String) -> String {
    let temp = tempfile::tempdir().unwrap();
    let shipped =
        std::fs::read_to_string(workspace_root().join("harness/scenarios/paper-fmi3.ssd")).unwrap();
    let broken = edit(&shipped);
    assert_ne!(broken, shipped, "the edit changed nothing");
    let path = temp.path().join("broken.ssd");
    std::fs::write(&path, broken).unwrap();
    let output = Command::new(python::venv_python())
        .arg(python::script("ssp2_validate.py"))
        .arg(&path)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!output.status.success(), "the broken SSD passed:\n{stderr}");
    stderr
}

#[test]
fn a_broken_copy_of_the_ssd_is_refused_by_the_schemas() {
    // A dimension before its connector's type: the SSD schema's order is type, then
    // dimensions.
    let error = refusal_of(|ssd| {
        ssd.replace(
            r#"<ssc:Float64/><ssc:Dimension size="3"/></ssd:Connector>"#,
            r#"<ssc:Dimension size="3"/><ssc:Float64/></ssd:Connector>"#,
        )
    });
    assert!(
        error.contains("SystemStructureDescription.xsd")
            && error.contains("SystemStructureCommon}Float64': This element is not expected"),
        "{error}"
    );
    // A list item that is not a double: only the parameter set's own schema sees it, the SSD
    // schema admits an inline parameter set laxly.
    let error =
        refusal_of(|ssd| ssd.replace(r#"value="0.0 800.0 0.0""#, r#"value="0.0 800.0 zero""#));
    assert!(
        error.contains("SystemStructureParameterValues.xsd")
            && error.contains("'zero' is not a valid value of the atomic type 'xs:double'"),
        "{error}"
    );
}
