//! The legal run every invariant comes back to: a master's ordinary sequence (setup,
//! initialize, then per step set inputs, get outputs, do step) with deterministic inputs,
//! recorded as the bit patterns of every Real output. Two runs agree only if every bit does.
use crate::ffi::*;
use crate::instance::{Fmu, Instance};
use crate::package::Lander;
use model_description::{Causality, VariableKind};

/// Communication step of the legal runs, s.
pub const STEP_S: f64 = 0.01;

/// Inputs of the legal run at time `t_s`, in the order of [`input_names`].
///
/// LanderPlant: a hovering thrust with a slow throttle ripple and small torques.
/// LanderGnc: a slowly varying, bounded navigation state (periodic, so valid for any run
/// length): a gently rocking, drifting lander whose mass breathes by a few percent.
/// LanderNav: the same state, as the true one it corrupts.
pub fn inputs_at(lander: Lander, t_s: f64) -> Vec<f64> {
    match lander {
        Lander::Plant => vec![
            1300.0 + 50.0 * (0.3 * t_s).sin(),
            5.0 * (0.5 * t_s).sin(),
            -3.0 * (0.2 * t_s).cos(),
            2.0,
        ],
        Lander::Gnc | Lander::Nav => {
            let axis: [f64; 3] = [0.3, 0.9, 0.3];
            let norm = axis.iter().map(|a| a * a).sum::<f64>().sqrt();
            let axis = axis.map(|a| a / norm);
            let angle_rad = 0.2 * (0.07 * t_s).sin();
            let rate_radps = 0.2 * 0.07 * (0.07 * t_s).cos();
            let (s, c) = (0.5 * angle_rad).sin_cos();
            vec![
                10.0 * (0.01 * t_s).sin(),
                500.0 + 300.0 * (0.003 * t_s).cos(),
                10.0 * (0.013 * t_s).cos(),
                0.1 * (0.01 * t_s).cos(),
                -0.9 * (0.003 * t_s).sin(),
                -0.13 * (0.013 * t_s).sin(),
                c,
                axis[0] * s,
                axis[1] * s,
                axis[2] * s,
                axis[0] * rate_radps,
                axis[1] * rate_radps,
                axis[2] * rate_radps,
                800.0 + 50.0 * (0.001 * t_s).sin(),
            ]
        }
    }
}

/// The contract names of the inputs `inputs_at` feeds (docs/interface.md).
pub fn input_names(lander: Lander) -> Vec<String> {
    let indexed = |base: &'static str, n: usize| (1..=n).map(move |k| format!("{base}[{k}]"));
    // LanderNav reads the plant's signals under the GNC's names with `_true` appended.
    let truth = |base: &'static str, n: usize| (1..=n).map(move |k| format!("{base}_true[{k}]"));
    match lander {
        Lander::Plant => std::iter::once("thrust_cmd".to_string())
            .chain(indexed("torque_cmd_body", 3))
            .collect(),
        Lander::Gnc => indexed("r_nue", 3)
            .chain(indexed("v_nue", 3))
            .chain(indexed("q_body_to_nue", 4))
            .chain(indexed("omega_body", 3))
            .chain(std::iter::once("mass".to_string()))
            .collect(),
        Lander::Nav => truth("r_nue", 3)
            .chain(truth("v_nue", 3))
            .chain(truth("q_body_to_nue", 4))
            .chain(truth("omega_body", 3))
            .chain(std::iter::once("mass_true".to_string()))
            .collect(),
    }
}

/// LanderNav's parameters with every kind of error on in every group (noise, bias, random
/// walk, quantisation, latency), seeded by `seed`; (name, value), Integers given as whole
/// numbers. Small errors, as a real navigation filter's would be.
pub fn nav_errors_on(seed: u32) -> Vec<(String, f64)> {
    let mut p: Vec<(String, f64)> = vec![("seed".into(), f64::from(seed))];
    p.push(("max_latency_steps".into(), 4.0));
    // Per group: bias per axis, noise sigma, random walk (per sqrt(s)), quantum, latency.
    let groups: [(&str, [f64; 3], [f64; 4]); 5] = [
        ("r_nue", [0.5, -1.0, 0.25], [0.3, 0.02, 0.01, 2.0]),
        ("v_nue", [0.01, 0.02, -0.01], [0.05, 0.002, 0.001, 1.0]),
        ("attitude", [1e-3, -2e-3, 5e-4], [5e-4, 1e-4, 0.0, 1.0]),
        ("omega_body", [1e-4, 0.0, -1e-4], [2e-4, 1e-5, 1e-5, 0.0]),
        ("mass", [2.0, 0.0, 0.0], [0.5, 0.01, 0.1, 4.0]),
    ];
    for (g, bias, [sigma, walk, quantum, latency]) in groups {
        p.push((format!("{g}_noise_sigma"), sigma));
        p.push((format!("{g}_random_walk"), walk));
        if g == "mass" {
            p.push(("mass_bias".into(), bias[0]));
        } else {
            for (k, b) in bias.iter().enumerate() {
                p.push((format!("{g}_bias[{}]", k + 1), *b));
            }
        }
        // A rounded quaternion would no longer be a rotation: the attitude has no quantum.
        if g != "attitude" {
            p.push((format!("{g}_quantum"), quantum));
        }
        p.push((format!("{g}_latency"), latency));
    }
    p
}

/// Value references of the legal run's inputs and of every Real output.
#[derive(Debug, Clone)]
pub struct Wiring {
    pub inputs: Vec<u32>,
    pub outputs: Vec<u32>,
}

impl Wiring {
    pub fn of(fmu: &Fmu) -> Wiring {
        Wiring {
            inputs: input_names(fmu.lander())
                .iter()
                .map(|n| fmu.vr(n))
                .collect(),
            outputs: fmu
                .package
                .variables
                .iter()
                .filter(|v| v.kind == VariableKind::Real && v.causality == Causality::Output)
                .map(|v| v.value_reference)
                .collect(),
        }
    }
}

/// `steps` steps of the legal run from t = 0 on an instance in state Instantiated; the bit
/// patterns of all Real outputs read before each step and after the last. `Err` names the
/// first call that did not return fmi2OK.
pub fn legal_run(inst: &Instance, steps: usize) -> Result<Vec<u64>, String> {
    legal_run_with(inst, steps, &[])
}

/// [`legal_run`] with `parameters` (name, value) set in initialization mode.
pub fn legal_run_with(
    inst: &Instance,
    steps: usize,
    parameters: &[(&str, f64)],
) -> Result<Vec<u64>, String> {
    let wiring = Wiring::of(inst.fmu);
    let lander = inst.fmu.lander();
    let fail = |what: &str, status: fmi2Status| {
        Err(format!(
            "{what} returned {}: {:?}",
            status.label(),
            inst.sink.all()
        ))
    };
    for (what, status) in [
        ("fmi2SetupExperiment", inst.setup(0.0, None)),
        ("fmi2EnterInitializationMode", inst.enter_init()),
    ] {
        if status != fmi2OK {
            return fail(what, status);
        }
    }
    for (name, value) in parameters {
        let status = inst.set_parameter(name, *value);
        if status != fmi2OK {
            return fail(&format!("setting {name}"), status);
        }
    }
    let status = inst.exit_init();
    if status != fmi2OK {
        return fail("fmi2ExitInitializationMode", status);
    }
    let mut bits = Vec::with_capacity((steps + 1) * wiring.outputs.len());
    for k in 0..=steps {
        // An integer step counter: the communication points are exactly k h.
        let t = k as f64 * STEP_S;
        let status = inst.set_reals(&wiring.inputs, &inputs_at(lander, t));
        if status != fmi2OK {
            return fail(&format!("fmi2SetReal at t = {t}"), status);
        }
        let (status, outputs) = inst.get_reals(&wiring.outputs);
        if status != fmi2OK {
            return fail(&format!("fmi2GetReal at t = {t}"), status);
        }
        bits.extend(outputs.iter().map(|v| v.to_bits()));
        if k < steps {
            let status = inst.step(t, STEP_S);
            if status != fmi2OK {
                return fail(&format!("fmi2DoStep at t = {t}"), status);
            }
        }
    }
    Ok(bits)
}
