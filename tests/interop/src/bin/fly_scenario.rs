//! Flies a scenario file (.toml, .ssd) in the harness and writes the trajectory as CSV (the
//! harness's format), for FMUs whose binary needs its process prepared: pythonfmu3's, like
//! pythonfmu's, calls into a Python interpreter it does not link, so this process is started
//! with libpython preloaded (`LD_PRELOAD`), `PYTHONHOME` naming that Python's installation
//! and `PYTHONPATH` the packages the FMU imports (tests/interop/tests/pythonfmu3.rs).
//!
//! It ends with `_exit`, not by returning from `main`, once the results are written and every
//! instance freed and library closed: pythonfmu3 0.3.4's Linux binary cannot be unloaded
//! (libstdc++'s `STB_GNU_UNIQUE` symbols make it `NODELETE`), so its teardown runs at process
//! exit, where the `atexit` destructor of its static `shared_ptr<PyState>` frees the state
//! and its ELF destructor (`onLibraryUnload`, `finalizePythonInterpreter`) then assigns to
//! that destroyed `shared_ptr`, reading and releasing the freed block. Valgrind shows the
//! invalid reads on every run; glibc aborts on the corrupted heap ("free(): corrupted unsorted
//! chunks", exit status 134) on the runs whose heap layout exposes it (with some FMU paths,
//! every time), after everything the harness did has succeeded.
//!
//! The CSV is streamed as `harness run` writes it, with column types: integers as integers,
//! an Int64 or UInt64 exact, strings as text, Binary in hex.
//!
//! Usage: fly_scenario SCENARIO OUT.csv
use anyhow::Result;
use cosim::master::Simulation;
use cosim::results::{Format, Stream};
use std::io::Write;

fn fly(scenario: &str, out_csv: &str) -> Result<()> {
    let system = lander::scenarios::load(scenario)?;
    let mut simulation = Simulation::new(system, &interop_tests::fmu_dir())?;
    let mut stream = Stream::create_typed(
        out_csv.as_ref(),
        simulation.column_names(),
        simulation.column_units(),
        &simulation.column_types(),
        Format::Csv,
    )?;
    let end = simulation.run(&mut stream)?;
    drop(simulation);
    let rows = stream.finish()?;
    println!("fly_scenario: {rows} rows, {end:?}");
    Ok(())
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let status = match args.as_slice() {
        [scenario, out_csv] => fly(scenario, out_csv),
        _ => Err(anyhow::anyhow!("usage: fly_scenario SCENARIO OUT.csv")),
    }
    .map_or_else(
        |e| {
            eprintln!("fly_scenario: {e:#}");
            1
        },
        |()| 0,
    );
    let _ = std::io::stdout().flush();
    let _ = std::io::stderr().flush();
    exit_without_teardown(status)
}

/// `_exit(2)`: ends the process without running `atexit` handlers or ELF destructors (see
/// the module comment).
#[allow(unsafe_code)]
fn exit_without_teardown(status: i32) -> ! {
    extern "C" {
        fn _exit(status: i32) -> !;
    }
    // SAFETY: `_exit` takes any status and does not return; the results are written and
    // the standard streams flushed.
    unsafe { _exit(status) }
}
