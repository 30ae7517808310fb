//! The long run: millions of communication steps of one FMU, checking after every
//! step that the outputs are finite and the attitude quaternion is a unit quaternion, and for
//! the plant (tumbling torque-free, engines off) that the angular momentum is conserved; the
//! FMU state is saved, serialized, restored and re-run bit-identically at checkpoints along
//! the way; resident memory is sampled at each checkpoint. LanderNav runs with every error on
//! (its estimate must stay finite and a unit quaternion, and differ from the truth), or with
//! every error off (its estimate must be the truth bit for bit). LanderSensors measures a
//! drifting, rocking true state between 100 m and 1,100 m (its validity flags must be 0 or 1
//! and an invalid measurement must read 0); LanderFilter fuses what the sensors would
//! measure of such a state (its covariance diagonal must stay positive and finite, its
//! quaternion a unit one, its degrees of freedom within their ranges, and its estimate is
//! compared with the truth).
use crate::ffi::*;
use crate::instance::{Fmu, Instance};
use crate::package::Lander;
use crate::reference::{
    boolean_inputs_at, input_names, inputs_at, nav_errors_on, rotate, true_state, Outputs, Wiring,
    FILTER_ALTITUDE, STEP_S,
};
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
    /// max over all steps of | |q| - 1 | of the attitude (plant, LanderNav, LanderFilter) or
    /// reference (GNC) quaternion; 0 for LanderSensors, which outputs none.
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
    /// LanderSensors: probed steps at which altimeter_valid, velocimeter_valid_1, _2, _3 were
    /// true. LanderFilter: probed steps with altimeter_dof = 1, then with velocimeter_dof = 0,
    /// 1, 2 and 3.
    pub valid_counts: Vec<usize>,
    /// LanderFilter: smallest and largest element of covariance_diag over all probed steps.
    pub covariance_min: f64,
    pub covariance_max: f64,
    /// LanderFilter: largest |altitude estimate - true altitude| (m) and |velocity estimate -
    /// true velocity| (m/s) over all probed steps.
    pub max_altitude_error_m: f64,
    pub max_velocity_error_mps: f64,
}

struct Probe {
    wiring: Wiring,
    /// Positions in the Real outputs of the quaternion (none for LanderSensors) and (plant)
    /// of omega_body.
    quaternion: Option<[usize; 4]>,
    omega: Option<[usize; 3]>,
    /// LanderNav: for each input (in `inputs` order), the position in `outputs` of its
    /// estimate (the input's name without `_true`).
    estimates: Option<Vec<usize>>,
    /// LanderSensors: (position of the flag in the Boolean outputs, position of the value it
    /// qualifies in the Real outputs), altimeter then beams 1 to 3.
    flags: Vec<(usize, usize)>,
    /// LanderFilter: positions of covariance_diag, r_nue, v_nue (Reals) and of
    /// altimeter_dof, velocimeter_dof, measurements_rejected (Integers).
    filter: Option<FilterProbe>,
}

struct FilterProbe {
    covariance: Vec<usize>,
    r: [usize; 3],
    v: [usize; 3],
    altimeter_dof: usize,
    velocimeter_dof: usize,
    rejected: usize,
}

impl Probe {
    fn new(fmu: &Fmu) -> Probe {
        let wiring = Wiring::of(fmu);
        let position = |vrs: &[u32], name: &str| {
            let vr = fmu.vr(name);
            vrs.iter().position(|&o| o == vr).expect("an output")
        };
        let at = |name: &str| position(&wiring.outputs, name);
        let q = match fmu.lander() {
            Lander::Plant | Lander::Nav | Lander::Filter => Some("q_body_to_nue"),
            Lander::Gnc => Some("q_ref"),
            _ => None,
        };
        let omega = (fmu.lander() == Lander::Plant)
            .then(|| [1, 2, 3].map(|k| at(&format!("omega_body[{k}]"))));
        let estimates = (fmu.lander() == Lander::Nav).then(|| {
            input_names(Lander::Nav)
                .iter()
                .map(|n| at(&n.replace("_true", "")))
                .collect()
        });
        let flags = if fmu.lander() == Lander::Sensors {
            let flag = |name: &str| position(&wiring.boolean_outputs, name);
            let mut flags = vec![(flag("altimeter_valid"), at("altimeter_range"))];
            for k in 1..=3 {
                flags.push((
                    flag(&format!("velocimeter_valid_{k}")),
                    at(&format!("velocimeter_los_velocity[{k}]")),
                ));
            }
            flags
        } else {
            Vec::new()
        };
        let filter = (fmu.lander() == Lander::Filter).then(|| {
            let int = |name: &str| position(&wiring.integer_outputs, name);
            FilterProbe {
                covariance: (1..=15)
                    .map(|k| at(&format!("covariance_diag[{k}]")))
                    .collect(),
                r: [1, 2, 3].map(|k| at(&format!("r_nue[{k}]"))),
                v: [1, 2, 3].map(|k| at(&format!("v_nue[{k}]"))),
                altimeter_dof: int("altimeter_dof"),
                velocimeter_dof: int("velocimeter_dof"),
                rejected: int("measurements_rejected"),
            }
        });
        Probe {
            estimates,
            quaternion: q.map(|q| [1, 2, 3, 4].map(|k| at(&format!("{q}[{k}]")))),
            omega,
            flags,
            filter,
            wiring,
        }
    }

    fn inputs(&self, lander: Lander, t: f64) -> Vec<f64> {
        match lander {
            // Engines off, no torque: a free tumble.
            Lander::Plant => vec![0.0; self.wiring.inputs.len()],
            _ => inputs_at(lander, t),
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

    /// One step: set inputs, read outputs, step; the outputs read, checked finite (Reals)
    /// and 0 or 1 (Booleans).
    fn step(&self, inst: &Instance, k: usize) -> Result<Outputs, String> {
        let t = k as f64 * STEP_S;
        let lander = inst.fmu.lander();
        let mut status = inst.set_reals(&self.wiring.inputs, &self.inputs(lander, t));
        if status == fmi2OK && !self.wiring.boolean_inputs.is_empty() {
            status = inst.set_booleans(&self.wiring.boolean_inputs, &boolean_inputs_at(lander, t));
        }
        let (get, outputs) = self.wiring.get_outputs(inst);
        let step = inst.step(t, STEP_S);
        if status != fmi2OK || get != fmi2OK || step != fmi2OK {
            // A Warning that comes with its message is the FMU telling what it sees (the
            // tumbling pattern tilts LanderGnc's thrust axis beyond 90 deg); anything else,
            // or a Warning without a message, fails the run.
            let log = inst.take_log();
            let explained = [status, get, step]
                .iter()
                .all(|s| *s == fmi2OK || *s == fmi2Warning)
                && log.iter().any(|r| r.status == fmi2Warning);
            if !explained {
                return Err(format!(
                    "step {k}: set {status}, get {get}, step {step}: {log:?}"
                ));
            }
        }
        if let Some(v) = outputs.reals.iter().find(|v| !v.is_finite()) {
            return Err(format!("step {k}: output {v}"));
        }
        if let Some(b) = outputs.booleans.iter().find(|&&b| b != 0 && b != 1) {
            return Err(format!("step {k}: Boolean output {b}"));
        }
        Ok(outputs)
    }

    fn quaternion(&self, y: &[f64]) -> Option<[f64; 4]> {
        self.quaternion.map(|q| q.map(|i| y[i]))
    }

    fn angular_momentum_nue(&self, y: &[f64]) -> Option<[f64; 3]> {
        let omega = self.omega?.map(|i| y[i]);
        let h_body = [0, 1, 2].map(|i| INERTIA_BODY_KGM2[i] * omega[i]);
        Some(rotate(self.quaternion(y)?, h_body))
    }

    /// The invariants of LanderSensors and LanderFilter at step `k`, into `report`.
    fn check_measurements(&self, k: usize, y: &Outputs, report: &mut Report) -> Result<(), String> {
        if !self.flags.is_empty() {
            report.valid_counts.resize(self.flags.len(), 0);
            for (j, &(flag, value)) in self.flags.iter().enumerate() {
                if y.booleans[flag] == 1 {
                    report.valid_counts[j] += 1;
                } else if y.reals[value] != 0.0 {
                    return Err(format!(
                        "step {k}: measurement {j} invalid but reads {}",
                        y.reals[value]
                    ));
                }
            }
        }
        let Some(f) = &self.filter else {
            return Ok(());
        };
        for &i in &f.covariance {
            let p = y.reals[i];
            if !(p > 0.0 && p.is_finite()) {
                return Err(format!("step {k}: covariance_diag element {i} = {p}"));
            }
            report.covariance_min = report.covariance_min.min(p);
            report.covariance_max = report.covariance_max.max(p);
        }
        let (alt, vel, rejected) = (
            y.integers[f.altimeter_dof],
            y.integers[f.velocimeter_dof],
            y.integers[f.rejected],
        );
        if !(0..=1).contains(&alt) || !(0..=3).contains(&vel) || rejected != 0 {
            return Err(format!(
                "step {k}: altimeter_dof {alt}, velocimeter_dof {vel}, \
                 measurements_rejected {rejected} (no gating)"
            ));
        }
        report.valid_counts.resize(5, 0);
        report.valid_counts[0] += alt as usize;
        report.valid_counts[1 + vel as usize] += 1;
        let truth = true_state(k as f64 * STEP_S, FILTER_ALTITUDE);
        report.max_altitude_error_m = report
            .max_altitude_error_m
            .max((y.reals[f.r[1]] - truth.r[1]).abs());
        let dv = [0, 1, 2].map(|i| y.reals[f.v[i]] - truth.v[i]);
        report.max_velocity_error_mps = report
            .max_velocity_error_mps
            .max(dv.iter().map(|d| d * d).sum::<f64>().sqrt());
        Ok(())
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

/// LanderSensors' long run: its default errors (biases, their random walks, white noise)
/// from seed 2026, and 5 % of the velocimeter's samples dropped.
pub fn sensors_parameters() -> Vec<(String, f64)> {
    vec![
        ("seed".to_string(), 2026.0),
        ("velocimeter_dropout_probability".to_string(), 0.05),
    ]
}

/// The parameters of each FMU's long run: the plant's tumble, LanderNav's errors (all on),
/// LanderSensors' dropouts; LanderGnc and LanderFilter at their defaults.
pub fn parameters(lander: Lander) -> Vec<(String, f64)> {
    match lander {
        Lander::Plant => plant_parameters(),
        Lander::Nav => nav_errors_on(2026),
        Lander::Sensors => sensors_parameters(),
        _ => Vec::new(),
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
    // A deterministic input pattern, not a plant answering LanderGnc's commands: its input
    // monitor would rightly say they do not add up.
    // The pattern also holds a torque at its limit for the whole run.
    if fmu.lander() == Lander::Gnc
        && (inst.set_booleans(&[fmu.vr("input_monitor")], &[false]) != fmi2OK
            || inst.set_parameter("saturation_time", 1e6) != fmi2OK)
    {
        return Err(format!(
            "cannot quiet the supervision: {:?}",
            inst.take_log()
        ));
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
    let mut report = Report {
        covariance_min: f64::INFINITY,
        ..Report::default()
    };
    let mut h0: Option<[f64; 3]> = None;
    let mut k = 0;
    while k < steps {
        let outputs = probe.step(&inst, k)?;
        let y = &outputs.reals;
        if let Some(q) = probe.quaternion(y) {
            let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
            report.max_quaternion_norm_error =
                report.max_quaternion_norm_error.max((norm - 1.0).abs());
        }
        report.probed_steps += 1;
        if probe.is_identity(fmu.lander(), k, y) {
            report.identity_steps += 1;
        }
        probe.check_measurements(k, &outputs, &mut report)?;
        if let Some(h) = probe.angular_momentum_nue(y) {
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
            bits.extend(probe.step(inst, j)?.bits());
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
