//! Instances of every FMU stepped on many threads at once give bit-identical results to the
//! same runs done one after another: no global state, no shared scratch memory.
use robustness_tests::instance::Fmu;
use robustness_tests::package::Lander;
use robustness_tests::reference::legal_run_with;

const STEPS: usize = 1500;
const PER_FMU: usize = 4;

/// A different parameter set per run, so that a run reading another's data would show.
fn parameters(lander: Lander, k: usize) -> Vec<(&'static str, f64)> {
    let k = k as f64;
    match lander {
        Lander::Gnc => vec![
            ("phi_cmd", 0.3 * k - 0.5),
            ("control_bandwidth", 0.4 + 0.05 * k),
        ],
        Lander::Plant => vec![("m0", 850.0 + 10.0 * k), ("omega0_body[1]", 0.01 * k)],
        // The errors are drawn per instance from its own seed: another's seed would show.
        Lander::Nav => vec![
            ("seed", 11.0 + k),
            ("r_nue_noise_sigma", 0.5),
            ("attitude_random_walk", 1e-3),
        ],
        // The same: each instance draws its noise from its own seed.
        Lander::Sensors => vec![("seed", 21.0 + k), ("altimeter_noise_sigma", 0.1 + 0.1 * k)],
        // Deterministic: a different initial uncertainty per run.
        Lander::Filter => vec![("r0_sigma", 10.0 + k), ("gravity", 1.62 + 0.001 * k)],
        // Another FMU runs at its defaults: a mix-up between its runs cannot show, one with
        // another FMU's can.
        _ => Vec::new(),
    }
}

fn run(fmu: &Fmu, k: usize) -> Vec<u64> {
    let inst = fmu.instantiate(&format!("run{k}"), false);
    legal_run_with(&inst, STEPS, &parameters(fmu.lander(), k)).expect("legal run")
}

#[test]
fn concurrent_instances_give_the_serial_results_bit_for_bit() {
    let fmus: Vec<Fmu> = Lander::all()
        .into_iter()
        .map(|l| Fmu::load(l).expect("packaged FMU"))
        .collect();
    let jobs: Vec<(&Fmu, usize)> = fmus
        .iter()
        .flat_map(|f| (0..PER_FMU).map(move |k| (f, k)))
        .collect();
    let serial: Vec<Vec<u64>> = jobs.iter().map(|(f, k)| run(f, *k)).collect();
    // The runs differ from each other, so a mix-up could not go unnoticed.
    for (i, a) in serial.iter().enumerate() {
        for (j, b) in serial.iter().enumerate().skip(i + 1) {
            let same_defaults = jobs[i].0.lander() == jobs[j].0.lander()
                && parameters(jobs[i].0.lander(), 0).is_empty();
            if !same_defaults {
                assert_ne!(a, b);
            }
        }
    }
    let concurrent: Vec<Vec<u64>> = std::thread::scope(|scope| {
        let handles: Vec<_> = jobs
            .iter()
            .map(|(f, k)| scope.spawn(move || run(f, *k)))
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("no panic"))
            .collect()
    });
    for (((f, k), s), c) in jobs.iter().zip(&serial).zip(&concurrent) {
        assert!(
            s == c,
            "{} run {k} differs on a thread",
            f.lander().model_identifier()
        );
    }
}
