//! Terminals (FMI 3.0 `terminalsAndIcons.xml`): the paper scenario with the FMI 3.0 pair
//! wired by one line per terminal (docs/examples/paper-terminals.toml) flies the trajectory
//! of the same pair wired signal by signal, bit for bit; connections between terminals that
//! do not match are refused before the run, naming the members.
use crate::common::harness;
use std::fs;
use std::path::Path;

fn example() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/examples/paper-terminals.toml");
    fs::read_to_string(path).unwrap()
}

/// The scenario with its terminal connections replaced by `connections`.
fn with_connections(connections: &str) -> String {
    let text = example();
    let start = text.find("[[connection]]").unwrap();
    let end = text.find("# Limits a review").unwrap();
    format!("{}{connections}\n{}", &text[..start], &text[end..])
}

fn run(dir: &Path, label: &str, text: &str) -> (std::process::Output, String) {
    let toml = dir.join(format!("{label}.toml"));
    let csv = dir.join(format!("{label}.csv"));
    fs::write(&toml, text).unwrap();
    let output = harness(&["run", toml.to_str().unwrap(), "-o", csv.to_str().unwrap()]);
    let recorded = fs::read_to_string(&csv).unwrap_or_default();
    (output, recorded)
}

#[test]
fn two_terminal_lines_fly_the_paper_as_the_eight_signal_connections_do() {
    // GIVEN the example (two terminal connections) and the same pair wired signal by signal,
    // the eight members the two terminals of each FMU share
    let temp = tempfile::tempdir().unwrap();
    let mut signals = String::new();
    for (from, to, names) in [
        (
            "plant",
            "gnc",
            &["r_nue", "v_nue", "q_body_to_nue", "omega_body", "mass"][..],
        ),
        (
            "gnc",
            "plant",
            &["thrust_cmd", "torque_cmd_body", "rcs_duty"][..],
        ),
    ] {
        for name in names {
            signals.push_str(&format!(
                "[[connection]]\nfrom = \"{from}.{name}\"\nto = \"{to}.{name}\"\n"
            ));
        }
    }
    // WHEN both are flown
    let (terminals, csv_terminals) = run(temp.path(), "terminals", &example());
    let (single, csv_single) = run(temp.path(), "signals", &with_connections(&signals));
    // THEN both pass with the same verdict and every recorded value equal
    for output in [&terminals, &single] {
        assert!(
            output.status.success(),
            "{}{}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
    }
    let stdout = String::from_utf8_lossy(&terminals.stdout);
    assert!(
        stdout.contains("verdict: completed at t = 172.00 s"),
        "{stdout}"
    );
    assert_eq!(csv_terminals.lines().count(), 17_202);
    assert!(csv_terminals == csv_single, "the trajectories differ");
}

#[test]
fn terminals_that_do_not_match_are_refused_naming_the_members() {
    let temp = tempfile::tempdir().unwrap();
    // GIVEN the plant's kinematics terminal (no mass, a specific force) wired to the GNC's
    // navigation terminal, a terminal wired to a single variable, and an unknown terminal
    let text = with_connections(
        "[[connection]]\nfrom = \"plant.kinematics\"\nto = \"gnc.navigation\"\n\
         [[connection]]\nfrom = \"gnc.commands\"\nto = \"plant.thrust_cmd\"\n\
         [[connection]]\nfrom = \"plant.nowhere\"\nto = \"gnc.navigation\"\n",
    );
    // WHEN it is run
    let (output, _) = run(temp.path(), "mismatch", &text);
    // THEN it is refused before any step, with every problem named
    assert_eq!(output.status.code(), Some(1), "{output:?}");
    let stderr = String::from_utf8_lossy(&output.stderr);
    for expected in [
        "the source terminal 'kinematics' is a plug, and its members specific_force_body find \
         no match",
        "the destination terminal 'navigation' is a plug, and its members mass find no match",
        "'gnc.commands' is a terminal but 'plant.thrust_cmd' is not",
        "'gnc.navigation' is a terminal but 'plant.nowhere' is not",
    ] {
        assert!(
            stderr.contains(expected),
            "missing {expected:?} in\n{stderr}"
        );
    }
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn the_full_stack_by_terminals_flies_as_the_full_fidelity_scenario_wired_by_signal() {
    let temp = tempfile::tempdir().unwrap();
    // GIVEN the full-fidelity scenario with its FMI 3.0 FMUs, as shipped (twenty signal
    // connections) and wired by terminals: plant -> sensors -> filter -> GNC -> plant, the
    // filter's navigation a bus without the mass, which the GNC's plug takes from the plant
    // on a line of its own
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/full-fidelity.toml");
    let shipped = fs::read_to_string(path)
        .unwrap()
        .replace("fmu = \"", "fmu = \"fmi3/");
    let start = shipped.find("[[connection]]").unwrap();
    let end = start
        + shipped[start..]
            .find("\n\n# What this run must do")
            .unwrap();
    let terminals = format!(
        "{}{}{}",
        &shipped[..start],
        "[[connection]]\nfrom = \"plant.kinematics\"\nto = \"sensors.kinematics\"\n\
         [[connection]]\nfrom = \"sensors.measurements\"\nto = \"filter.measurements\"\n\
         [[connection]]\nfrom = \"filter.navigation\"\nto = \"gnc.navigation\"\n\
         [[connection]]\nfrom = \"plant.mass\"\nto = \"gnc.mass\"\n\
         [[connection]]\nfrom = \"gnc.commands\"\nto = \"plant.commands\"\n",
        &shipped[end..]
    );
    // WHEN both fly the first 5 s
    let fly = |label: &str, text: &str| {
        let toml = temp.path().join(format!("{label}.toml"));
        let csv = temp.path().join(format!("{label}.csv"));
        fs::write(&toml, text).unwrap();
        let output = harness(&[
            "run",
            toml.to_str().unwrap(),
            "--stop-time",
            "5",
            "-o",
            csv.to_str().unwrap(),
        ]);
        assert!(
            matches!(output.status.code(), Some(0 | 3)),
            "{label}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        fs::read_to_string(&csv).unwrap()
    };
    let by_signal = fly("signals", &shipped);
    let by_terminal = fly("terminals", &terminals);
    // THEN every recorded value is the same
    assert_eq!(by_terminal.lines().count(), 502);
    assert!(by_terminal == by_signal, "the trajectories differ");
}
