//! How a run's dispersed inputs are drawn: one uniform number per input from the run's own
//! stream (random), or placed in the run's stratum of that input (Latin hypercube); then,
//! with correlations, through the Gaussian copula; then each distribution's quantile.
//!
//! Run `j`'s uniforms come from `ChaCha8Rng::seed_from_u64(run_seed(seed, j))`
//! ([`crate::seed::run_seed`]), one 53-bit number per input in declaration order, so a run is
//! a function of the campaign seed and `j`. Latin hypercube: the runs' strata of input `d` are
//! a permutation of `0..runs` (Fisher-Yates from ChaCha8 stream 1 of
//! `run_seed(seed, d)`), and run `j`'s number is `(stratum + v) / runs` with `v` its uniform:
//! exactly one run in each of the `runs` equal-probability strata of every input.
use crate::generic::distribution::{normal_cdf, normal_quantile};
use crate::seed::run_seed;
use cosim::system::campaign_table::Correlation;
use rand::{Rng, RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sampling {
    Random,
    LatinHypercube,
}

/// A uniform number in the open interval (0, 1): the 53 high bits, offset by half a unit.
fn open_unit(rng: &mut ChaCha8Rng) -> f64 {
    ((rng.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

/// The `dims` uniforms of the run seeded with `run_seed`; with `strata` (each input's
/// stratum of this run, and the run count), placed in them.
pub fn uniforms(run_seed: u64, dims: usize, strata: Option<(&[u64], u64)>) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(run_seed);
    (0..dims)
        .map(|d| {
            let v = open_unit(&mut rng);
            match strata {
                Some((strata, runs)) => (strata[d] as f64 + v) / runs as f64,
                None => v,
            }
        })
        .collect()
}

/// The stratum of each of `runs` runs in input `dim`: a seeded permutation of `0..runs`.
pub fn strata(seed: u64, dim: u64, runs: u64) -> Vec<u64> {
    let mut rng = ChaCha8Rng::seed_from_u64(run_seed(seed, dim));
    rng.set_stream(1);
    let mut order: Vec<u64> = (0..runs).collect();
    for i in (1..order.len()).rev() {
        let j = rng.gen_range(0..=i);
        order.swap(i, j);
    }
    order
}

/// The correlation matrix of the dispersed inputs `names` from the `[[campaign.correlation]]`
/// entries (`None` without any), every bad entry named.
pub fn correlation(
    names: &[&str],
    entries: &[Correlation],
) -> Result<Option<Vec<Vec<f64>>>, Vec<String>> {
    if entries.is_empty() {
        return Ok(None);
    }
    let n = names.len();
    let mut matrix: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| f64::from(u8::from(i == j))).collect())
        .collect();
    let mut problems = Vec::new();
    let mut seen = Vec::new();
    for entry in entries {
        let at = format!("[[campaign.correlation]] between = {:?}", entry.between);
        if !(entry.rho > -1.0 && entry.rho < 1.0) {
            problems.push(format!("{at}: rho = {} is not inside (-1, 1)", entry.rho));
        }
        let [a, b] = entry.between.as_slice() else {
            problems.push(format!(
                "{at}: names {} parameters, not 2",
                entry.between.len()
            ));
            continue;
        };
        let index = |name: &str| names.iter().position(|n| *n == name);
        let (Some(i), Some(j)) = (index(a), index(b)) else {
            for name in [a, b].into_iter().filter(|name| index(name).is_none()) {
                problems.push(format!(
                    "{at}: \"{name}\" is not a [[campaign.dispersion]] parameter"
                ));
            }
            continue;
        };
        if i == j {
            problems.push(format!("{at}: a parameter with itself"));
            continue;
        }
        if seen.contains(&(i.min(j), i.max(j))) {
            problems.push(format!("{at}: the pair is correlated twice"));
        }
        seen.push((i.min(j), i.max(j)));
        matrix[i][j] = entry.rho;
        matrix[j][i] = entry.rho;
    }
    if problems.is_empty() {
        Ok(Some(matrix))
    } else {
        Err(problems)
    }
}

/// The lower Cholesky factor of the correlation matrix `m`; refused when `m` is not
/// positive definite, naming the correlated pairs of the input where it fails.
pub fn cholesky(m: &[Vec<f64>], names: &[&str]) -> Result<Vec<Vec<f64>>, Vec<String>> {
    let n = m.len();
    let mut l = vec![vec![0.0; n]; n];
    for j in 0..n {
        let diagonal = m[j][j] - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>();
        if diagonal <= 1e-12 {
            let pairs: Vec<String> = (0..n)
                .filter(|&k| k != j && m[j][k] != 0.0)
                .map(|k| format!("\"{}\" and \"{}\" (rho = {})", names[k], names[j], m[j][k]))
                .collect();
            return Err(vec![format!(
                "[[campaign.correlation]]: the correlations are not positive definite (no \
                 joint distribution has them); the conflict shows at \"{}\", correlated as {}",
                names[j],
                pairs.join(", ")
            )]);
        }
        l[j][j] = diagonal.sqrt();
        for i in j + 1..n {
            let off = m[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>();
            l[i][j] = off / l[j][j];
        }
    }
    Ok(l)
}

/// The Gaussian copula: independent uniforms `u` to standard normals, mixed by the
/// correlation's Cholesky factor `l`, back to uniforms.
pub fn correlate(u: &[f64], l: &[Vec<f64>]) -> Vec<f64> {
    let z: Vec<f64> = u.iter().map(|&u| normal_quantile(u)).collect();
    l.iter()
        .map(|row| normal_cdf(row.iter().zip(&z).map(|(a, b)| a * b).sum()))
        .collect()
}
