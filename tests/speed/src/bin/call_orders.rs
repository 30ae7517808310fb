//! Instructions per closed-loop step of the paper flight through the C ABI, in three call
//! orders, against the plain Rust loop of the same math (the floor).
//!
//! `call_orders count` runs `call_orders fly` once per order under callgrind, counting only
//! inside `measured_flight` (no start-up, loading or instantiation), checks that the plain
//! loop and the read-then-step loop end in the same state bit for bit, and prints the table.
//! `cargo xtask bench` runs it after the wall-clock table.
#![deny(unsafe_code)]

use anyhow::{ensure, Context, Result};
use clap::{Parser, Subcommand};
use speed_bench::c_master::{self, Variant};
use speed_bench::call_orders::{measured_flight, Order, Pair, PAPER_STEPS};
use speed_bench::{c_floor, callgrind};
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "call_orders",
    about = "Instructions per closed-loop step in each call order, against plain Rust"
)]
struct Cli {
    /// Folder with LanderGnc.fmu and LanderPlant.fmu.
    #[arg(long, global = true, default_value = "target/fmu")]
    fmu_dir: PathBuf,
    /// Steps of 0.01 s (the paper flight: 17,200).
    #[arg(long, global = true, default_value_t = PAPER_STEPS)]
    steps: usize,
    /// Load each FMU's binary from this folder of the same build, unstripped
    /// (`libfmu_gnc.so`, `libfmu_plant.so`), so callgrind can name the functions and count
    /// the GNC's evaluations; by default the archives' own (stripped) binaries.
    #[arg(long, global = true)]
    binaries: Option<PathBuf>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Fly once in one order; print the plant's final navigation outputs as bit patterns.
    Fly {
        #[arg(long, value_enum)]
        order: Order,
        /// FMI version of the entry points: 2 or 3.
        #[arg(long, default_value_t = 2)]
        fmi: u8,
    },
    /// Count every order under callgrind and print the table, then the C master's.
    Count,
    /// Only the C master's table: every FMI version, call order and list variant.
    Variants,
    /// The C master in one FMI version, call order and list variant under callgrind, its
    /// `run_loop` counted; the callgrind file is kept for `callgrind_annotate`.
    Profile {
        #[arg(long, value_enum)]
        order: Order,
        #[arg(long, default_value_t = 2)]
        fmi: u8,
        /// contract, sorted, reversed, shuffled, reshuffled or per-value.
        #[arg(long, default_value = "per-value")]
        variant: String,
        /// Where callgrind writes its file.
        #[arg(long, default_value = "callgrind.out.profile")]
        out: PathBuf,
    },
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Command::Fly { order, fmi } => {
            let mut pair = Pair::new(order, fmi, &cli.fmu_dir, cli.binaries.as_deref())?;
            let nav = measured_flight(&mut pair, order, cli.steps)?;
            let bits: Vec<String> = nav
                .iter()
                .map(|x| format!("{:016x}", x.to_bits()))
                .collect();
            println!("{}", bits.join(" "));
            Ok(())
        }
        Command::Count => count(&cli),
        Command::Profile {
            order,
            fmi,
            ref variant,
            ref out,
        } => {
            let variant = Variant::ALL
                .into_iter()
                .find(|v| v.name() == variant)
                .with_context(|| format!("no list variant named {variant}"))?;
            let scratch = tempfile::tempdir()?;
            let exe = c_master::compile(scratch.path())?;
            let plan = c_master::Plan::new(&cli.fmu_dir, fmi, cli.binaries.as_deref())?;
            let counts = plan.profile(&exe, order, variant, cli.steps, out)?;
            println!(
                "{:.0} instructions per step; callgrind file {}",
                counts.instructions as f64 / cli.steps as f64,
                out.display()
            );
            Ok(())
        }
        Command::Variants => {
            ensure!(
                callgrind::available(),
                "valgrind is not installed (Debian: sudo apt-get install valgrind)"
            );
            let scratch = tempfile::tempdir()?;
            let c_exe = c_floor::compile(scratch.path())?;
            let c_counts =
                c_floor::count(&c_exe, scratch.path()).context("counting the C floor")?;
            variants(&cli, c_counts.instructions as f64 / c_floor::STEPS as f64)
        }
    }
}

fn count(cli: &Cli) -> Result<()> {
    ensure!(
        callgrind::available(),
        "valgrind is not installed (Debian: sudo apt-get install valgrind)"
    );
    let me = std::env::current_exe()?;
    let scratch = tempfile::tempdir()?;
    let mut rows = Vec::new();
    let runs = Order::ALL
        .into_iter()
        .map(|order| (order, 2))
        .chain(Order::ALL[1..].iter().map(|&order| (order, 3)));
    for (order, fmi) in runs {
        let mut args: Vec<String> = [
            "--fmu-dir",
            &cli.fmu_dir.display().to_string(),
            "--steps",
            &cli.steps.to_string(),
        ]
        .map(String::from)
        .to_vec();
        if let Some(dir) = &cli.binaries {
            args.extend(["--binaries".into(), dir.display().to_string()]);
        }
        args.extend(["fly", "--order", order.name(), "--fmi", &fmi.to_string()].map(String::from));
        let counts = callgrind::count(&me, &args, "*measured_flight*", scratch.path())
            .with_context(|| format!("counting {} (FMI {fmi})", order.name()))?;
        rows.push((order, fmi, counts));
    }
    // The floor must be the same flight: plain and read-then-step agree bit for bit, and
    // FMI 3.0 flies what FMI 2.0 flies in every order.
    let fly = |order: Order, fmi: u8| -> Result<String> {
        let mut pair = Pair::new(order, fmi, &cli.fmu_dir, cli.binaries.as_deref())?;
        let nav = measured_flight(&mut pair, order, cli.steps)?;
        Ok(format!("{:?}", nav.map(f64::to_bits)))
    };
    ensure!(
        fly(Order::Plain, 2)? == fly(Order::ReadThenStep, 2)?,
        "the plain loop and the FMUs (read, then step) flew different flights"
    );
    for order in &Order::ALL[1..] {
        ensure!(
            fly(*order, 2)? == fly(*order, 3)?,
            "FMI 2.0 and FMI 3.0 flew different flights ({})",
            order.name()
        );
    }
    // The C floor flies the paper flight in plain C; its final state is compared with the
    // plain Rust loop's (the same equations, evaluated in a different order in places).
    let c_exe = c_floor::compile(scratch.path())?;
    let c_counts = c_floor::count(&c_exe, scratch.path()).context("counting the C floor")?;
    let c_per_step = c_counts.instructions as f64 / c_floor::STEPS as f64;
    let c_state = c_floor::final_state(&c_exe)?;
    let steps = cli.steps as f64;
    let floor = rows[0].2.instructions as f64 / steps;
    if cli.steps == c_floor::STEPS {
        let mut pair = Pair::new(Order::Plain, 2, &cli.fmu_dir, None)?;
        let rust_state = measured_flight(&mut pair, Order::Plain, cli.steps)?;
        print_state_comparison(&c_state, &rust_state);
    } else {
        println!(
            "(the C floor flies {} steps whatever --steps says; its count is per its own step)\n",
            c_floor::STEPS
        );
    }
    println!(
        "Instructions per closed-loop step, paper flight ({} steps of 0.01 s, both FMUs), \
         callgrind:\n",
        cli.steps
    );
    // A debug build's plain loop is unoptimised Rust (tens of times the optimised one)
    // while the FMUs it loads are release builds: a ratio to it would say nothing.
    let debug = cfg!(debug_assertions);
    if debug {
        println!(
            "(a debug build: the plain loop is unoptimised, so its count, and every \
             comparison with it, means nothing; `cargo xtask bench` runs the release build)\n"
        );
    }
    let against_plain = |per_step: f64| {
        if debug {
            ("(debug)".to_string(), "(debug)".to_string())
        } else {
            (
                format!("{:.2}x", per_step / floor),
                format!("{:+.0}", per_step - floor),
            )
        }
    };
    println!(
        "| FMI | Call order | Instructions per step | Ratio to C floor | Ratio to plain | \
         Over plain | GNC evaluations per step |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    let (ratio, over) = against_plain(c_per_step);
    println!(
        "| none | C floor: the same math in plain C (tests/speed/c, cc -O2), `run_loop` | \
         {c_per_step:.0} | 1.00x | {ratio} | {over} | 1.000 |"
    );
    for (order, fmi, counts) in &rows {
        let per_step = counts.instructions as f64 / steps;
        // One call of `gnc_outputs` (never inlined) is one evaluation of the attitude law.
        let evaluations = counts.calls_of("gnc_outputs") as f64 / steps;
        let version = if *order == Order::Plain {
            "none".to_string()
        } else {
            format!("{fmi}.0")
        };
        // Stripped binaries hide the function names.
        let evaluations = if evaluations > 0.0 {
            format!("{evaluations:.3}")
        } else {
            "(stripped: use --binaries)".to_string()
        };
        let (ratio, over) = against_plain(per_step);
        println!(
            "| {version} | {} | {:.0} | {:.2}x | {ratio} | {over} | {evaluations} |",
            order.describe(),
            per_step,
            per_step / c_per_step,
        );
    }
    if cli.steps < c_floor::STEPS {
        println!(
            "\n(a flight of {} steps: the flight's one-off calls, such as the read before \
             the first step, which evaluates the GNC once more, weigh more per step than on \
             the paper flight's {})",
            cli.steps,
            c_floor::STEPS
        );
    }
    println!();
    variants(cli, c_per_step)
}

/// The C master's table: each FMI version and call order, with the value references listed
/// in each variant, against the C floor (`c_per_step` instructions per step), and the worst
/// variant of each call order. Refuses to print unless every variant flies what the Rust
/// master flies in that order, bit for bit.
fn variants(cli: &Cli, c_per_step: f64) -> Result<()> {
    let scratch = tempfile::tempdir()?;
    let exe = c_master::compile(scratch.path())?;
    let binaries = cli.binaries.as_deref();
    let steps = cli.steps as f64;
    let orders = [Order::ReadThenStep, Order::StepThenRead, Order::Jacobi];
    let mut rows = Vec::new();
    let mut worst = Vec::new();
    for fmi in [2, 3] {
        let plan = c_master::Plan::new(&cli.fmu_dir, fmi, binaries)?;
        for order in orders {
            let mut pair = Pair::new(order, fmi, &cli.fmu_dir, binaries)?;
            let expected = measured_flight(&mut pair, order, cli.steps)?.map(f64::to_bits);
            let mut worst_here = (0.0, Variant::Contract);
            for variant in Variant::ALL {
                let flown = plan.fly(&exe, order, variant, cli.steps)?.map(f64::to_bits);
                ensure!(
                    flown == expected,
                    "the C master ({}, {}, FMI {fmi}) flew another flight than the Rust master",
                    order.name(),
                    variant.name()
                );
                let counts = plan
                    .count(&exe, order, variant, cli.steps, scratch.path())
                    .with_context(|| {
                        format!(
                            "counting the C master ({} {})",
                            order.name(),
                            variant.name()
                        )
                    })?;
                let per_step = counts.instructions as f64 / steps;
                if per_step > worst_here.0 {
                    worst_here = (per_step, variant);
                }
                rows.push((fmi, order, variant, per_step));
            }
            worst.push((fmi, order, worst_here));
        }
    }
    println!(
        "Instructions per closed-loop step in a native C master (tests/speed/c/\
         list_orders_master.c, official headers), by how it lists the value references; \
         C floor {c_per_step:.0}:\n"
    );
    println!(
        "| FMI | Call order | Value references listed | Instructions per step | Ratio to C floor |"
    );
    println!("| --- | --- | --- | --- | --- |");
    for (fmi, order, variant, per_step) in &rows {
        println!(
            "| {fmi}.0 | {} | {} | {per_step:.0} | {:.2}x |",
            order.name(),
            variant.describe(),
            per_step / c_per_step
        );
    }
    println!("\nThe worst variant of each call order:\n");
    println!("| FMI | Call order | Worst variant | Instructions per step | Ratio to C floor |");
    println!("| --- | --- | --- | --- | --- |");
    for (fmi, order, (per_step, variant)) in &worst {
        println!(
            "| {fmi}.0 | {} | {} | {per_step:.0} | {:.2}x |",
            order.name(),
            variant.describe(),
            per_step / c_per_step
        );
    }
    Ok(())
}

/// How far the C floor's final state lies from the plain Rust loop's, component by component.
fn print_state_comparison(c: &[f64; 14], rust: &[f64; 14]) {
    const NAMES: [&str; 14] = [
        "r_nue[1]", "r_nue[2]", "r_nue[3]", "v_nue[1]", "v_nue[2]", "v_nue[3]", "q[1]", "q[2]",
        "q[3]", "q[4]", "omega[1]", "omega[2]", "omega[3]", "mass",
    ];
    let equal = c
        .iter()
        .zip(rust)
        .filter(|(a, b)| a.to_bits() == b.to_bits())
        .count();
    println!(
        "Final state after the paper flight, C floor against the plain Rust loop: \
         {equal} of 14 components bit for bit equal."
    );
    println!("\n| Output | C floor | plain Rust | difference |\n| --- | --- | --- | --- |");
    for ((name, a), b) in NAMES.iter().zip(c).zip(rust) {
        println!("| {name} | {a:.12e} | {b:.12e} | {:.2e} |", a - b);
    }
    println!();
}
