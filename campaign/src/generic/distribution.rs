//! The distributions a `[[campaign.dispersion]]` draws from, each as its quantile function
//! (inverse CDF) of a uniform number in (0, 1): one transform serves random sampling, Latin
//! hypercube strata and the Gaussian copula of correlated inputs alike.

/// One input's distribution, its parameters checked by [`Distribution::new`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Distribution {
    /// Uniform on [min, max].
    Uniform { min: f64, max: f64 },
    /// Normal with mean and standard deviation sd.
    Normal { mean: f64, sd: f64 },
    /// The normal (mean, sd) conditioned on [min, max].
    TruncatedNormal {
        mean: f64,
        sd: f64,
        min: f64,
        max: f64,
    },
    /// exp of a normal: median exp(mu), sigma the standard deviation of its logarithm.
    LogNormal { median: f64, sigma: f64 },
}

/// The distribution names a scenario writes, with the parameters each takes.
pub const NAMES: [(&str, &[&str]); 4] = [
    ("uniform", &["min", "max"]),
    ("normal", &["mean", "sd"]),
    ("truncated-normal", &["mean", "sd", "min", "max"]),
    ("log-normal", &["median", "sigma"]),
];

/// The parameters as written (`None`: not given).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Parameters {
    pub min: Option<f64>,
    pub max: Option<f64>,
    pub mean: Option<f64>,
    pub sd: Option<f64>,
    pub median: Option<f64>,
    pub sigma: Option<f64>,
}

impl Parameters {
    /// The parameters of a `[[campaign.dispersion]]` entry.
    pub fn of(entry: &cosim::system::campaign_table::Dispersion) -> Self {
        Self {
            min: entry.min,
            max: entry.max,
            mean: entry.mean,
            sd: entry.sd,
            median: entry.median,
            sigma: entry.sigma,
        }
    }

    fn given(&self) -> [(&'static str, Option<f64>); 6] {
        [
            ("min", self.min),
            ("max", self.max),
            ("mean", self.mean),
            ("sd", self.sd),
            ("median", self.median),
            ("sigma", self.sigma),
        ]
    }
}

impl Distribution {
    /// The distribution `name` with `parameters`; every problem listed (which parameter is
    /// missing, foreign, not a number or out of its range, with its value).
    pub fn new(name: &str, parameters: &Parameters) -> Result<Self, Vec<String>> {
        let Some((_, wanted)) = NAMES.iter().find(|(n, _)| *n == name) else {
            let known: Vec<String> = NAMES.iter().map(|(n, _)| format!("\"{n}\"")).collect();
            return Err(vec![format!(
                "distribution = \"{name}\" is none of {}",
                known.join(", ")
            )]);
        };
        let mut problems = Vec::new();
        for (key, value) in parameters.given() {
            match (wanted.contains(&key), value) {
                (true, None) => problems.push(format!("\"{name}\" needs {key}")),
                (false, Some(v)) => problems.push(format!(
                    "{key} = {v} is not a parameter of \"{name}\" (it takes {})",
                    wanted.join(", ")
                )),
                (true, Some(v)) if !v.is_finite() => {
                    problems.push(format!("{key} = {v} is not a finite number"))
                }
                _ => {}
            }
        }
        if !problems.is_empty() {
            return Err(problems);
        }
        let p = |v: Option<f64>| v.unwrap_or_default();
        let positive = |problems: &mut Vec<String>, key: &str, v: f64| {
            if v <= 0.0 {
                problems.push(format!("{key} = {v} must be greater than 0"));
            }
        };
        let ordered = |problems: &mut Vec<String>, min: f64, max: f64| {
            if min >= max {
                problems.push(format!("min = {min} must be less than max = {max}"));
            }
        };
        let distribution = match name {
            "uniform" => {
                let (min, max) = (p(parameters.min), p(parameters.max));
                ordered(&mut problems, min, max);
                Distribution::Uniform { min, max }
            }
            "normal" => {
                let (mean, sd) = (p(parameters.mean), p(parameters.sd));
                positive(&mut problems, "sd", sd);
                Distribution::Normal { mean, sd }
            }
            "truncated-normal" => {
                let (mean, sd) = (p(parameters.mean), p(parameters.sd));
                let (min, max) = (p(parameters.min), p(parameters.max));
                positive(&mut problems, "sd", sd);
                ordered(&mut problems, min, max);
                let d = Distribution::TruncatedNormal { mean, sd, min, max };
                if problems.is_empty() && (d.mass().is_nan() || d.mass() <= 0.0) {
                    problems.push(format!(
                        "[{min}, {max}] holds no probability of the normal (mean {mean}, sd \
                         {sd}) it truncates"
                    ));
                }
                d
            }
            _ => {
                let (median, sigma) = (p(parameters.median), p(parameters.sigma));
                positive(&mut problems, "median", median);
                positive(&mut problems, "sigma", sigma);
                Distribution::LogNormal { median, sigma }
            }
        };
        if problems.is_empty() {
            Ok(distribution)
        } else {
            Err(problems)
        }
    }

    /// The truncated normal's probability inside [min, max] (1 for the others).
    fn mass(&self) -> f64 {
        match *self {
            Distribution::TruncatedNormal { mean, sd, min, max } => {
                normal_cdf((max - mean) / sd) - normal_cdf((min - mean) / sd)
            }
            _ => 1.0,
        }
    }

    /// The value whose CDF is `u` (in (0, 1)).
    pub fn quantile(&self, u: f64) -> f64 {
        match *self {
            Distribution::Uniform { min, max } => min + u * (max - min),
            Distribution::Normal { mean, sd } => mean + sd * normal_quantile(u),
            Distribution::TruncatedNormal { mean, sd, min, max } => {
                let low = normal_cdf((min - mean) / sd);
                let high = normal_cdf((max - mean) / sd);
                let z = normal_quantile(low + u * (high - low));
                (mean + sd * z).clamp(min, max)
            }
            Distribution::LogNormal { median, sigma } => {
                median * (sigma * normal_quantile(u)).exp()
            }
        }
    }
}

/// The standard normal CDF, Phi(z) = erfc(-z / sqrt 2) / 2 (libm's erfc: accurate in both
/// tails).
pub fn normal_cdf(z: f64) -> f64 {
    0.5 * libm::erfc(-z / std::f64::consts::SQRT_2)
}

/// The standard normal quantile: Acklam's rational approximation (relative error 1.15e-9),
/// refined by one Halley step on [`normal_cdf`] to near double precision.
pub fn normal_quantile(p: f64) -> f64 {
    if p <= 0.0 {
        return f64::NEG_INFINITY;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let x = if p < 0.02425 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.02425 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    };
    let e = normal_cdf(x) - p;
    let u = e * (2.0 * std::f64::consts::PI).sqrt() * (x * x / 2.0).exp();
    x - u / (1.0 + x * u / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(pairs: &[(&str, f64)]) -> Parameters {
        let mut p = Parameters::default();
        for &(k, v) in pairs {
            let slot = match k {
                "min" => &mut p.min,
                "max" => &mut p.max,
                "mean" => &mut p.mean,
                "sd" => &mut p.sd,
                "median" => &mut p.median,
                _ => &mut p.sigma,
            };
            *slot = Some(v);
        }
        p
    }

    #[test]
    fn the_normal_quantile_inverts_the_cdf_and_knows_its_table_values() {
        // Tabulated: Phi^-1(0.975) = 1.959963984540054, Phi^-1(0.99865) = 3.0000 (3 sigma).
        assert!((normal_quantile(0.975) - 1.959_963_984_540_054).abs() < 1e-13);
        assert!((normal_quantile(0.5)).abs() < 1e-15);
        assert!((normal_cdf(3.0) - 0.998_650_101_968_369_9).abs() < 1e-15);
        for k in 1..1000 {
            let p = k as f64 / 1000.0;
            assert!((normal_cdf(normal_quantile(p)) - p).abs() < 1e-14, "{p}");
        }
        assert!((normal_cdf(normal_quantile(1e-12)) / 1e-12 - 1.0).abs() < 1e-9);
    }

    #[test]
    fn bad_parameters_are_each_named_with_their_value() {
        let e = Distribution::new("normal", &params(&[("mean", 1.0), ("sd", 0.0)])).unwrap_err();
        assert_eq!(e, ["sd = 0 must be greater than 0"]);
        let e = Distribution::new(
            "uniform",
            &params(&[("min", 2.0), ("max", 1.0), ("sd", 3.0)]),
        )
        .unwrap_err();
        assert!(
            e[0].contains("sd = 3 is not a parameter of \"uniform\""),
            "{e:?}"
        );
        let e = Distribution::new("truncated-normal", &params(&[("mean", 0.0), ("sd", 1.0)]))
            .unwrap_err();
        assert_eq!(
            e,
            [
                "\"truncated-normal\" needs min",
                "\"truncated-normal\" needs max"
            ]
        );
        let e = Distribution::new("cauchy", &Parameters::default()).unwrap_err();
        assert!(e[0].contains("\"cauchy\" is none of"), "{e:?}");
        let e = Distribution::new("log-normal", &params(&[("median", -1.0), ("sigma", -2.0)]))
            .unwrap_err();
        assert_eq!(e.len(), 2);
        let e = Distribution::new(
            "truncated-normal",
            &params(&[("mean", 0.0), ("sd", 1.0), ("min", 50.0), ("max", 60.0)]),
        )
        .unwrap_err();
        assert!(e[0].contains("holds no probability"), "{e:?}");
    }
}
