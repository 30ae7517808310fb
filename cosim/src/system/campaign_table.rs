//! The `[campaign]` table a TOML scenario may carry: runs, seed, sampling, its
//! `[[campaign.sweep]]`, `[[campaign.dispersion]]` and `[[campaign.correlation]]` entries, as
//! written. The system reader accepts it (a misspelt key is refused with the scenario); the
//! `campaign` crate checks and runs it (`harness campaign`).
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Declaration {
    /// Draws per sweep point.
    #[serde(default = "default_runs")]
    pub runs: u64,
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// "random" (default) or "latin-hypercube".
    #[serde(default = "default_sampling")]
    pub sampling: String,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sweep: Vec<Sweep>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub dispersion: Vec<Dispersion>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub correlation: Vec<Correlation>,
}

fn default_runs() -> u64 {
    10
}

fn default_seed() -> u64 {
    1
}

fn default_sampling() -> String {
    "random".into()
}

/// A parameter set to each of its values in turn: a list, or a grid of evenly spaced
/// values.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Sweep {
    pub parameter: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub values: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<Grid>,
}

/// `count` values from `from` to `to`, both included.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Grid {
    pub from: f64,
    pub to: f64,
    pub count: u64,
}

/// A parameter drawn per run from a distribution.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Dispersion {
    pub parameter: String,
    pub distribution: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sd: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub median: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma: Option<f64>,
}

/// The rank-free (Gaussian copula) correlation of two dispersed parameters.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Correlation {
    pub between: Vec<String>,
    pub rho: f64,
}

/// The keys each table accepts, by table (`campaign.sweep.grid` the inline `grid`).
pub fn keys() -> Vec<(&'static str, &'static [&'static str])> {
    use super::fields::of;
    vec![
        ("campaign", of::<Declaration>()),
        ("campaign.sweep", of::<Sweep>()),
        ("campaign.sweep.grid", of::<Grid>()),
        ("campaign.dispersion", of::<Dispersion>()),
        ("campaign.correlation", of::<Correlation>()),
    ]
}

/// The `[campaign]` table of a scenario's TOML text; `None` without one.
pub fn from_toml(text: &str) -> Result<Option<Declaration>, String> {
    let mut table: toml::Table = toml::from_str(text).map_err(|e| e.to_string())?;
    let Some(campaign) = table.remove("campaign") else {
        return Ok(None);
    };
    campaign
        .try_into()
        .map(Some)
        .map_err(|e: toml::de::Error| format!("[campaign]: {}", e.message()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_reads_with_its_defaults_and_refuses_unknown_keys() {
        let d = from_toml(
            "name = 'x'\n[campaign]\nruns = 4\n[[campaign.sweep]]\nparameter = 'a.b'\n\
             grid = { from = 1.0, to = 2.0, count = 3 }\n[[campaign.dispersion]]\n\
             parameter = 'a.c'\ndistribution = 'normal'\nmean = 1.0\nsd = 0.5\n",
        )
        .unwrap()
        .unwrap();
        assert_eq!((d.runs, d.seed, d.sampling.as_str()), (4, 1, "random"));
        assert_eq!(d.sweep[0].grid.unwrap().count, 3);
        assert_eq!(d.dispersion[0].sd, Some(0.5));
        assert_eq!(from_toml("name = 'x'").unwrap(), None);
        let e = from_toml("[campaign]\nrunz = 3\n").unwrap_err();
        assert!(e.contains("[campaign]") && e.contains("runz"), "{e}");
    }
}
