//! A checked `[campaign]`: the sweep points, the dispersed inputs with their distributions
//! and correlation, and how runs are numbered.
//!
//! Run `j` (0..runs) is one draw of every dispersed input; it is run at every sweep point
//! (common random numbers: the points are compared on the same draws). Its index is
//! `j * points + point`, the sweep points numbered with the first `[[campaign.sweep]]`
//! varying slowest. The draw of run `j` is a function of the campaign seed and `j` alone
//! ([`crate::generic::sampling`]).
use crate::generic::distribution::Distribution;
use crate::generic::sampling::{self, Sampling};
use crate::generic::target::Target;
use crate::seed::run_seed;
use cosim::system::campaign_table::Declaration;

/// The most runs a Latin hypercube campaign may have: its strata are a permutation of the
/// runs per dispersed parameter, held in memory (80 MB per parameter at this count).
pub const MAX_LATIN_HYPERCUBE_RUNS: u64 = 10_000_000;

#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    pub seed: u64,
    pub runs: u64,
    pub sampling: Sampling,
    /// Each swept input and its values.
    pub sweeps: Vec<(Target, Vec<f64>)>,
    pub dispersions: Vec<(Target, Distribution)>,
    /// The lower Cholesky factor of the inputs' correlation matrix (`None`: independent).
    pub cholesky: Option<Vec<Vec<f64>>>,
    /// Latin hypercube: the stratum of each run in each dimension.
    strata: Vec<Vec<u64>>,
}

/// One run of a campaign at one sweep point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RunId {
    pub index: u64,
    pub run: u64,
    pub run_seed: u64,
    pub point: u64,
}

impl Plan {
    /// Checks `declaration`, listing every problem with the key and value at fault.
    pub fn new(declaration: &Declaration) -> Result<Self, Vec<String>> {
        let mut problems = Vec::new();
        let d = declaration;
        if d.runs == 0 {
            problems.push("[campaign] runs = 0: a campaign needs at least one run".into());
        }
        let sampling = match d.sampling.as_str() {
            "random" => Sampling::Random,
            "latin-hypercube" if d.runs > MAX_LATIN_HYPERCUBE_RUNS => {
                problems.push(format!(
                    "[campaign] runs = {} with sampling = \"latin-hypercube\": at most {} (the \
                     strata of every run are held in memory, 8 bytes per run and parameter)",
                    d.runs, MAX_LATIN_HYPERCUBE_RUNS
                ));
                Sampling::LatinHypercube
            }
            "latin-hypercube" => Sampling::LatinHypercube,
            other => {
                problems.push(format!(
                    "[campaign] sampling = \"{other}\" is neither \"random\" nor \
                     \"latin-hypercube\""
                ));
                Sampling::Random
            }
        };
        let mut named: Vec<String> = Vec::new();
        let mut target = |problems: &mut Vec<String>, table: &str, text: &str| {
            let parsed = Target::parse(text)
                .map_err(|e| problems.push(format!("{table} {e}")))
                .ok();
            if named.iter().any(|n| n == text) {
                problems.push(format!(
                    "{table} parameter = \"{text}\" is swept or dispersed twice"
                ));
            }
            named.push(text.to_owned());
            parsed
        };
        let mut sweeps = Vec::new();
        for sweep in &d.sweep {
            let table = "[[campaign.sweep]]";
            let at = target(&mut problems, table, &sweep.parameter);
            let values = match (&sweep.values, sweep.grid) {
                (Some(values), None) => {
                    if values.is_empty() {
                        problems.push(format!("{table} {}: values = [] is empty", sweep.parameter));
                    }
                    if let Some(bad) = values.iter().find(|v| !v.is_finite()) {
                        problems.push(format!(
                            "{table} {}: value {bad} is not a finite number",
                            sweep.parameter
                        ));
                    }
                    values.clone()
                }
                (None, Some(grid)) => {
                    if grid.count == 0 || !grid.from.is_finite() || !grid.to.is_finite() {
                        problems.push(format!(
                            "{table} {}: grid = {{ from = {}, to = {}, count = {} }} needs \
                             finite ends and count >= 1",
                            sweep.parameter, grid.from, grid.to, grid.count
                        ));
                        Vec::new()
                    } else {
                        let step = match grid.count {
                            1 => 0.0,
                            n => (grid.to - grid.from) / (n - 1) as f64,
                        };
                        (0..grid.count)
                            .map(|i| match i + 1 == grid.count && grid.count > 1 {
                                true => grid.to,
                                false => grid.from + i as f64 * step,
                            })
                            .collect()
                    }
                }
                _ => {
                    problems.push(format!(
                        "{table} {}: give either values = [...] or grid = {{ from, to, count }}",
                        sweep.parameter
                    ));
                    Vec::new()
                }
            };
            if let Some(at) = at {
                sweeps.push((at, values));
            }
        }
        let mut dispersions = Vec::new();
        for dispersion in &d.dispersion {
            let table = "[[campaign.dispersion]]";
            let at = target(&mut problems, table, &dispersion.parameter);
            match Distribution::new(
                &dispersion.distribution,
                &crate::generic::distribution::Parameters::of(dispersion),
            ) {
                Ok(distribution) => {
                    if let Some(at) = at {
                        dispersions.push((at, distribution));
                    }
                }
                Err(found) => problems.extend(
                    found
                        .into_iter()
                        .map(|p| format!("{table} {}: {p}", dispersion.parameter)),
                ),
            }
        }
        let names: Vec<&str> = d.dispersion.iter().map(|x| x.parameter.as_str()).collect();
        let cholesky = sampling::correlation(&names, &d.correlation)
            .and_then(|m| m.map(|m| sampling::cholesky(&m, &names)).transpose())
            .unwrap_or_else(|found| {
                problems.extend(found);
                None
            });
        if !problems.is_empty() {
            return Err(problems);
        }
        let points: u64 = sweeps.iter().map(|(_, v)| v.len() as u64).product();
        if d.runs.checked_mul(points).is_none() {
            return Err(vec![format!("[campaign] runs = {}: too many runs", d.runs)]);
        }
        let strata = match sampling {
            Sampling::Random => Vec::new(),
            Sampling::LatinHypercube => (0..dispersions.len())
                .map(|dim| sampling::strata(d.seed, dim as u64, d.runs))
                .collect(),
        };
        Ok(Plan {
            seed: d.seed,
            runs: d.runs,
            sampling,
            sweeps,
            dispersions,
            cholesky,
            strata,
        })
    }

    /// The sweep points (the product of every sweep's values; 1 without sweeps).
    pub fn points(&self) -> u64 {
        self.sweeps.iter().map(|(_, v)| v.len() as u64).product()
    }

    /// Runs in the campaign: runs per point times points.
    pub fn total(&self) -> u64 {
        self.runs * self.points()
    }

    pub fn run_id(&self, index: u64) -> RunId {
        let points = self.points();
        let run = index / points;
        RunId {
            index,
            run,
            run_seed: run_seed(self.seed, run),
            point: index % points,
        }
    }

    /// The swept values of sweep point `point`, in sweep order.
    pub fn point_values(&self, point: u64) -> Vec<f64> {
        let mut rest = point;
        let mut values = vec![0.0; self.sweeps.len()];
        for (slot, (_, list)) in values.iter_mut().zip(&self.sweeps).rev() {
            let n = list.len() as u64;
            *slot = list[(rest % n) as usize];
            rest /= n;
        }
        values
    }

    /// The dispersed inputs' values of run `run`, in declaration order.
    pub fn draw(&self, run: u64) -> Vec<f64> {
        let strata: Vec<u64> = self.strata.iter().map(|s| s[run as usize]).collect();
        let u = sampling::uniforms(
            run_seed(self.seed, run),
            self.dispersions.len(),
            (!strata.is_empty()).then_some((strata.as_slice(), self.runs)),
        );
        let u = match &self.cholesky {
            Some(l) => sampling::correlate(&u, l),
            None => u,
        };
        self.dispersions
            .iter()
            .zip(u)
            .map(|((_, distribution), u)| distribution.quantile(u))
            .collect()
    }

    /// Every input of run `id` with its value: the swept ones, then the dispersed ones.
    pub fn inputs(&self, id: &RunId) -> Vec<(&Target, f64)> {
        let swept = self
            .sweeps
            .iter()
            .map(|(t, _)| t)
            .zip(self.point_values(id.point));
        let drawn = self
            .dispersions
            .iter()
            .map(|(t, _)| t)
            .zip(self.draw(id.run));
        swept.chain(drawn).collect()
    }

    /// The inputs' names, as the manifest heads their columns.
    pub fn input_names(&self) -> Vec<String> {
        let swept = self.sweeps.iter().map(|(t, _)| t.to_string());
        swept
            .chain(self.dispersions.iter().map(|(t, _)| t.to_string()))
            .collect()
    }

    pub fn targets(&self) -> impl Iterator<Item = &Target> {
        let swept = self.sweeps.iter().map(|(t, _)| t);
        swept.chain(self.dispersions.iter().map(|(t, _)| t))
    }
}
