//! The long run (10 million communication steps per FMU by default):
//! `cargo run --release -p robustness-tests --bin long-run -- --steps 10000000`
use clap::Parser;
use robustness_tests::instance::Fmu;
use robustness_tests::long_run;
use robustness_tests::package::Lander;
use std::time::Instant;

#[derive(Parser)]
#[command(
    about = "Millions of steps of the packaged lander FMUs with invariants and state restores"
)]
struct Args {
    #[arg(long, default_value_t = 10_000_000)]
    steps: usize,
    /// Save/serialize/restore checks spread over the run.
    #[arg(long, default_value_t = 20)]
    checkpoints: usize,
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
        let started = Instant::now();
        let r =
            long_run::run(&fmu, args.steps, args.checkpoints).map_err(|e| anyhow::anyhow!(e))?;
        let rss_min = r.rss_kib.iter().min().copied().unwrap_or(0);
        let rss_max = r.rss_kib.iter().max().copied().unwrap_or(0);
        println!(
            "{}: {} steps in {:.1} s, all outputs finite; max | |q| - 1 | = {:.3e}; \
             max relative angular-momentum drift = {:.3e}; {} bit-exact restores; \
             VmRSS at the checkpoints {rss_min}..{rss_max} KiB",
            lander.model_identifier(),
            r.steps,
            started.elapsed().as_secs_f64(),
            r.max_quaternion_norm_error,
            r.max_angular_momentum_drift,
            r.restores,
        );
        match lander {
            Lander::Sensors => println!(
                "LanderSensors: of {} probed steps, altimeter_valid true at {}, \
                 velocimeter_valid_1/_2/_3 at {:?}; every invalid measurement read 0",
                r.probed_steps,
                r.valid_counts[0],
                &r.valid_counts[1..]
            ),
            Lander::Filter => println!(
                "LanderFilter: of {} probed steps, {} with an altimeter update, velocimeter_dof \
                 0/1/2/3 at {:?}; covariance_diag in [{:.3e}, {:.3e}]; max |altitude error| \
                 {:.3} m, max |velocity error| {:.4} m/s",
                r.probed_steps,
                r.valid_counts[0],
                &r.valid_counts[1..],
                r.covariance_min,
                r.covariance_max,
                r.max_altitude_error_m,
                r.max_velocity_error_mps,
            ),
            _ => {}
        }
        if lander == Lander::Nav {
            println!(
                "LanderNav, errors on: {} of {} probed steps had outputs equal to the inputs",
                r.identity_steps, r.probed_steps
            );
            let started = Instant::now();
            let off = long_run::run_with(&fmu, args.steps, args.checkpoints, &[])
                .map_err(|e| anyhow::anyhow!(e))?;
            println!(
                "LanderNav, errors off: {} steps in {:.1} s; {} of {} probed steps had outputs \
                 equal to the inputs bit for bit; {} bit-exact restores",
                off.steps,
                started.elapsed().as_secs_f64(),
                off.identity_steps,
                off.probed_steps,
                off.restores,
            );
            if off.identity_steps != off.probed_steps || r.identity_steps != 0 {
                anyhow::bail!("LanderNav: errors on must change every step, errors off none");
            }
        }
    }
    Ok(())
}
