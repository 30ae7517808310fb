//! The long run: millions of communication steps of one FMU, checking after every
//! step that the outputs are finite and the attitude quaternion is a unit quaternion, and for
//! the plant (tumbling torque-free, engines off) that the angular momentum is conserved; the
//! FMU state is saved, serialized, restored and re-run bit-identically at checkpoints along
//! the way; resident memory is sampled at each checkpoint. LanderNav runs with every error on
//! (its estimate must stay finite and a unit quaternion, and differ from the truth), or with
//! every error off (its estimate must be the truth bit for bit).
use crate::ffi::*;
use crate::instance::{Fmu, Instance};
use crate::package::Lander;
use crate::reference::{input_names, inputs_at, nav_errors_on, Wiring, STEP_S};
use crate::rss::vm_rss_kib;

/// Steps re-run after each restore.
const REPLAY_STEPS: usize = 100;

/// The plant's tumble: principal moments (kg m^2; x is the intermediate axis, the unstable
/// one) and the initial body rate (rad/s).
pub const INERTIA_BODY_KGM2: [f64; 3] = [400.0, 300.0, 450.0];
pub const OMEGA0_BODY_RADPS: [f64; 3] = [0.2, 0.6, -0.3];

#[derive(Debug, Clone, Default)]
pub struct Report {
    pub steps: usize,
    /// max over all steps of | |q| - 1 | of the attitude (plant, LanderNav) or reference (GNC)
    /// quaternion.
    pub max_quaternion_norm_error: f64,
    /// LanderNav only: steps whose 14 outputs equal their inputs bit for bit.
    pub identity_steps: usize,
    /// Steps whose outputs went through the checks above (the others are replays).
    pub probed_steps: usize,
    /// Plant only: max over all steps of |H_nue(t) - H_nue(0)| / |H_nue(0)|.
    pub max_angular_momentum_drift: f64,
    pub restores: usize,
    /// VmRSS at each checkpoint, KiB.
    pub rss_kib: Vec<u64>,
}

/// `v` rotated by the scalar-first unit quaternion `q`: v + 2 w (u x v) + 2 u x (u x v).
fn rotate(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let [w, x, y, z] = q;
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let u = [x, y, z];
    let t = cross(u, v).map(|c| 2.0 * c);
    let ut = cross(u, t);
    [0, 1, 2].map(|i| v[i] + w * t[i] + ut[i])
}

struct Probe {
    inputs: Vec<u32>,
    outputs: Vec<u32>,
    /// Positions in `outputs` of the quaternion and (plant) of omega_body.
    quaternion: [usize; 4],
    omega: Option<[usize; 3]>,
    /// LanderNav: for each input (in `inputs` order), the position in `outputs` of its
    /// estimate (the input's name without `_true`).
    estimates: Option<Vec<usize>>,
}

impl Probe {
    fn new(fmu: &Fmu) -> Probe {
        let wiring = Wiring::of(fmu);
        let at = |name: &str| {
            let vr = fmu.vr(name);
            wiring
                .outputs
                .iter()
                .position(|&o| o == vr)
                .expect("an output")
        };
        let (q, omega) = match fmu.lander() {
            Lander::Plant => (
                "q_body_to_nue",
                Some([1, 2, 3].map(|k| at(&format!("omega_body[{k}]")))),
            ),
            Lander::Gnc => ("q_ref", None),
            Lander::Nav => ("q_body_to_nue", None),
        };
        let estimates = (fmu.lander() == Lander::Nav).then(|| {
            input_names(Lander::Nav)
                .iter()
                .map(|n| at(&n.replace("_true", "")))
                .collect()
        });
        Probe {
            estimates,
            quaternion: [1, 2, 3, 4].map(|k| at(&format!("{q}[{k}]"))),
            omega,
            inputs: wiring.inputs,
            outputs: wiring.outputs,
        }
    }

    fn inputs(&self, lander: Lander, t: f64) -> Vec<f64> {
        match lander {
            // Engines off, no torque: a free tumble.
            Lander::Plant => vec![0.0; self.inputs.len()],
            Lander::Gnc | Lander::Nav => inputs_at(lander, t),
        }
    }

    /// LanderNav: whether the outputs `y` read at step `k` are its inputs bit for bit.
    fn is_identity(&self, lander: Lander, k: usize, y: &[f64]) -> bool {
        let Some(estimates) = &self.estimates else {
            return false;
        };
        let u = self.inputs(lander, k as f64 * STEP_S);
        estimates
            .iter()
            .zip(&u)
            .all(|(&i, x)| y[i].to_bits() == x.to_bits())
    }

    /// One step: set inputs, read outputs, step; the outputs read.
    fn step(&self, inst: &Instance, k: usize) -> Result<Vec<f64>, String> {
        let t = k as f64 * STEP_S;
        let lander = inst.fmu.lander();
        let status = inst.set_reals(&self.inputs, &self.inputs(lander, t));
        let (get, outputs) = inst.get_reals(&self.outputs);
        let step = inst.step(t, STEP_S);
        if status != fmi2OK || get != fmi2OK || step != fmi2OK {
            return Err(format!(
                "step {k}: set {status}, get {get}, step {step}: {:?}",
                inst.take_log()
            ));
        }
        if let Some(v) = outputs.iter().find(|v| !v.is_finite()) {
            return Err(format!("step {k}: output {v}"));
        }
        Ok(outputs)
    }

    fn quaternion(&self, y: &[f64]) -> [f64; 4] {
        self.quaternion.map(|i| y[i])
    }

    fn angular_momentum_nue(&self, y: &[f64]) -> Option<[f64; 3]> {
        let omega = self.omega?.map(|i| y[i]);
        let h_body = [0, 1, 2].map(|i| INERTIA_BODY_KGM2[i] * omega[i]);
        Some(rotate(self.quaternion(y), h_body))
    }
}

/// The plant's parameters for the tumble: drifting far above a Moon of negligible gravity
/// (which must be > 0), so that it never lands.
pub fn plant_parameters() -> Vec<(String, f64)> {
    let mut p = vec![("g".to_string(), 1e-6), ("r0_nue[2]".to_string(), 1e5)];
    for k in 0..3 {
        p.push((format!("inertia_body[{}]", k + 1), INERTIA_BODY_KGM2[k]));
        p.push((format!("omega0_body[{}]", k + 1), OMEGA0_BODY_RADPS[k]));
    }
    p
}

/// The parameters of each FMU's long run: the plant's tumble, LanderNav's errors (all on).
pub fn parameters(lander: Lander) -> Vec<(String, f64)> {
    match lander {
        Lander::Plant => plant_parameters(),
        Lander::Nav => nav_errors_on(2026),
        Lander::Gnc => Vec::new(),
    }
}

/// Runs `steps` steps with `checkpoints` save/restore checks evenly spread, with the FMU's
/// long-run [`parameters`].
pub fn run(fmu: &Fmu, steps: usize, checkpoints: usize) -> Result<Report, String> {
    run_with(fmu, steps, checkpoints, &parameters(fmu.lander()))
}

/// [`run`] with the given parameters (name, value) instead.
pub fn run_with(
    fmu: &Fmu,
    steps: usize,
    checkpoints: usize,
    parameters: &[(String, f64)],
) -> Result<Report, String> {
    let probe = Probe::new(fmu);
    let inst = fmu.instantiate("long-run", false);
    for status in [inst.setup(0.0, None), inst.enter_init()] {
        if status != fmi2OK {
            return Err(format!("initialization: {status}"));
        }
    }
    for (name, value) in parameters {
        if inst.set_parameter(name, *value) != fmi2OK {
            return Err(format!("cannot set {name}: {:?}", inst.take_log()));
        }
    }
    if inst.exit_init() != fmi2OK {
        return Err(format!("fmi2ExitInitializationMode: {:?}", inst.take_log()));
    }
    let every = (steps / checkpoints.max(1)).max(REPLAY_STEPS + 1);
    let mut report = Report::default();
    let mut h0: Option<[f64; 3]> = None;
    let mut k = 0;
    while k < steps {
        let y = probe.step(&inst, k)?;
        let q = probe.quaternion(&y);
        let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
        report.max_quaternion_norm_error = report.max_quaternion_norm_error.max((norm - 1.0).abs());
        report.probed_steps += 1;
        if probe.is_identity(fmu.lander(), k, &y) {
            report.identity_steps += 1;
        }
        if let Some(h) = probe.angular_momentum_nue(&y) {
            let h0 = *h0.get_or_insert(h);
            let diff = [0, 1, 2].map(|i| h[i] - h0[i]);
            let drift = diff.iter().map(|d| d * d).sum::<f64>().sqrt()
                / h0.iter().map(|d| d * d).sum::<f64>().sqrt();
            report.max_angular_momentum_drift = report.max_angular_momentum_drift.max(drift);
        }
        k += 1;
        if k % every == 0 && k + REPLAY_STEPS < steps {
            replay(&probe, &inst, k)?;
            report.restores += 1;
            k += REPLAY_STEPS;
            report.rss_kib.push(vm_rss_kib().unwrap_or(0));
        }
    }
    report.steps = k;
    Ok(report)
}

/// Saves the state, serializes and deserializes it, runs `REPLAY_STEPS`, restores the copy and
/// runs them again: both runs must agree bit for bit.
fn replay(probe: &Probe, inst: &Instance, k: usize) -> Result<(), String> {
    let (status, mut saved) = inst.get_fmu_state();
    if status != fmi2OK {
        return Err(format!("fmi2GetFMUstate at step {k}: {status}"));
    }
    let bytes = inst
        .serialize(saved)
        .map_err(|s| format!("serialize at step {k}: {s}"))?;
    let (status, mut copy) = inst.deserialize(&bytes);
    if status != fmi2OK {
        return Err(format!("fmi2DeSerializeFMUstate at step {k}: {status}"));
    }
    let run = |from: usize| -> Result<Vec<u64>, String> {
        let mut bits = Vec::new();
        for j in from..from + REPLAY_STEPS {
            bits.extend(probe.step(inst, j)?.iter().map(|v| v.to_bits()));
        }
        Ok(bits)
    };
    let first = run(k)?;
    if inst.set_fmu_state(copy) != fmi2OK {
        return Err(format!(
            "fmi2SetFMUstate at step {k}: {:?}",
            inst.take_log()
        ));
    }
    let second = run(k)?;
    if first != second {
        return Err(format!(
            "the run restored at step {k} differs from the original"
        ));
    }
    for state in [&mut saved, &mut copy] {
        if inst.free_fmu_state(state) != fmi2OK {
            return Err(format!("fmi2FreeFMUstate at step {k}"));
        }
    }
    Ok(())
}
