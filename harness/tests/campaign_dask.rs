//! `harness monte-carlo --dask tcp://...` against a Dask scheduler and two workers started
//! here (the venv's dask), each worker with a working directory and `--local-directory` of
//! its own, the client in a third: the workers get the harness, the FMUs and the scenario
//! file only through their tasks, and each task runs in a directory under its worker's
//! local directory. The merged campaign equals the one flown locally, manifest.csv byte for
//! byte; with a worker killed mid-campaign, its lost shard is flown again by the other and
//! the manifest is the same. `harness campaign --dask` flies a scenario campaign (the
//! Oscillator example, as TOML and as an SSD with its sidecar) the same way. Without dask and
//! distributed, `--dask` says which module is missing and how to install it.
use crate::common;

use std::io::{BufRead, BufReader};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

fn venv_python() -> PathBuf {
    let python = common::workspace_root().join(".venv/bin/python");
    assert!(
        python.is_file(),
        "{} is missing: run `cargo xtask python-env` (or `cargo xtask test`, which does)",
        python.display()
    );
    python
}

/// A process of the cluster in a process group of its own (killed with it, its children
/// too), with its stderr gathered by a thread.
struct Process {
    child: Child,
    log: Arc<Mutex<String>>,
}

impl Process {
    fn start(command: &mut Command) -> Process {
        let mut child = command
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .process_group(0)
            .spawn()
            .unwrap();
        let log = Arc::new(Mutex::new(String::new()));
        let stderr = child.stderr.take().unwrap();
        let gathered = Arc::clone(&log);
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                let mut log = gathered.lock().unwrap();
                log.push_str(&line);
                log.push('\n');
            }
        });
        Process { child, log }
    }

    fn log(&self) -> String {
        self.log.lock().unwrap().clone()
    }

    /// Waits until the log holds `text`; returns the rest of its line.
    fn wait_for(&self, text: &str) -> String {
        let started = Instant::now();
        loop {
            if let Some(line) = self.log().lines().find(|l| l.contains(text)) {
                return line[line.find(text).unwrap() + text.len()..]
                    .trim()
                    .to_owned();
            }
            assert!(
                started.elapsed() < Duration::from_secs(90),
                "no '{text}' after 90 s:\n{}",
                self.log()
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    fn kill(&mut self) {
        // The group: the worker and the harness processes of its task.
        unsafe { libc::kill(-(self.child.id() as i32), libc::SIGKILL) };
        let _ = self.child.wait();
    }
}

impl Drop for Process {
    fn drop(&mut self) {
        self.kill();
    }
}

/// A scheduler and two single-threaded workers without nanny (a killed worker stays dead),
/// each in its own temporary directory; the worker's address and local directory.
struct Cluster {
    scheduler: Process,
    address: String,
    workers: Vec<(Process, String, PathBuf)>,
    _dirs: tempfile::TempDir,
}

impl Cluster {
    fn start() -> Cluster {
        let dirs = tempfile::tempdir().unwrap();
        let python = venv_python();
        let scheduler_dir = dirs.path().join("scheduler");
        std::fs::create_dir(&scheduler_dir).unwrap();
        let scheduler = Process::start(
            Command::new(&python)
                .args([
                    "-m",
                    "dask",
                    "scheduler",
                    "--host",
                    "127.0.0.1",
                    "--port",
                    "0",
                ])
                .arg("--no-dashboard")
                .current_dir(&scheduler_dir),
        );
        let address = scheduler.wait_for("Scheduler at:");
        let workers = ["a", "b"]
            .into_iter()
            .map(|name| {
                let dir = dirs.path().join(format!("worker-{name}"));
                std::fs::create_dir(&dir).unwrap();
                let worker = Process::start(
                    Command::new(&python)
                        .args(["-m", "dask", "worker", &address, "--name", name])
                        .args(["--nthreads", "1", "--no-nanny", "--no-dashboard"])
                        .args(["--host", "127.0.0.1", "--local-directory"])
                        .arg(&dir)
                        .current_dir(&dir),
                );
                (worker, dir)
            })
            .collect::<Vec<_>>()
            .into_iter()
            .map(|(worker, dir)| {
                let at = worker.wait_for("Start worker at:");
                worker.wait_for("Registered to:");
                (worker, at, dir)
            })
            .collect();
        Cluster {
            scheduler,
            address,
            workers,
            _dirs: dirs,
        }
    }
}

/// The scenario file the campaigns fly: the paper's, copied into the client's directory, so
/// that its bytes have to travel with the tasks.
fn scenario_in(client: &Path) -> String {
    let dir = client.join("my-scenarios");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(
        common::workspace_root().join("harness/scenarios/paper.toml"),
        dir.join("paper-copy.toml"),
    )
    .unwrap();
    "my-scenarios/paper-copy.toml".to_owned()
}

/// `harness monte-carlo` in `cwd` with the campaign and `extra` options.
fn monte_carlo(cwd: &Path, campaign: &[&str], extra: &[&str]) -> Command {
    harness_in(cwd, "monte-carlo", campaign, extra)
}

/// `harness SUBCOMMAND` in `cwd` with the campaign and `extra` options.
fn harness_in(cwd: &Path, subcommand: &str, campaign: &[&str], extra: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_harness"));
    command
        .current_dir(cwd)
        .arg("--fmu-dir")
        .arg(common::fmu_dir())
        .arg(subcommand)
        .args(campaign)
        .args(extra)
        .env("HARNESS_PYTHON", venv_python())
        .env("RUST_BACKTRACE", "0");
    command
}

fn text(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr)
}

/// The local campaign's manifest.csv and exit code.
fn local_manifest(client: &Path, campaign: &[&str]) -> (Vec<u8>, Option<i32>) {
    let output = monte_carlo(client, campaign, &["--out-dir", "local", "--quiet"])
        .output()
        .unwrap();
    // 3: flown, some flights outside the paper scenario's limits.
    assert!(
        matches!(output.status.code(), Some(0 | 3)),
        "{}",
        text(&output)
    );
    (
        std::fs::read(client.join("local/manifest.csv")).unwrap(),
        output.status.code(),
    )
}

/// The `dask: shard k/S flown by ADDRESS in DIR` lines: (address, dir) per shard.
fn flown_by(stdout: &str) -> Vec<(String, String)> {
    stdout
        .lines()
        .filter_map(|line| {
            let rest = line.split_once(" flown by ")?.1;
            let (address, rest) = rest.split_once(" in ")?;
            let dir = rest.split_once(" (")?.0;
            Some((address.to_owned(), dir.to_owned()))
        })
        .collect()
}

/// Every shard was flown by one of the cluster's workers, in a directory under that
/// worker's own local directory; returns the shards per worker.
fn check_flown_on(cluster: &Cluster, stdout: &str, shards: usize) -> Vec<usize> {
    let flown = flown_by(stdout);
    assert_eq!(flown.len(), shards, "one line per shard:\n{stdout}");
    let mut per_worker = vec![0; cluster.workers.len()];
    for (address, dir) in &flown {
        let index = cluster
            .workers
            .iter()
            .position(|(_, at, _)| at == address)
            .unwrap_or_else(|| panic!("{address} is none of the cluster's workers:\n{stdout}"));
        let local = &cluster.workers[index].2;
        assert!(
            Path::new(dir).starts_with(local),
            "{dir} is not under {}'s local directory {}",
            address,
            local.display()
        );
        per_worker[index] += 1;
    }
    per_worker
}

/// The task directories (`harness-dask-*`) under a worker's local directory.
fn task_dirs(local: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut look = vec![(local.to_owned(), 0)];
    while let Some((dir, depth)) = look.pop() {
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let path = entry.path();
            if entry
                .file_name()
                .to_string_lossy()
                .starts_with("harness-dask-")
            {
                found.push(path);
            } else if depth < 2 && path.is_dir() {
                look.push((path, depth + 1));
            }
        }
    }
    found
}

/// `SUBCOMMAND CAMPAIGN --out-dir OUT --dask ADDRESS --dask-shards=S` in `client`, ended with
/// `code`, every shard flown on the cluster: its stdout and the shards per worker.
fn on_cluster(
    cluster: &Cluster,
    client: &Path,
    (subcommand, campaign, out): (&str, &[&str], &str),
    shards: usize,
    code: Option<i32>,
) -> (String, Vec<usize>) {
    let output = harness_in(
        client,
        subcommand,
        campaign,
        &["--out-dir", out, "--dask", &cluster.address],
    )
    .arg(format!("--dask-shards={shards}"))
    .output()
    .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert_eq!(output.status.code(), code, "{}", text(&output));
    let per_worker = check_flown_on(cluster, &stdout, shards);
    (stdout, per_worker)
}

/// The merged campaign in `client/out` names `scenario` and every worker of the cluster in
/// its campaign.toml, and its store of shards is removed.
fn check_merged(cluster: &Cluster, client: &Path, out: &str, scenario: &str) {
    let toml = std::fs::read_to_string(client.join(out).join("campaign.toml")).unwrap();
    assert!(
        toml.contains(&format!("scenario = \"{scenario}\"")),
        "the scenario as the user named it:\n{toml}"
    );
    for (_, address, _) in &cluster.workers {
        assert!(toml.contains(address.as_str()), "{address} in:\n{toml}");
    }
    assert!(
        !client.join(format!("{out}.dask-shards")).exists(),
        "the shards are removed once merged"
    );
}

/// `--resume` into `again` with a shard already in its store, which is not flown again: shard 2
/// of 4 flown here as a task flies it, its scenario (`campaign[at]`, a file in `client`)
/// named as the workers name it. The resumed run's stdout.
fn resume_with_a_stored_shard(
    cluster: &Cluster,
    client: &Path,
    (subcommand, campaign, at): (&str, &[&str], usize),
    code: Option<i32>,
) -> String {
    let name = Path::new(campaign[at]).file_name().unwrap();
    std::fs::create_dir_all(client.join("scenario")).unwrap();
    std::fs::copy(
        client.join(campaign[at]),
        client.join("scenario").join(name),
    )
    .unwrap();
    let on_workers = format!("scenario/{}", name.to_str().unwrap());
    let mut as_on_workers = campaign.to_vec();
    as_on_workers[at] = &on_workers;
    let shard = harness_in(
        client,
        subcommand,
        &as_on_workers,
        &["--shard", "2/4", "--workers", "1", "--quiet"],
    )
    .args(["--out-dir", "again.dask-shards/shard-2-of-4"])
    .output()
    .unwrap();
    assert!(
        matches!(shard.status.code(), Some(0 | 3)),
        "{}",
        text(&shard)
    );
    let resumed = harness_in(
        client,
        subcommand,
        campaign,
        &["--out-dir", "again", "--dask", &cluster.address, "--resume"],
    )
    .output()
    .unwrap();
    let stdout = String::from_utf8_lossy(&resumed.stdout).into_owned();
    assert_eq!(resumed.status.code(), code, "{}", text(&resumed));
    assert!(stdout.contains("shards done before: 1"), "{stdout}");
    check_flown_on(cluster, &stdout, 3);
    assert!(!stdout.contains("shard 2/4 flown"), "{stdout}");
    stdout
}

#[test]
fn a_dask_campaign_on_two_workers_without_shared_paths_equals_the_local_campaign() {
    let started = Instant::now();
    let cluster = Cluster::start();
    let client = tempfile::tempdir().unwrap();
    let scenario = scenario_in(client.path());
    let campaign = [
        "--scenario",
        &scenario,
        "-n",
        "8",
        "--phi-cmd-deg",
        "0,150",
        "--law",
        "decoupled,coupled",
        "--seed",
        "11",
        "--no-plots",
    ];
    let (local, local_code) = local_manifest(client.path(), &campaign);

    let (stdout, per_worker) = on_cluster(
        &cluster,
        client.path(),
        ("monte-carlo", &campaign, "dask"),
        4,
        local_code,
    );
    assert!(
        per_worker.iter().all(|&n| n > 0),
        "both workers flew shards: {per_worker:?}\n{stdout}"
    );
    assert!(stdout.contains("32/32 flights"), "{stdout}");
    assert!(
        std::fs::read(client.path().join("dask/manifest.csv")).unwrap() == local,
        "manifest.csv differs from the local campaign's"
    );
    check_merged(&cluster, client.path(), "dask", &scenario);

    let resumed_stdout = resume_with_a_stored_shard(
        &cluster,
        client.path(),
        ("monte-carlo", &campaign, 1),
        local_code,
    );
    assert!(
        resumed_stdout.contains("4 shards of 32 flights"),
        "{resumed_stdout}"
    );
    assert!(
        std::fs::read(client.path().join("again/manifest.csv")).unwrap() == local,
        "the resumed campaign's manifest.csv differs from the local campaign's"
    );
    println!(
        "dask campaign test: {:.1} s\n{stdout}{resumed_stdout}",
        started.elapsed().as_secs_f64()
    );
}

#[test]
fn a_worker_killed_mid_campaign_loses_no_shard() {
    let started = Instant::now();
    let mut cluster = Cluster::start();
    let client = tempfile::tempdir().unwrap();
    let scenario = scenario_in(client.path());
    let campaign = [
        "--scenario",
        &scenario,
        "-n",
        "8",
        "--phi-cmd-deg",
        "0,150",
        "--law",
        "decoupled,coupled",
        "--seed",
        "5",
        "--no-plots",
    ];
    let (local, local_code) = local_manifest(client.path(), &campaign);

    let mut run = monte_carlo(
        client.path(),
        &campaign,
        &["--out-dir", "dask", "--dask", &cluster.address],
    )
    .arg("--dask-shards=6")
    .stdout(Stdio::piped())
    .stderr(Stdio::piped())
    .spawn()
    .unwrap();
    // The first shard done: its worker has already been given its next one (a worker holds
    // up to two tasks of a queue); killing it loses that shard.
    let mut lines = BufReader::new(run.stdout.take().unwrap()).lines();
    let mut stdout = String::new();
    let first = loop {
        let line = lines
            .next()
            .expect("the campaign ended before a shard was flown")
            .unwrap();
        stdout += &line;
        stdout.push('\n');
        if let Some((address, _)) = flown_by(&line).pop() {
            break address;
        }
    };
    let killed = cluster
        .workers
        .iter()
        .position(|(_, at, _)| *at == first)
        .unwrap();
    // Killed while it flies its next shard: a task's directory is there (the finished one's
    // was removed before its result came back).
    let waiting = Instant::now();
    while task_dirs(&cluster.workers[killed].2).is_empty() {
        assert!(
            waiting.elapsed() < Duration::from_secs(30),
            "{first} took no second shard"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    cluster.workers[killed].0.kill();
    for line in lines {
        stdout += &line.unwrap();
        stdout.push('\n');
    }
    let status = run.wait().unwrap();
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut run.stderr.take().unwrap(), &mut stderr).unwrap();
    assert_eq!(status.code(), local_code, "{stdout}{stderr}");

    let killed_address = cluster.workers[killed].1.clone();
    let removed = cluster
        .scheduler
        .wait_for(&format!("Remove worker addr: {killed_address}"));
    println!("scheduler: Remove worker addr: {killed_address} {removed}");
    let per_worker = check_flown_on(&cluster, &stdout, 6);
    let survivor = 1 - killed;
    assert!(
        per_worker[survivor] >= 6 - per_worker[killed] && per_worker[killed] >= 1,
        "{per_worker:?}\n{stdout}"
    );
    assert!(
        std::fs::read(client.path().join("dask/manifest.csv")).unwrap() == local,
        "manifest.csv differs from the local campaign's"
    );
    println!(
        "dask worker-loss test: {:.1} s\n{stdout}",
        started.elapsed().as_secs_f64()
    );
}

#[test]
fn without_dask_installed_the_missing_module_and_the_pip_command_are_named() {
    let client = tempfile::tempdir().unwrap();
    // The venv's Python with `distributed` unimportable.
    let site = client.path().join("site");
    std::fs::create_dir(&site).unwrap();
    std::fs::write(
        site.join("sitecustomize.py"),
        "import sys\nsys.modules['distributed'] = None\n",
    )
    .unwrap();
    let output = monte_carlo(
        client.path(),
        &["-n", "1", "--phi-cmd-deg", "0", "--law", "decoupled"],
        &["--dask", "local:1", "--out-dir", "mc"],
    )
    .env("PYTHONPATH", &site)
    .output()
    .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output));
    assert!(
        stderr.contains("no Python module 'distributed'")
            && stderr.contains("-m pip install dask distributed"),
        "{stderr}"
    );
    assert!(!client.path().join("mc/manifest.csv").exists());
}

#[test]
fn options_a_dask_campaign_cannot_honour_are_refused() {
    let client = tempfile::tempdir().unwrap();
    let output = monte_carlo(
        client.path(),
        &["-n", "1", "--shard", "1/2"],
        &["--dask", "local:1"],
    )
    .output()
    .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output));
    assert!(stderr.contains("--dask cannot honour --shard"), "{stderr}");
}

/// The Oscillator example in the client's directory, as TOML (`osc.toml`) and as an SSD
/// (`osc.ssd`) whose sidecar `osc.campaign.toml` declares the same campaign; the SSD names
/// its FMU by the file name alone, found in the FMU directory.
fn oscillator_in(client: &Path) -> (String, String) {
    let dir = client.join("my-scenarios");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(
        common::workspace_root().join("docs/examples/oscillator-campaign.toml"),
        dir.join("osc.toml"),
    )
    .unwrap();
    common::oscillator_campaign_ssd(&dir);
    (
        "my-scenarios/osc.toml".to_owned(),
        "my-scenarios/osc.ssd".to_owned(),
    )
}

/// `harness campaign` run locally into `out`: its exit code (0, or 3 when a run failed its
/// requirements).
fn local_campaign(client: &Path, campaign: &[&str], out: &str) -> Option<i32> {
    let output = harness_in(client, "campaign", campaign, &["--out-dir", out, "--quiet"])
        .output()
        .unwrap();
    assert!(
        matches!(output.status.code(), Some(0 | 3)),
        "{}",
        text(&output)
    );
    output.status.code()
}

#[test]
fn a_dask_scenario_campaign_on_two_workers_equals_the_local_campaign() {
    let started = Instant::now();
    let cluster = Cluster::start();
    let client = tempfile::tempdir().unwrap();
    let (toml, ssd) = oscillator_in(client.path());
    let campaign = [toml.as_str(), "-n", "6", "--seed", "3"];
    let local_code = local_campaign(client.path(), &campaign, "local");
    let read = |dir: &str, file: &str| std::fs::read(client.path().join(dir).join(file)).unwrap();

    let (stdout, per_worker) = on_cluster(
        &cluster,
        client.path(),
        ("campaign", &campaign, "dask"),
        4,
        local_code,
    );
    assert!(
        per_worker.iter().all(|&n| n > 0),
        "both workers ran shards: {per_worker:?}\n{stdout}"
    );
    assert!(
        stdout.contains("4 shards of 18 runs") && stdout.contains("18/18 runs"),
        "{stdout}"
    );
    for file in ["manifest.csv", "summary.csv", "sensitivity.csv"] {
        assert!(
            read("dask", file) == read("local", file),
            "{file} differs from the local campaign's"
        );
    }
    // The scenario by its absolute path here, as a local campaign names it.
    let here = std::path::absolute(client.path().join(&toml)).unwrap();
    check_merged(&cluster, client.path(), "dask", &here.display().to_string());

    let resumed_stdout = resume_with_a_stored_shard(
        &cluster,
        client.path(),
        ("campaign", &campaign, 0),
        local_code,
    );
    assert!(
        read("again", "manifest.csv") == read("local", "manifest.csv"),
        "the resumed campaign's manifest.csv differs from the local campaign's"
    );

    // An SSD: its sidecar travels beside it, its FMU from the FMU directory.
    let ssd_campaign = [ssd.as_str(), "-n", "4"];
    let ssd_code = local_campaign(client.path(), &ssd_campaign, "ssd-local");
    let (ssd_stdout, _) = on_cluster(
        &cluster,
        client.path(),
        ("campaign", &ssd_campaign, "ssd-dask"),
        2,
        ssd_code,
    );
    assert!(
        read("ssd-dask", "manifest.csv") == read("ssd-local", "manifest.csv"),
        "the SSD campaign's manifest.csv differs from the local campaign's"
    );
    println!(
        "dask scenario campaign test: {:.1} s\n{stdout}{resumed_stdout}{ssd_stdout}",
        started.elapsed().as_secs_f64()
    );
}

#[test]
fn a_dask_scenario_campaign_refuses_what_it_cannot_honour() {
    let client = tempfile::tempdir().unwrap();
    let (toml, _) = oscillator_in(client.path());
    let output = harness_in(
        client.path(),
        "campaign",
        &[&toml, "--workers", "2"],
        &["--dask", "local:1"],
    )
    .output()
    .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output));
    assert!(
        stderr.contains("--dask cannot honour --workers"),
        "{stderr}"
    );
}
