use super::*;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The manifest Reference-FMUs ship with BouncingBall.
const BALL_MANIFEST: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiReferences
    xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
    xmlns:fmi-ls="http://fmi-standard.org/fmi-ls-manifest"
    fmi-ls:fmi-ls-name="org.fmi-standard.fmi-ls-ref"
    fmi-ls:fmi-ls-version="1.0.0-alpha.1">
    <Related type="text/csv" source="BouncingBall_out.csv" role="result" description="Output of the default experiment"/>
</fmiReferences>
"#;

const BALL_OUT: &str = "time,h,v\n0,1,0\n0.01,0.99955855,-0.0981\n0.02,0.9981361,-0.1962\n";

/// An archive of `files` at `dir/name`.
fn fmu(dir: &Path, name: &str, files: &[(&str, &str)]) -> PathBuf {
    let path = dir.join(name);
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&path).unwrap());
    for (file, text) in files {
        zip.start_file(*file, zip::write::SimpleFileOptions::default())
            .unwrap();
        zip.write_all(text.as_bytes()).unwrap();
    }
    zip.finish().unwrap();
    path
}

fn ls(file: &str) -> String {
    format!("{}/{file}", archive::DIR)
}

#[test]
fn a_reference_fmus_manifest_gives_the_default_experiment_and_its_result() {
    let dir = tempfile::tempdir().unwrap();
    let path = fmu(
        dir.path(),
        "BouncingBall.fmu",
        &[
            ("modelDescription.xml", "<fmiModelDescription/>"),
            (&ls("fmi-ls-manifest.xml"), BALL_MANIFEST),
            (&ls("BouncingBall_out.csv"), BALL_OUT),
        ],
    );
    let references = read(&path).unwrap().expect("it carries references");
    assert_eq!(references.experiments.len(), 1);
    let experiment = &references.experiments[0];
    assert_eq!(experiment.name, "DefaultExperiment");
    assert_eq!(
        (
            experiment.start_time,
            experiment.stop_time,
            experiment.step_size
        ),
        (None, None, None)
    );
    assert!(experiment.stimuli.is_none());
    assert_eq!(experiment.references[0].source, "BouncingBall_out.csv");
    assert_eq!(experiment.references[0].table.names, ["h", "v"]);
}

#[test]
fn an_fmu_without_the_folder_has_no_references() {
    let dir = tempfile::tempdir().unwrap();
    let path = fmu(
        dir.path(),
        "Plain.fmu",
        &[("modelDescription.xml", "<fmiModelDescription/>")],
    );
    assert_eq!(read(&path).unwrap(), None);
}

#[test]
fn a_manifest_naming_a_missing_csv_is_refused_naming_the_file_and_element() {
    let dir = tempfile::tempdir().unwrap();
    let manifest = BALL_MANIFEST.replace(
        "<Related type",
        "<Related source=\"notes.txt\" role=\"documentation\"/>\n    <Related type",
    );
    let path = fmu(
        dir.path(),
        "BouncingBall.fmu",
        &[(&ls("fmi-ls-manifest.xml"), &manifest)],
    );
    let problems = read(&path).unwrap_err();
    assert_eq!(problems.len(), 2, "{problems:#?}");
    let text = problems.join("\n");
    for expected in [
        "BouncingBall.fmu: extra/org.fmi-standard.fmi-ls-ref/fmi-ls-manifest.xml: \
         <Related source=\"BouncingBall_out.csv\"> (line 8): no such file in the FMU \
         (looked for extra/org.fmi-standard.fmi-ls-ref/BouncingBall_out.csv and \
         BouncingBall_out.csv)",
        "<Related source=\"notes.txt\"> (line 7): no such file in the FMU",
    ] {
        assert!(text.contains(expected), "{expected}\nnot in\n{text}");
    }
}

#[test]
fn an_experiments_file_gives_times_stimuli_references_and_tolerances() {
    let dir = tempfile::tempdir().unwrap();
    let experiments = r#"<Experiments>
  <Experiment name="step" startTime="0" stopTime="0.02" stepSize="0.01">
    <Parameters source="step.ssv"/>
    <Stimuli source="in.csv"/>
    <References source="resources/out.csv" relativeTolerance="0.01" absoluteTolerance="1e-6"/>
  </Experiment>
</Experiments>"#;
    let path = fmu(
        dir.path(),
        "M.fmu",
        &[
            (&ls("experiments.xml"), experiments),
            (&ls("in.csv"), "time,u\n0,0\n1,1\n"),
            (&ls("step.ssv"), "<ssv/>"),
            ("resources/out.csv", BALL_OUT),
        ],
    );
    let references = read(&path).unwrap().unwrap();
    let experiment = &references.experiments[0];
    assert_eq!(experiment.name, "step");
    assert_eq!(
        (
            experiment.start_time,
            experiment.stop_time,
            experiment.step_size
        ),
        (Some(0.0), Some(0.02), Some(0.01))
    );
    let stimuli = experiment.stimuli.as_ref().unwrap();
    assert_eq!(stimuli.table.names, ["u"]);
    assert_eq!(stimuli.text, "time,u\n0,0\n1,1\n");
    let given = experiment.references[0].tolerances;
    assert_eq!(
        (given.relative, given.absolute, given.time),
        (Some(0.01), Some(1e-6), None)
    );
    assert!(experiment.notes[0].contains("step.ssv is not applied"));
}

#[test]
fn every_problem_of_an_experiments_file_is_named_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let experiments = r#"<Experiments>
  <Experiment name="a" stopTime="soon">
    <Stimuli source="missing_in.csv"/>
    <References source="bad.csv" timeTolerance="3"/>
  </Experiment>
  <Experiment name="b"/>
</Experiments>"#;
    let path = fmu(
        dir.path(),
        "M.fmu",
        &[
            (&ls("experiments.xml"), experiments),
            (&ls("bad.csv"), "t,x\n0,1\n"),
        ],
    );
    let text = read(&path).unwrap_err().join("\n");
    for expected in [
        "<Experiment name=\"a\"> (line 2): stopTime=\"soon\" is not a finite number",
        "<Stimuli source=\"missing_in.csv\"> (line 3): no such file in the FMU",
        "<References source=\"bad.csv\"> (line 4): timeTolerance: 3 is not a number from 0 to 1",
        "<References source=\"bad.csv\"> (line 4): bad.csv: the first column is 't', not 'time'",
        "<Experiment name=\"b\">: no <References>",
    ] {
        assert!(text.contains(expected), "{expected}\nnot in\n{text}");
    }
}

fn trajectory(names: &[&str], times: &[f64], columns: &[Vec<f64>]) -> Trajectory {
    let mut values = Vec::new();
    for k in 0..times.len() {
        values.extend(columns.iter().map(|c| c[k]));
    }
    Trajectory {
        names: names.iter().map(|n| n.to_string()).collect(),
        times: times.to_vec(),
        values,
    }
}

fn experiment_of(csv: &str) -> Experiment {
    Experiment {
        name: "DefaultExperiment".into(),
        start_time: None,
        stop_time: None,
        step_size: None,
        stimuli: None,
        references: vec![archive::Reference {
            source: "M_out.csv".into(),
            table: table::ReferenceTable::parse_csv(csv).unwrap(),
            tolerances: ToleranceOverrides::default(),
            signals: Vec::new(),
        }],
        notes: Vec::new(),
    }
}

#[test]
fn a_run_is_judged_per_signal_by_its_instance_qualified_columns() {
    let times: Vec<f64> = (0..=100).map(|k| k as f64 * 0.01).collect();
    let x: Vec<f64> = times.iter().map(|t| t * t).collect();
    let mut csv = String::from("time,x,y,s,gone\n");
    for (t, x) in times.iter().zip(&x) {
        csv.push_str(&format!("{t},{x},1,text,0\n"));
    }
    let experiment = experiment_of(&csv);
    let run = trajectory(&["M.x"], &times, std::slice::from_ref(&x));
    let checked = compare(
        &run,
        Some("M"),
        &experiment,
        (0.0, 1.0),
        &Tolerances::default(),
        &ToleranceOverrides::default(),
        &|name| name != "gone",
    );
    assert!(
        checked.signals[0].passes(),
        "{}",
        checked.signals[0].describe()
    );
    assert_eq!(
        checked.signals[1].describe(),
        "y: FAIL: not among the run's columns"
    );
    assert!(!checked.passes());
    assert_eq!(
        checked.notes,
        [
            "s (M_out.csv): text, not compared",
            "gone (M_out.csv): no variable of this FMU the harness reads, not compared"
        ]
    );
    let cases = checked.cases();
    assert_eq!(cases[0].name, "reference DefaultExperiment: x");
    assert_eq!(cases[0].outcome, Outcome::Passed);
    assert!(matches!(&cases[1].outcome, Outcome::Failed(m) if m.contains("y: FAIL")));

    // A run that stopped early does not cover its reference.
    let short = trajectory(&["M.x"], &times[..50], &[x[..50].to_vec()]);
    let checked = compare(
        &short,
        Some("M"),
        &experiment,
        (0.0, 1.0),
        &Tolerances::default(),
        &ToleranceOverrides::default(),
        &|name| name != "gone",
    );
    assert!(checked.signals[0]
        .describe()
        .contains("the run ended at t = 0.49 s, before the reference's end at 1 s"));
}

#[test]
fn the_command_lines_tolerances_win_over_the_references_which_win_over_the_defaults() {
    let csv = "time,x\n0,0\n0.5,0.5\n1,1\n";
    let mut experiment = experiment_of(csv);
    experiment.references[0].tolerances.relative = Some(0.5);
    let run = trajectory(&["x"], &[0.0, 0.5, 1.0], &[vec![0.0, 0.8, 1.0]]);
    let judge = |given: ToleranceOverrides| {
        compare(
            &run,
            None,
            &experiment,
            (0.0, 1.0),
            &Tolerances::default(),
            &given,
            &|_| true,
        )
        .passes()
    };
    // 0.3 off a reference of range 1: inside 0.5, outside 0.1.
    assert!(judge(ToleranceOverrides::default()));
    assert!(!judge(ToleranceOverrides {
        relative: Some(0.1),
        ..Default::default()
    }));
}

#[test]
fn a_reference_that_ends_early_expects_the_run_to_stop_there_too() {
    let experiment = experiment_of("time,x\n0,0\n0.5,1\n0.72,2\n");
    let run = |end: f64| trajectory(&["x"], &[0.0, 0.5, end], &[vec![0.0, 1.0, 2.0]]);
    assert_eq!(
        early_end(&experiment, &run(0.72), 1.0, 0.01),
        Some(Ok(0.72))
    );
    let on = early_end(&experiment, &run(1.0), 1.0, 0.01)
        .unwrap()
        .unwrap_err();
    assert!(on.contains("the references end at t = 0.72 s"), "{on}");
    assert!(on.contains("this run ended at t = 1 s"), "{on}");
    // A reference to the stop says nothing of the end.
    let whole = experiment_of("time,x\n0,0\n1,1\n");
    assert_eq!(early_end(&whole, &run(0.72), 1.0, 0.01), None);
}

#[test]
fn a_reference_that_names_no_variable_of_the_fmu_fails() {
    let experiment = experiment_of("time,a,b\n0,0,0\n1,1,1\n");
    let run = trajectory(&["x"], &[0.0, 1.0], &[vec![0.0, 1.0]]);
    let checked = compare(
        &run,
        None,
        &experiment,
        (0.0, 1.0),
        &Tolerances::default(),
        &ToleranceOverrides::default(),
        &|_| false,
    );
    assert!(!checked.passes());
    assert!(checked.signals[0]
        .describe()
        .contains("no reference column names a variable of this FMU"));
}

#[test]
fn signal_elements_select_the_columns_compared() {
    let dir = tempfile::tempdir().unwrap();
    let experiments = r#"<Experiments>
  <Experiment name="some" stopTime="0.02">
    <References source="out.csv">
      <Signal name="v"/>
      <Signal name="w"/>
    </References>
  </Experiment>
</Experiments>"#;
    let path = fmu(
        dir.path(),
        "M.fmu",
        &[
            (&ls("experiments.xml"), experiments),
            (&ls("out.csv"), BALL_OUT),
        ],
    );
    let references = read(&path).unwrap().unwrap();
    let experiment = &references.experiments[0];
    assert_eq!(experiment.references[0].signals, ["v", "w"]);
    let run = trajectory(
        &["M.h", "M.v"],
        &[0.0, 0.01, 0.02],
        &[
            vec![1.0, 0.99955855, 0.9981361],
            vec![0.0, -0.0981, -0.1962],
        ],
    );
    let checked = compare(
        &run,
        Some("M"),
        experiment,
        (0.0, 0.02),
        &Tolerances::default(),
        &ToleranceOverrides::default(),
        &|_| true,
    );
    let names: Vec<&str> = checked.signals.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["w", "v"]);
    assert!(checked.signals[0]
        .describe()
        .contains("a <Signal> names it, out.csv has no such column"));
    assert!(checked.signals[1].passes());
}
