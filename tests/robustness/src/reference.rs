//! The legal run every invariant comes back to: a master's ordinary sequence (setup,
//! initialize, then per step set inputs, get outputs, do step) with deterministic inputs,
//! recorded as the bit patterns of every Real output. Two runs agree only if every bit does.
// std's transcendental functions make the legal run's deterministic inputs here, outside any FMU (the
// workspace clippy.toml forbids them for the FMUs' sake).
#![allow(clippy::disallowed_methods)]
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
/// LanderSensors: such a true state ([`true_state`]) between 100 m and 1,100 m, so that the
/// velocimeter's beams leave and re-enter their 1,000 m range, with the specific force that
/// moves it against lunar gravity.
/// LanderFilter: what LanderSensors at its defaults would measure of that state between
/// 200 m and 800 m ([`measurements_at`]), with noise of the sensors' default 1-sigmas.
pub fn inputs_at(lander: Lander, t_s: f64) -> Vec<f64> {
    match lander {
        Lander::Plant => vec![
            1300.0 + 50.0 * (0.3 * t_s).sin(),
            5.0 * (0.5 * t_s).sin(),
            -3.0 * (0.2 * t_s).cos(),
            2.0,
        ],
        Lander::Gnc | Lander::Nav => {
            let s = true_state(t_s, NAV_ALTITUDE);
            s.r.iter()
                .chain(&s.v)
                .chain(&s.q)
                .chain(&s.omega)
                .copied()
                .chain([800.0 + 50.0 * (0.001 * t_s).sin()])
                .collect()
        }
        Lander::Sensors => {
            let s = true_state(t_s, SENSORS_ALTITUDE);
            s.r.iter()
                .chain(&s.v)
                .chain(&s.q)
                .chain(&s.omega)
                .chain(&s.specific_force_body())
                .copied()
                .collect()
        }
        Lander::Filter => measurements_at(t_s).reals(),
        // An FMU this suite knows nothing of runs on its start values.
        _ => Vec::new(),
    }
}

/// The Boolean inputs of the legal run at `t_s`, in the order of [`boolean_input_names`]:
/// LanderFilter's validity flags; none for the others.
pub fn boolean_inputs_at(lander: Lander, t_s: f64) -> Vec<bool> {
    match lander {
        Lander::Filter => measurements_at(t_s).valid.to_vec(),
        _ => Vec::new(),
    }
}

/// The contract names of the inputs `inputs_at` feeds (docs/interface.md, docs/sensors.md,
/// docs/filter.md).
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
        Lander::Sensors => indexed("r_nue", 3)
            .chain(indexed("v_nue", 3))
            .chain(indexed("q_body_to_nue", 4))
            .chain(indexed("omega_body", 3))
            .chain(indexed("specific_force_body", 3))
            .collect(),
        Lander::Filter => indexed("accel_body_meas", 3)
            .chain(indexed("gyro_body_meas", 3))
            .chain(std::iter::once("altimeter_range".to_string()))
            .chain(indexed("velocimeter_los_velocity", 3))
            .collect(),
        _ => Vec::new(),
    }
}

/// The names of the Boolean inputs [`boolean_inputs_at`] feeds.
pub fn boolean_input_names(lander: Lander) -> Vec<String> {
    match lander {
        Lander::Filter => [
            "altimeter_valid",
            "velocimeter_valid_1",
            "velocimeter_valid_2",
            "velocimeter_valid_3",
        ]
        .map(String::from)
        .to_vec(),
        _ => Vec::new(),
    }
}

/// Lunar gravity of the plant's, the sensors' and the filter's defaults, m/s2 (along -Up).
pub const GRAVITY_MPS2: f64 = 1.62;

/// Altitude of a [`true_state`]: mean and amplitude of a slow cosine, m.
#[derive(Debug, Clone, Copy)]
pub struct Altitude {
    pub mean_m: f64,
    pub amplitude_m: f64,
}

/// The GNC's and LanderNav's inputs: 200 m to 800 m.
pub const NAV_ALTITUDE: Altitude = Altitude {
    mean_m: 500.0,
    amplitude_m: 300.0,
};
/// LanderSensors' inputs: 100 m to 1,100 m.
pub const SENSORS_ALTITUDE: Altitude = Altitude {
    mean_m: 600.0,
    amplitude_m: 500.0,
};
/// LanderFilter's measurements: 200 m to 800 m (every beam within its range but when tilted
/// high up).
pub const FILTER_ALTITUDE: Altitude = NAV_ALTITUDE;

/// A smooth, bounded, periodic true state (NUE, body to NUE, scalar first): a lander drifting
/// a few metres, rising and sinking, rocking by up to 0.2 rad about a fixed axis.
#[derive(Debug, Clone, Copy)]
pub struct TrueState {
    pub r: [f64; 3],
    pub v: [f64; 3],
    /// The acceleration d v / dt, NUE.
    pub a: [f64; 3],
    pub q: [f64; 4],
    pub omega: [f64; 3],
}

impl TrueState {
    /// The specific force in body axes: R^T (a - g), what an accelerometer feels.
    pub fn specific_force_body(&self) -> [f64; 3] {
        let f_nue = [self.a[0], self.a[1] + GRAVITY_MPS2, self.a[2]];
        let [w, x, y, z] = self.q;
        rotate([w, -x, -y, -z], f_nue)
    }
}

pub fn true_state(t_s: f64, altitude: Altitude) -> TrueState {
    let axis: [f64; 3] = [0.3, 0.9, 0.3];
    let norm = axis.iter().map(|a| a * a).sum::<f64>().sqrt();
    let axis = axis.map(|a| a / norm);
    let angle_rad = 0.2 * (0.07 * t_s).sin();
    let rate_radps = 0.2 * 0.07 * (0.07 * t_s).cos();
    let (s, c) = (0.5 * angle_rad).sin_cos();
    let Altitude {
        mean_m,
        amplitude_m,
    } = altitude;
    TrueState {
        r: [
            10.0 * (0.01 * t_s).sin(),
            mean_m + amplitude_m * (0.003 * t_s).cos(),
            10.0 * (0.013 * t_s).cos(),
        ],
        v: [
            0.1 * (0.01 * t_s).cos(),
            -0.003 * amplitude_m * (0.003 * t_s).sin(),
            -0.13 * (0.013 * t_s).sin(),
        ],
        a: [
            -0.001 * (0.01 * t_s).sin(),
            -0.003 * 0.003 * amplitude_m * (0.003 * t_s).cos(),
            -0.13 * 0.013 * (0.013 * t_s).cos(),
        ],
        q: [c, axis[0] * s, axis[1] * s, axis[2] * s],
        omega: axis.map(|a| a * rate_radps),
    }
}

/// `v` rotated by the scalar-first unit quaternion `q`: v + 2 w (u x v) + 2 u x (u x v).
pub fn rotate(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
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

/// One communication point's measurements as LanderSensors gives them to LanderFilter.
#[derive(Debug, Clone, Copy)]
pub struct SensorSample {
    pub accel: [f64; 3],
    pub gyro: [f64; 3],
    pub altimeter_range: f64,
    pub los_velocity: [f64; 3],
    /// Altimeter, then the three velocimeter beams.
    pub valid: [bool; 4],
}

impl SensorSample {
    /// In the order of [`input_names`] for LanderFilter.
    pub fn reals(&self) -> Vec<f64> {
        self.accel
            .iter()
            .chain(&self.gyro)
            .chain([&self.altimeter_range])
            .chain(&self.los_velocity)
            .copied()
            .collect()
    }
}

/// A standard normal value that is a function of (t, channel) alone (splitmix64 and
/// Box-Muller), so that the inputs of any step can be recomputed.
fn normal(t_s: f64, channel: u64) -> f64 {
    let u1 = uniform(t_s, 2 * channel);
    let u2 = uniform(t_s, 2 * channel + 1);
    (-2.0 * (1.0 - u1).ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// Uniform in [0, 1) from (t, channel).
fn uniform(t_s: f64, channel: u64) -> f64 {
    let mut z = t_s
        .to_bits()
        .wrapping_add(channel.wrapping_mul(0x9e37_79b9_7f4a_7c15));
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

/// What LanderSensors at its defaults (no bias, no scale factor or misalignment, the default
/// beams over the flat terrain at 0 m) would measure of [`true_state`] at `t_s` between 200 m
/// and 800 m: the IMU with its white noise (1-sigma 5e-3 m/s2 and 1.5e-4 rad/s at 0.01 s), the
/// altimeter with 0.1 m and 1e-3 per metre, each beam with 0.02 m/s; a beam is invalid beyond
/// 1,000 m of slant range, and each beam and the altimeter drop 2 % of their samples.
pub fn measurements_at(t_s: f64) -> SensorSample {
    let s = true_state(t_s, FILTER_ALTITUDE);
    let f = s.specific_force_body();
    let accel = std::array::from_fn(|i| f[i] + 5e-3 * normal(t_s, i as u64));
    let gyro = std::array::from_fn(|i| s.omega[i] + 1.5e-4 * normal(t_s, 3 + i as u64));
    // The slant range along a body beam b to the plane Up = 0, with its validity.
    let beam = |b: [f64; 3], max_range: f64, channel: u64| -> Option<(f64, [f64; 3])> {
        let n = b.iter().map(|x| x * x).sum::<f64>().sqrt();
        let d = rotate(s.q, b.map(|x| x / n));
        let rho = s.r[1] / -d[1];
        let kept = uniform(t_s, 100 + channel) >= 0.02;
        (d[1] < 0.0 && rho <= max_range && kept).then_some((rho, d))
    };
    let altimeter = beam([0.0, -1.0, 0.0], 2000.0, 0).map(|(rho, _)| {
        let sigma = (0.1f64 * 0.1 + (1e-3 * rho) * (1e-3 * rho)).sqrt();
        rho + sigma * normal(t_s, 6)
    });
    let (sc, cc) = 20f64.to_radians().sin_cos();
    let mut los = [None; 3];
    for (i, l) in los.iter_mut().enumerate() {
        let (sa, ca) = (120.0 * i as f64).to_radians().sin_cos();
        *l = beam([sc * ca, -cc, sc * sa], 1000.0, 1 + i as u64).map(|(_, d)| {
            let v_los: f64 = (0..3).map(|k| s.v[k] * d[k]).sum();
            v_los + 0.02 * normal(t_s, 7 + i as u64)
        });
    }
    SensorSample {
        accel,
        gyro,
        altimeter_range: altimeter.unwrap_or(0.0),
        los_velocity: los.map(|l| l.unwrap_or(0.0)),
        valid: [
            altimeter.is_some(),
            los[0].is_some(),
            los[1].is_some(),
            los[2].is_some(),
        ],
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

/// Value references of the legal run's inputs and of every output, by type.
#[derive(Debug, Clone)]
pub struct Wiring {
    pub inputs: Vec<u32>,
    pub boolean_inputs: Vec<u32>,
    pub outputs: Vec<u32>,
    pub integer_outputs: Vec<u32>,
    pub boolean_outputs: Vec<u32>,
}

impl Wiring {
    pub fn of(fmu: &Fmu) -> Wiring {
        let outputs = |kind: VariableKind| -> Vec<u32> {
            fmu.package
                .variables
                .iter()
                .filter(|v| v.kind == kind && v.causality == Causality::Output)
                .map(|v| v.value_reference)
                .collect()
        };
        let vrs = |names: Vec<String>| names.iter().map(|n| fmu.vr(n)).collect();
        Wiring {
            inputs: vrs(input_names(fmu.lander())),
            boolean_inputs: vrs(boolean_input_names(fmu.lander())),
            outputs: outputs(VariableKind::Real),
            integer_outputs: outputs(VariableKind::Integer),
            boolean_outputs: outputs(VariableKind::Boolean),
        }
    }

    /// Sets the legal run's inputs at `t` (Reals, then Booleans if any): the first status
    /// that is not fmi2OK, or fmi2OK.
    pub fn set_inputs(&self, inst: &Instance, t: f64) -> fmi2Status {
        let lander = inst.fmu.lander();
        let status = inst.set_reals(&self.inputs, &inputs_at(lander, t));
        if status != fmi2OK || self.boolean_inputs.is_empty() {
            return status;
        }
        inst.set_booleans(&self.boolean_inputs, &boolean_inputs_at(lander, t))
    }

    /// Reads every output: the first status that is not fmi2OK (or fmi2OK) and the Reals,
    /// Integers and Booleans read.
    pub fn get_outputs(&self, inst: &Instance) -> (fmi2Status, Outputs) {
        let (s1, reals) = inst.get_reals(&self.outputs);
        let (s2, integers) = inst.get_integers(&self.integer_outputs);
        let (s3, booleans) = inst.get_booleans(&self.boolean_outputs);
        let status = [s1, s2, s3]
            .into_iter()
            .find(|s| *s != fmi2OK)
            .unwrap_or(fmi2OK);
        (
            status,
            Outputs {
                reals,
                integers,
                booleans,
            },
        )
    }
}

/// The outputs read at one communication point, in the order of a [`Wiring`]'s.
#[derive(Debug, Clone, Default)]
pub struct Outputs {
    pub reals: Vec<f64>,
    pub integers: Vec<i32>,
    pub booleans: Vec<fmi2Boolean>,
}

impl Outputs {
    /// Every value's bit pattern, Reals first.
    pub fn bits(&self) -> impl Iterator<Item = u64> + '_ {
        let reals = self.reals.iter().map(|v| v.to_bits());
        let integers = self.integers.iter().map(|&i| i as u32 as u64);
        let booleans = self.booleans.iter().map(|&b| b as u32 as u64);
        reals.chain(integers).chain(booleans)
    }
}

/// `steps` steps of the legal run from t = 0 on an instance in state Instantiated; the bit
/// patterns of all outputs (Reals, Integers, Booleans) read before each step and after the
/// last. `Err` names the
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
    // The legal run's inputs are a deterministic pattern, not a plant answering LanderGnc's
    // commands: its input monitor would rightly say they do not add up.
    if inst.fmu.lander() == Lander::Gnc {
        let status = inst.set_booleans(&[inst.fmu.vr("input_monitor")], &[false]);
        if status != fmi2OK {
            return fail("setting input_monitor", status);
        }
        let status = inst.set_parameter("saturation_time", 1e6);
        if status != fmi2OK {
            return fail("setting saturation_time", status);
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
        let status = wiring.set_inputs(inst, t);
        if status != fmi2OK {
            return fail(&format!("setting the inputs at t = {t}"), status);
        }
        let (status, outputs) = wiring.get_outputs(inst);
        if status != fmi2OK {
            return fail(&format!("reading the outputs at t = {t}"), status);
        }
        bits.extend(outputs.bits());
        if k < steps {
            let status = inst.step(t, STEP_S);
            if status != fmi2OK {
                return fail(&format!("fmi2DoStep at t = {t}"), status);
            }
        }
    }
    Ok(bits)
}
