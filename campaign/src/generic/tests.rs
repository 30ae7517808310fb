//! Draws against their analytic moments and bounds at a fixed seed, Latin hypercube strata,
//! copula correlation, and the checks of a `[campaign]` table.
use super::distribution::normal_cdf;
use super::plan::Plan;
use cosim::system::campaign_table::from_toml;

fn plan(body: &str) -> Result<Plan, Vec<String>> {
    Plan::new(&from_toml(&format!("[campaign]\n{body}")).unwrap().unwrap())
}

fn column(plan: &Plan, dim: usize) -> Vec<f64> {
    (0..plan.runs).map(|j| plan.draw(j)[dim]).collect()
}

fn mean_sd(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, var.sqrt())
}

const DISPERSIONS: &str = "seed = 11\nruns = 20000\n\
    [[campaign.dispersion]]\nparameter = 'a.u'\ndistribution = 'uniform'\nmin = 2.0\nmax = 5.0\n\
    [[campaign.dispersion]]\nparameter = 'a.n'\ndistribution = 'normal'\nmean = 10.0\nsd = 2.0\n\
    [[campaign.dispersion]]\nparameter = 'a.t'\ndistribution = 'truncated-normal'\n\
    mean = 0.0\nsd = 1.0\nmin = -1.0\nmax = 2.0\n\
    [[campaign.dispersion]]\nparameter = 'a.l'\ndistribution = 'log-normal'\n\
    median = 3.0\nsigma = 0.25\n";

/// The sample mean and sd of each distribution within 4 standard errors of the analytic
/// values, and every draw inside its support.
fn check_moments(sampling: &str) {
    let plan = plan(&format!("sampling = '{sampling}'\n{DISPERSIONS}")).unwrap();
    let n = plan.runs as f64;
    // Truncated standard normal on [a, b]: mean (phi(a) - phi(b)) / Z, variance
    // 1 + (a phi(a) - b phi(b)) / Z - mean^2.
    let phi = |x: f64| (-x * x / 2.0).exp() / (2.0 * std::f64::consts::PI).sqrt();
    let (a, b) = (-1.0_f64, 2.0_f64);
    let z = normal_cdf(b) - normal_cdf(a);
    let t_mean = (phi(a) - phi(b)) / z;
    let t_sd = (1.0 + (a * phi(a) - b * phi(b)) / z - t_mean * t_mean).sqrt();
    let (s2, m) = (0.25_f64 * 0.25, 3.0_f64);
    let l_mean = m * (s2 / 2.0).exp();
    let l_sd = l_mean * (s2.exp() - 1.0).sqrt();
    let expected = [
        (3.5, 3.0 / 12f64.sqrt(), 2.0, 5.0),
        (10.0, 2.0, f64::NEG_INFINITY, f64::INFINITY),
        (t_mean, t_sd, a, b),
        (l_mean, l_sd, 0.0, f64::INFINITY),
    ];
    for (dim, (mean, sd, low, high)) in expected.into_iter().enumerate() {
        let x = column(&plan, dim);
        let (m, s) = mean_sd(&x);
        assert!(
            (m - mean).abs() < 4.0 * sd / n.sqrt(),
            "{sampling} dim {dim}: mean {m} vs {mean}"
        );
        // The sd's standard error is about sd / sqrt(2n) (normal kurtosis; a margin for others).
        assert!(
            (s - sd).abs() < 6.0 * sd / (2.0 * n).sqrt(),
            "{sampling} dim {dim}: sd {s} vs {sd}"
        );
        assert!(
            x.iter().all(|v| *v >= low && *v <= high),
            "{sampling} dim {dim} out of bounds"
        );
    }
}

#[test]
fn random_draws_have_their_distributions_moments_and_bounds() {
    check_moments("random");
}

#[test]
fn latin_hypercube_draws_have_their_distributions_moments_and_bounds() {
    check_moments("latin-hypercube");
}

#[test]
fn latin_hypercube_puts_one_run_in_each_stratum_of_each_input() {
    let plan = plan(&format!(
        "sampling = 'latin-hypercube'\n{}",
        DISPERSIONS.replace("20000", "37")
    ))
    .unwrap();
    let cdfs: [&dyn Fn(f64) -> f64; 2] = [&|x| (x - 2.0) / 3.0, &|x| normal_cdf((x - 10.0) / 2.0)];
    for (dim, cdf) in cdfs.iter().enumerate() {
        let mut strata: Vec<u64> = column(&plan, dim)
            .iter()
            .map(|&x| (cdf(x) * 37.0).floor() as u64)
            .collect();
        strata.sort_unstable();
        assert_eq!(strata, (0..37).collect::<Vec<_>>(), "dim {dim}");
    }
    // Random sampling does not stratify: some stratum gets two runs.
    let random = plan_random_37();
    let mut strata: Vec<u64> = column(&random, 0)
        .iter()
        .map(|&x| ((x - 2.0) / 3.0 * 37.0) as u64)
        .collect();
    strata.sort_unstable();
    strata.dedup();
    assert!(strata.len() < 37);
}

fn plan_random_37() -> Plan {
    plan(&DISPERSIONS.replace("20000", "37")).unwrap()
}

#[test]
fn a_run_is_a_function_of_the_seed_and_its_index_alone() {
    let a = plan(DISPERSIONS).unwrap();
    let b = plan(&DISPERSIONS.replace("runs = 20000", "runs = 5")).unwrap();
    for j in 0..5 {
        assert_eq!(a.draw(j), b.draw(j));
    }
    let c = plan(&DISPERSIONS.replace("seed = 11", "seed = 12")).unwrap();
    assert_ne!(a.draw(0), c.draw(0));
}

fn pearson(x: &[f64], y: &[f64]) -> f64 {
    crate::analysis::pearson(x, y)
}

#[test]
fn correlated_normals_have_the_declared_correlation() {
    for (rho, sampling) in [(0.6, "random"), (-0.8, "latin-hypercube")] {
        let plan = plan(&format!(
            "sampling = '{sampling}'\n{DISPERSIONS}[[campaign.correlation]]\n\
             between = ['a.n', 'a.l']\nrho = {rho}\n"
        ))
        .unwrap();
        let n = column(&plan, 1);
        // The copula's correlation is that of the normals: log of the log-normal is normal.
        let l: Vec<f64> = column(&plan, 3).iter().map(|v| v.ln()).collect();
        let r = pearson(&n, &l);
        // Standard error of r: (1 - rho^2) / sqrt(n) = 0.0045 at rho 0.6.
        assert!((r - rho).abs() < 0.02, "{sampling}: r = {r}, rho = {rho}");
        // The other inputs stay independent, and the marginals keep their moments.
        assert!(pearson(&column(&plan, 0), &n).abs() < 0.03);
        let (m, s) = mean_sd(&n);
        assert!((m - 10.0).abs() < 0.06 && (s - 2.0).abs() < 0.06, "{m} {s}");
    }
}

#[test]
fn a_correlation_matrix_that_is_not_positive_definite_is_refused_naming_its_pairs() {
    let e = plan(&format!(
        "{DISPERSIONS}[[campaign.correlation]]\nbetween = ['a.u', 'a.n']\nrho = 0.9\n\
         [[campaign.correlation]]\nbetween = ['a.n', 'a.t']\nrho = 0.9\n\
         [[campaign.correlation]]\nbetween = ['a.u', 'a.t']\nrho = -0.9\n"
    ))
    .unwrap_err();
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(
        e[0].contains("not positive definite") && e[0].contains("\"a.u\" and \"a.t\" (rho = -0.9)"),
        "{e:?}"
    );
}

#[test]
fn every_problem_of_a_campaign_table_is_listed_at_once() {
    let e = plan(
        "runs = 0\nsampling = 'sobol'\n\
         [[campaign.sweep]]\nparameter = 'nodot'\nvalues = [1.0]\n\
         [[campaign.sweep]]\nparameter = 'a.b'\nvalues = [1.0]\ngrid = { from = 0.0, to = 1.0, count = 2 }\n\
         [[campaign.dispersion]]\nparameter = 'a.b'\ndistribution = 'normal'\nmean = 1.0\nsd = -2.0\n\
         [[campaign.dispersion]]\nparameter = 'a.c'\ndistribution = 'uniform'\nmin = 3.0\nmax = 3.0\n\
         [[campaign.correlation]]\nbetween = ['a.c', 'z.z']\nrho = 1.5\n",
    )
    .unwrap_err();
    let expected = [
        "runs = 0",
        "sampling = \"sobol\"",
        "parameter = \"nodot\" is not of the form",
        "a.b: give either values",
        "parameter = \"a.b\" is swept or dispersed twice",
        "a.b: sd = -2 must be greater than 0",
        "a.c: min = 3 must be less than max = 3",
        "rho = 1.5 is not inside (-1, 1)",
        "\"z.z\" is not a [[campaign.dispersion]] parameter",
    ];
    for text in expected {
        assert!(
            e.iter().any(|p| p.contains(text)),
            "missing '{text}' in {e:#?}"
        );
    }
    assert_eq!(e.len(), expected.len(), "{e:#?}");
    let e = plan("runs = 10000001\nsampling = 'latin-hypercube'\n").unwrap_err();
    assert!(e[0].contains("at most 10000000"), "{e:?}");
}

#[test]
fn sweeps_make_points_and_every_run_meets_every_point() {
    let plan = plan(
        "runs = 3\n[[campaign.sweep]]\nparameter = 'a.x'\nvalues = [1.0, 2.0]\n\
         [[campaign.sweep]]\nparameter = 'a.y'\ngrid = { from = 0.0, to = 1.0, count = 3 }\n\
         [[campaign.dispersion]]\nparameter = 'a.z'\ndistribution = 'normal'\nmean = 0.0\nsd = 1.0\n",
    )
    .unwrap();
    assert_eq!((plan.points(), plan.total()), (6, 18));
    assert_eq!(plan.point_values(0), [1.0, 0.0]);
    assert_eq!(plan.point_values(4), [2.0, 0.5]);
    assert_eq!(plan.point_values(5), [2.0, 1.0]);
    let id = plan.run_id(13);
    assert_eq!((id.run, id.point), (2, 1));
    let inputs = plan.inputs(&id);
    assert_eq!(inputs[2].1, plan.draw(2)[0]);
    assert_eq!(plan.inputs(&plan.run_id(12))[2].1, inputs[2].1);
}
