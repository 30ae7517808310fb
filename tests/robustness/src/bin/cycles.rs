//! The leak check: instantiate/initialize/step/free cycles of each lander FMU,
//! printing VmRSS along the way. Run it under valgrind for leaks:
//! `valgrind --leak-check=full --errors-for-leak-kinds=definite --error-exitcode=99 \
//!   target/release/cycles --cycles 10000`
use clap::Parser;
use robustness_tests::cycles::cycle;
use robustness_tests::instance::Fmu;
use robustness_tests::package::Lander;
use robustness_tests::reference::Wiring;
use robustness_tests::rss::vm_rss_kib;

#[derive(Parser)]
#[command(about = "Instantiate/initialize/step/free cycles of the packaged lander FMUs")]
struct Args {
    #[arg(long, default_value_t = 10_000)]
    cycles: usize,
    /// LanderGnc, LanderPlant, LanderNav, LanderSensors or LanderFilter; all five when absent.
    #[arg(long)]
    fmu: Option<String>,
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let landers: Vec<Lander> = match &args.fmu {
        Some(name) => {
            vec![Lander::parse(name).ok_or_else(|| anyhow::anyhow!("unknown FMU {name}"))?]
        }
        None => Lander::all(),
    };
    for lander in landers {
        let fmu = Fmu::load(lander)?;
        let wiring = Wiring::of(&fmu);
        let mut samples = Vec::new();
        for k in 0..args.cycles {
            cycle(&fmu, &wiring, k).map_err(|e| anyhow::anyhow!(e))?;
            if (k + 1) % (args.cycles / 10).max(1) == 0 {
                samples.push(vm_rss_kib().unwrap_or(0));
            }
        }
        let after_first = samples.first().copied().unwrap_or(0);
        let last = samples.last().copied().unwrap_or(0);
        println!(
            "{}: {} cycles; VmRSS at each tenth (KiB): {samples:?}; growth after the first tenth: {} KiB",
            lander.model_identifier(),
            args.cycles,
            last as i64 - after_first as i64
        );
    }
    Ok(())
}
