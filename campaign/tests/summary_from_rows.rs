//! A campaign's summary comes from the rows it wrote, not from its manifest read back: the
//! summary (table, `summary.csv`, failed flights) of the rows a run returns equals the one of
//! its manifest, fresh and resumed, and the manifest is parsed only to resume. Needs the
//! packaged FMUs (`cargo xtask fmus`).
use campaign::dispersion::DispersionRanges;
use campaign::{manifest, runner, summary, summary_csv};
use campaign::{CampaignSpec, Shard};
use lander::laws::Law;
use std::path::{Path, PathBuf};

fn fmu_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/fmu");
    assert!(
        dir.join("LanderGnc.fmu").is_file(),
        "{} holds no FMUs: run `cargo xtask fmus` first",
        dir.display()
    );
    dir
}

/// What the report of a campaign shows from `rows`: the printed table, `summary.csv`'s bytes
/// and the failed flights.
fn summary_of(rows: &[manifest::Row], dir: &Path) -> (String, Vec<u8>, Vec<String>) {
    let (_, paper) = lander::scenarios::spec::load("paper").unwrap();
    let requirements = lander::scenarios::spec::requirements("paper")
        .unwrap()
        .len();
    std::fs::create_dir_all(dir).unwrap();
    let path = summary_csv::write(rows, paper.expect, requirements, dir).unwrap();
    (
        summary::table(&summary::summarise(rows)),
        std::fs::read(path).unwrap(),
        summary_csv::failed_lines(rows),
    )
}

#[test]
fn a_campaigns_summary_is_its_manifests_and_the_manifest_is_not_read_back() {
    let spec = CampaignSpec {
        scenario: "paper".into(),
        seed: 11,
        phi_cmd_deg: vec![0.0, 150.0],
        laws: vec![Law::COUPLED, Law::DECOUPLED],
        runs_per_point: 2,
        dispersions: DispersionRanges::default(),
        sets: Vec::new(),
    };
    let dir = tempfile::tempdir().unwrap();
    let options = runner::RunOptions {
        fmu_dir: fmu_dir(),
        out_dir: dir.path().join("campaign"),
        workers: 2,
        shard: Shard::WHOLE,
        progress: false,
    };
    let reads = manifest::reads_on_this_thread;

    // A fresh campaign parses no manifest.
    let before = reads();
    let fresh = runner::run(&spec, &options).unwrap();
    assert_eq!(reads(), before, "a fresh campaign read its manifest back");
    assert_eq!(fresh.rows.len(), 8);
    let written = manifest::read(&fresh.manifest).unwrap();
    let expected = summary_of(&written, &dir.path().join("read"));
    assert_eq!(summary_of(&fresh.rows, &dir.path().join("kept")), expected);

    // GIVEN the campaign cut to its first three rows, one of them to be flown again
    let text = std::fs::read_to_string(&fresh.manifest).unwrap();
    let cut: Vec<&str> = text.lines().take(4).collect();
    std::fs::write(&fresh.manifest, cut.join("\n") + "\n").unwrap();
    let resume = runner::Resume { rerun: vec![1] };
    // WHEN it is resumed
    let before = reads();
    let resumed = runner::run_resumed(&spec, &options, Some(&resume)).unwrap();
    // THEN the manifest is parsed once, for the resume check, and the summary is the
    // manifest's, which is the uninterrupted campaign's
    assert_eq!(
        reads() - before,
        1,
        "a resumed campaign read its manifest twice"
    );
    assert_eq!((resumed.kept, resumed.flights), (2, 6));
    assert_eq!(std::fs::read_to_string(&resumed.manifest).unwrap(), text);
    let written = manifest::read(&resumed.manifest).unwrap();
    let from_file = summary_of(&written, &dir.path().join("read-resumed"));
    assert_eq!(
        summary_of(&resumed.rows, &dir.path().join("kept-resumed")),
        from_file
    );
    assert_eq!(from_file, expected);
}
