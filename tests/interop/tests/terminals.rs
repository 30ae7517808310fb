//! The FMI 3.0 FMUs' terminals and icons (`terminalsAndIcons/`), read by a reader we did not
//! write: each file valid against the FMI 3.0 XSD fmpy ships (lxml), each member a variable
//! of the FMU's own description, each icon a PNG (tests/interop/python/terminals_check.py);
//! and the groups that connect our FMUs to each other carry the same members with the
//! causalities that let them connect (outputs on one side, inputs on the other).
use interop_tests::python;
use serde_json::Value;
use std::collections::BTreeMap;
use system_tests::{fmi3_fmu_path, fmi3_fmus};

/// (FMU, terminal) -> memberName -> causality.
type Members = BTreeMap<String, String>;

fn members(fmus: &BTreeMap<String, Value>, fmu: &str, terminal: &str) -> Members {
    let t = &fmus[fmu]["terminals"][terminal];
    assert!(t.is_object(), "{fmu} has no terminal {terminal}");
    t["members"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(member, v)| (member.clone(), v[1].as_str().unwrap().to_owned()))
        .collect()
}

fn same_names(a: &Members, b: &Members) -> bool {
    a.keys().eq(b.keys())
}

fn all(m: &Members, causality: &str) -> bool {
    m.values().all(|c| c == causality)
}

#[test]
fn every_fmi3_fmu_carries_valid_terminals_and_an_icon_that_match_across_fmus() {
    let ids = fmi3_fmus();
    let report = python::run("terminals_check.py", ids.iter().map(|id| fmi3_fmu_path(id)));
    let fmus: BTreeMap<String, Value> = report
        .lines()
        .filter(|l| l.starts_with('{'))
        .map(|l| {
            let v: Value = serde_json::from_str(l).unwrap();
            let name = v["fmu"]
                .as_str()
                .unwrap()
                .trim_end_matches(".fmu")
                .to_owned();
            (name, v)
        })
        .collect();
    assert_eq!(fmus.len(), ids.len(), "{report}");
    for (name, fmu) in &fmus {
        assert_eq!(fmu["problems"], Value::Array(vec![]), "{name}: {fmu}");
    }
    // The lander FMUs have icons and the groups that wire them.
    for name in [
        "LanderGnc",
        "LanderPlant",
        "LanderNav",
        "LanderSensors",
        "LanderFilter",
    ] {
        assert_eq!(fmus[name]["icon"], Value::Bool(true), "{name}: no icon");
    }
    let gnc_nav = members(&fmus, "LanderGnc", "navigation");
    let gnc_cmd = members(&fmus, "LanderGnc", "commands");
    let plant_nav = members(&fmus, "LanderPlant", "navigation");
    let plant_cmd = members(&fmus, "LanderPlant", "commands");
    assert_eq!(gnc_nav.len(), 5);
    assert!(
        same_names(&gnc_nav, &plant_nav) && all(&gnc_nav, "input") && all(&plant_nav, "output")
    );
    assert_eq!(gnc_cmd.len(), 3);
    assert!(
        same_names(&gnc_cmd, &plant_cmd) && all(&gnc_cmd, "output") && all(&plant_cmd, "input")
    );
    let nav_truth = members(&fmus, "LanderNav", "truth");
    let nav_out = members(&fmus, "LanderNav", "navigation");
    assert!(same_names(&nav_truth, &plant_nav) && all(&nav_truth, "input"));
    assert!(same_names(&nav_out, &gnc_nav) && all(&nav_out, "output"));
    let kinematics = members(&fmus, "LanderPlant", "kinematics");
    let sensed = members(&fmus, "LanderSensors", "kinematics");
    assert!(same_names(&kinematics, &sensed) && all(&sensed, "input"));
    let measured = members(&fmus, "LanderSensors", "measurements");
    let filtered = members(&fmus, "LanderFilter", "measurements");
    assert!(
        same_names(&measured, &filtered) && all(&measured, "output") && all(&filtered, "input")
    );
    // The filter estimates no mass: its navigation is a bus of the GNC's other four members.
    let estimate = members(&fmus, "LanderFilter", "navigation");
    assert_eq!(
        fmus["LanderFilter"]["terminals"]["navigation"]["matchingRule"],
        "bus"
    );
    assert!(estimate.keys().all(|m| gnc_nav.contains_key(m)) && estimate.len() == 4);
}
