//! The C floor: the same closed loop as plain C (`c/closed_loop_floor.c`: guidance at 10 Hz,
//! the decoupled law, the flat 6-DOF plant with RK4 at 0.01 s, both FMUs' defaults), compiled
//! at run time with `$CC` (default `cc`) at `-O2` and counted with callgrind inside its
//! `run_loop`, as the Rust loops are counted inside `measured_flight`.
use crate::call_orders::PAPER_STEPS;
use crate::callgrind::{self, Counts};
use anyhow::{anyhow, ensure, Context, Result};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The C source, built into the binary so the bench needs no source tree at run time.
pub const SOURCE: &str = include_str!("../c/closed_loop_floor.c");

/// Steps the C loop flies (fixed in its `main`): the paper flight.
pub const STEPS: usize = PAPER_STEPS;

/// Compiles the floor into `dir`; returns the executable.
pub fn compile(dir: &Path) -> Result<PathBuf> {
    let source = dir.join("closed_loop_floor.c");
    std::fs::write(&source, SOURCE)?;
    let exe = dir.join("closed_loop_floor");
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    // -g only names the functions for callgrind; it does not change the code.
    let output = Command::new(&cc)
        .args(["-O2", "-g", "-o"])
        .arg(&exe)
        .arg(&source)
        .arg("-lm")
        .output()
        .with_context(|| format!("running the C compiler {cc}"))?;
    ensure!(
        output.status.success(),
        "{cc} -O2 closed_loop_floor.c failed:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    Ok(exe)
}

/// The final plant state `[r(3), v(3), q(4, scalar first), omega(3), m]` of one flight.
pub fn final_state(exe: &Path) -> Result<[f64; 14]> {
    let output = Command::new(exe).output()?;
    ensure!(output.status.success(), "{} failed", exe.display());
    parse_bits(&String::from_utf8_lossy(&output.stdout))
}

pub fn parse_bits(stdout: &str) -> Result<[f64; 14]> {
    let line = stdout
        .lines()
        .find_map(|l| l.strip_prefix("bits"))
        .ok_or_else(|| anyhow!("no bits line in the C floor's output"))?;
    let mut x = [0.0; 14];
    let mut words = line.split_whitespace();
    for slot in &mut x {
        let word = words.next().ok_or_else(|| anyhow!("fewer than 14 bits"))?;
        *slot = f64::from_bits(u64::from_str_radix(word, 16)?);
    }
    Ok(x)
}

/// Instructions inside `run_loop` (one flight of [`STEPS`] steps).
pub fn count(exe: &Path, out_dir: &Path) -> Result<Counts> {
    callgrind::count(exe, &[], "run_loop", out_dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bits_line_is_read_exactly() {
        let text = "final 1 2\nbits 3ff0000000000000 4000000000000000 0 0 0 0 0 0 0 0 0 0 0 \
                    c08c800000000000\n";
        let x = parse_bits(text).unwrap();
        assert_eq!(x[0], 1.0);
        assert_eq!(x[1], 2.0);
        assert_eq!(x[13], -912.0);
    }
}
