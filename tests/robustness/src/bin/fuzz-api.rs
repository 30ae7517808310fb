//! The long API fuzzing run:
//! `cargo run --release -p robustness-tests --bin fuzz-api -- --calls 1000000 --seed 1`
//! (needs `cargo xtask fmus` first). Exit status 1 with the offending sequence on the first
//! violated invariant; the watchdog aborts the process on a hang.
use clap::Parser;
use robustness_tests::fuzz::{self, Watchdog};
use robustness_tests::instance::Fmu;
use robustness_tests::package::Lander;
use std::time::{Duration, Instant};

#[derive(Parser)]
#[command(about = "Random call sequences over the 34 FMI functions of the packaged lander FMUs")]
struct Args {
    /// Fuzz calls per FMU (at least; the last sequence is completed).
    #[arg(long, default_value_t = 1_000_000)]
    calls: u64,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// LanderGnc, LanderPlant, LanderNav, LanderSensors or LanderFilter; all five when absent.
    #[arg(long)]
    fmu: Option<String>,
    /// Longest time one call may take before the run is declared hung, s.
    #[arg(long, default_value_t = 10.0)]
    call_limit: f64,
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let landers: Vec<Lander> = match &args.fmu {
        Some(name) => {
            vec![Lander::parse(name).ok_or_else(|| anyhow::anyhow!("unknown FMU {name}"))?]
        }
        None => Lander::all(),
    };
    let dog = Watchdog::start(Duration::from_secs_f64(args.call_limit));
    for lander in landers {
        let fmu = Fmu::load(lander)?;
        let started = Instant::now();
        let mut next_report = args.calls / 10;
        let stats = fuzz::run(&fmu, args.calls, args.seed, &dog, |s| {
            if s.fuzz_calls >= next_report {
                eprintln!(
                    "{}: {} calls in {} sequences",
                    lander.model_identifier(),
                    s.fuzz_calls,
                    s.sequences
                );
                next_report += args.calls / 10;
            }
        })
        .map_err(|e| anyhow::anyhow!(e))?;
        let [ok, warning, discard, error, fatal] = stats.statuses;
        println!(
            "{}: seed {}, {} fuzz calls in {} sequences ({:.1} s), {} check calls; statuses: \
             fmi2OK {ok}, Warning {warning}, Discard {discard}, Error {error}, Fatal {fatal}; \
             {} predicted refusals confirmed, {} NULL instances, {} crafted states accepted, \
             {} instances beyond reset after a crafted state; no crash, no hang (limit {:?}), \
             no invariant violated",
            lander.model_identifier(),
            args.seed,
            stats.fuzz_calls,
            stats.sequences,
            started.elapsed().as_secs_f64(),
            stats.check_calls,
            stats.predicted_refusals,
            stats.null_instances,
            stats.crafted_accepted,
            stats.fatal_after_crafted,
            dog.limit(),
        );
    }
    Ok(())
}
