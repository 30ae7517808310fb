//! LanderPlant's partial derivatives through the C ABI of both FMI versions: Model Exchange
//! directional derivatives against central differences of `fmi2GetDerivatives` /
//! `fmi3GetContinuousStateDerivatives` and of the outputs, FMI 3.0's adjoint as the exact
//! transpose, Co-Simulation's outputs by the inputs, and every bad argument refused with a
//! log line while the instance stays usable.
#![allow(unsafe_code)]
use crate::common::{self, vr};
use crate::fmi3_common::Plant as Plant3;
use fmi_testkit::fmi2::*;
use fmi_testkit::fmi3_ffi::{fmi3Error, fmi3OK};
use fmi_testkit::{fmi2_me_functions, Fmi2MeFunctions, MeSolver};

const NX: usize = 18;

/// The FMI 2.0 scalars of the states, in state-vector order.
fn state_names() -> Vec<String> {
    let mut names = Vec::new();
    for (base, n) in [
        ("translation_state", 6),
        ("attitude_state", 4),
        ("omega_body", 3),
        ("mass", 1),
        ("thrust_lag_state", 1),
        ("torque_lag_state_body", 3),
    ] {
        if n == 1 {
            names.push(base.to_string());
        } else {
            names.extend((1..=n).map(|i| format!("{base}[{i}]")));
        }
    }
    names
}

/// The unknowns compared: the state derivatives and the outputs that move with the knowns.
fn unknown_names() -> Vec<String> {
    let mut names: Vec<String> = state_names().iter().map(|s| format!("der_{s}")).collect();
    for (base, n) in [
        ("r_nue", 3),
        ("v_nue", 3),
        ("q_body_to_nue", 4),
        ("specific_force_body", 3),
        ("engine_torque_body", 3),
        ("torque_actual_body", 3),
    ] {
        names.extend((1..=n).map(|i| format!("{base}[{i}]")));
    }
    names.push("thrust_actual".into());
    names
}

const INPUTS: [&str; 4] = [
    "thrust_cmd",
    "torque_cmd_body[1]",
    "torque_cmd_body[2]",
    "torque_cmd_body[3]",
];

/// Lags on, so that every state moves the derivatives; a tumbling, thrusting lander.
const PARAMETERS: [(&str, f64); 9] = [
    ("engine_time_constant", 0.2),
    ("rcs_time_constant", 0.1),
    ("r0_nue[2]", 1500.0),
    ("v0_nue[1]", 12.0),
    ("v0_nue[2]", -30.0),
    ("omega0_body[1]", 0.2),
    ("omega0_body[3]", -0.1),
    ("q0_body_to_nue[1]", 0.96),
    ("q0_body_to_nue[2]", 0.28),
];

const COMMANDS: [(&str, f64); 4] = [
    ("thrust_cmd", 1300.0),
    ("torque_cmd_body[1]", 30.0),
    ("torque_cmd_body[2]", -70.0),
    ("torque_cmd_body[3]", 10.0),
];

/// The largest error of `numeric` against `exact` (columns by known), as a fraction of the
/// entry or, for a small one, of 1e-3 of the row's largest contribution of any known.
fn largest_error(exact: &[Vec<f64>], numeric: &[Vec<f64>], steps: &[f64]) -> f64 {
    let rows = exact[0].len();
    let mut worst: f64 = 0.0;
    for i in 0..rows {
        let scale = (0..exact.len())
            .map(|j| (exact[j][i] * steps[j]).abs())
            .fold(0.0, f64::max);
        for j in 0..exact.len() {
            let reference = exact[j][i]
                .abs()
                .max(1e-3 * scale / steps[j])
                .max(f64::MIN_POSITIVE);
            worst = worst.max((numeric[j][i] - exact[j][i]).abs() / reference);
        }
    }
    worst
}

struct Me2 {
    solver: MeSolver,
    me: Fmi2MeFunctions,
    x: Vec<f64>,
}

impl Me2 {
    fn started() -> Me2 {
        let guid = fmi2_export::guid::<fmu_plant::LanderPlant>();
        let me = fmi2_me_functions!(fmu_plant);
        let mut solver = MeSolver::instantiate(&common::FUNCTIONS, me, &guid, NX, 2);
        for (name, value) in PARAMETERS.iter().chain(&COMMANDS) {
            assert_eq!(solver.instance.set_real(vr(name), *value), fmi2OK);
        }
        solver.start();
        let mut x = solver.x.clone();
        x[14] = 900.0; // thrust lag state
        x[15] = 40.0; // torque lag state
        x[17] = -25.0;
        Me2 { solver, me, x }
    }

    fn set_states(&self, x: &[f64]) {
        let c = self.solver.instance.component();
        // SAFETY: a live instance; x of the state count.
        let status = unsafe { (self.me.set_continuous_states)(c, x.as_ptr(), x.len()) };
        assert_eq!(status, fmi2OK, "{:?}", self.solver.instance.messages());
    }

    /// Derivatives, then the output unknowns, at state `x`.
    fn values(&self, x: &[f64], outputs: &[u32]) -> Vec<f64> {
        self.set_states(x);
        let mut dx = vec![0.0; NX];
        let c = self.solver.instance.component();
        // SAFETY: as above.
        let status = unsafe { (self.me.get_derivatives)(c, dx.as_mut_ptr(), NX) };
        assert_eq!(status, fmi2OK);
        let (status, y) = self.solver.instance.get_reals(outputs);
        assert_eq!(status, fmi2OK);
        dx.extend(y);
        dx
    }
}

#[test]
fn fmi2_model_exchange_derivatives_equal_central_differences_of_get_derivatives() {
    let me = Me2::started();
    let unknowns: Vec<u32> = unknown_names().iter().map(|n| vr(n)).collect();
    let outputs = &unknowns[NX..];
    let knowns: Vec<String> = state_names()
        .into_iter()
        .chain(INPUTS.iter().map(|s| s.to_string()))
        .collect();
    me.set_states(&me.x);
    let instance = &me.solver.instance;
    let mut exact = Vec::new();
    let mut numeric = Vec::new();
    let mut steps = Vec::new();
    for (j, known) in knowns.iter().enumerate() {
        me.set_states(&me.x);
        let (status, column) = instance.directional_derivative(&unknowns, &[vr(known)], &[1.0]);
        assert_eq!(status, fmi2OK, "{:?}", instance.messages());
        exact.push(column);
        let (plus, minus, h) = if j < NX {
            let h = 1e-6 * me.x[j].abs().max(1.0);
            let mut x = me.x.clone();
            x[j] += h;
            let plus = me.values(&x, outputs);
            x[j] -= 2.0 * h;
            (plus, me.values(&x, outputs), h)
        } else {
            let base = COMMANDS[j - NX].1;
            let h = 1e-6 * base.abs();
            instance.set_real(vr(known), base + h);
            let plus = me.values(&me.x, outputs);
            instance.set_real(vr(known), base - h);
            let minus = me.values(&me.x, outputs);
            instance.set_real(vr(known), base);
            (plus, minus, h)
        };
        numeric.push(
            plus.iter()
                .zip(&minus)
                .map(|(p, m)| (p - m) / (2.0 * h))
                .collect::<Vec<f64>>(),
        );
        steps.push(h);
    }
    let error = largest_error(&exact, &numeric, &steps);
    println!("FMI 2.0 Model Exchange: largest error against central differences {error:.1e}");
    assert!(error <= 1e-6, "{error:e}");
    // Not all zero: the test would tell a Jacobian that is not there.
    let nonzeros = exact.iter().flatten().filter(|v| **v != 0.0).count();
    assert!(nonzeros > 50, "{nonzeros}");
}

/// The FMI 3.0 value references: knowns (states, then thrust and torque commands) and
/// unknowns (state derivatives, then the outputs), each array whole.
const KNOWNS3: [u32; 8] = [200, 206, 20, 23, 210, 211, 1, 2];
const UNKNOWNS3: [u32; 13] = [220, 226, 230, 233, 234, 235, 10, 13, 16, 70, 29, 26, 25];
const N_KNOWNS3: usize = 22;
const N_UNKNOWNS3: usize = 38;

fn length(name: &str) -> usize {
    use fmi_model::Model;
    fmu_plant::LanderPlant::declarations()
        .iter()
        .find(|d| d.name == name)
        .map_or(1, |d| d.shape().len())
}

fn me3() -> Plant3 {
    let fmu = Plant3::model_exchange();
    assert_eq!(fmu.enter_initialization_mode(0.0, None), fmi3OK);
    for (name, value) in PARAMETERS.iter().chain(&COMMANDS) {
        let (base, element) = match name.split_once('[') {
            Some((base, rest)) => (base, rest.trim_end_matches(']').parse::<usize>().unwrap()),
            None => (*name, 1),
        };
        let n = length(base);
        let mut values = fmu.get(base, n);
        values[element - 1] = *value;
        assert_eq!(fmu.set(base, &values), fmi3OK, "{}", fmu.log());
    }
    assert_eq!(fmu.exit_initialization_mode(), fmi3OK);
    assert_eq!(fmu.enter_continuous_time_mode(), fmi3OK, "{}", fmu.log());
    fmu
}

#[test]
fn fmi3_directional_and_adjoint_derivatives_are_one_jacobian_and_equal_differences() {
    let fmu = me3();
    let (_, mut x) = fmu.continuous_states(NX);
    x[14] = 900.0;
    x[15] = 40.0;
    assert_eq!(fmu.set_continuous_states(&x), fmi3OK);
    // Columns by forward calls, rows by adjoint calls: one matrix, to the last bit.
    let mut columns = Vec::new();
    for j in 0..N_KNOWNS3 {
        let mut seed = vec![0.0; N_KNOWNS3];
        seed[j] = 1.0;
        let (status, column) = fmu.derivative(false, &UNKNOWNS3, &KNOWNS3, &seed, N_UNKNOWNS3);
        assert_eq!(status, fmi3OK, "{}", fmu.log());
        columns.push(column);
    }
    for i in 0..N_UNKNOWNS3 {
        let mut seed = vec![0.0; N_UNKNOWNS3];
        seed[i] = 1.0;
        let (status, row) = fmu.derivative(true, &UNKNOWNS3, &KNOWNS3, &seed, N_KNOWNS3);
        assert_eq!(status, fmi3OK, "{}", fmu.log());
        for j in 0..N_KNOWNS3 {
            assert_eq!(row[j], columns[j][i], "J[{i}][{j}]");
        }
    }
    // AND with dense seeds v' (J w) = (v' J) w
    let w: Vec<f64> = (0..N_KNOWNS3).map(|j| 0.3 + 0.1 * j as f64).collect();
    let v: Vec<f64> = (0..N_UNKNOWNS3).map(|i| 1.0 - 0.05 * i as f64).collect();
    let (_, jw) = fmu.derivative(false, &UNKNOWNS3, &KNOWNS3, &w, N_UNKNOWNS3);
    let (_, vj) = fmu.derivative(true, &UNKNOWNS3, &KNOWNS3, &v, N_KNOWNS3);
    let left: f64 = v.iter().zip(&jw).map(|(a, b)| a * b).sum();
    let right: f64 = vj.iter().zip(&w).map(|(a, b)| a * b).sum();
    assert!(
        (left - right).abs() <= 1e-12 * left.abs(),
        "{left} vs {right}"
    );
    // AND the columns equal central differences of the derivatives and outputs (states).
    let values = |x: &[f64]| -> Vec<f64> {
        assert_eq!(fmu.set_continuous_states(x), fmi3OK);
        let (_, mut all) = fmu.derivatives(NX);
        let (status, outputs) = fmu.get_float64(&UNKNOWNS3[6..], N_UNKNOWNS3 - NX);
        assert_eq!(status, fmi3OK);
        all.extend(outputs);
        all
    };
    let mut numeric = Vec::new();
    let mut steps = Vec::new();
    for j in 0..NX {
        let h = 1e-6 * x[j].abs().max(1.0);
        let mut xp = x.clone();
        xp[j] += h;
        let plus = values(&xp);
        xp[j] -= 2.0 * h;
        let minus = values(&xp);
        numeric.push(
            plus.iter()
                .zip(&minus)
                .map(|(p, m)| (p - m) / (2.0 * h))
                .collect(),
        );
        steps.push(h);
    }
    let error = largest_error(&columns[..NX], &numeric, &steps);
    println!("FMI 3.0 Model Exchange: largest error against central differences {error:.1e}");
    assert!(error <= 1e-6, "{error:e}");
}

#[test]
fn co_simulation_outputs_by_inputs_through_both_versions() {
    // GIVEN Co-Simulation instances after a step, 1300 N commanded (inside the throttle
    // range, no lag): thrust_actual follows the command one to one, the specific force by
    // the thrust direction over the mass.
    let cs2 = common::Plant::new();
    cs2.init();
    cs2.set("thrust_cmd", 1300.0);
    assert_eq!(cs2.step(0.0, 0.01), fmi2OK);
    let mass = cs2.get("mass");
    let unknowns2 = [
        vr("thrust_actual"),
        vr("specific_force_body[2]"),
        vr("r_nue[2]"),
    ];
    let (status, d) = cs2.directional_derivative(&unknowns2, &[vr("thrust_cmd")], &[1.0]);
    assert_eq!(status, fmi2OK, "{:?}", cs2.messages());
    assert_eq!(d[0], 1.0);
    assert!((d[1] - 1.0 / mass).abs() < 1e-15, "{d:?}");
    assert_eq!(
        d[2], 0.0,
        "a state is no function of the inputs at a communication point"
    );
    let cs3 = Plant3::co_simulation(false);
    cs3.init();
    assert_eq!(cs3.set("thrust_cmd", &[1300.0]), fmi3OK);
    let step = cs3.do_step(0.0, 0.01);
    assert_eq!(step.status, fmi3OK);
    let (status, d3) = cs3.derivative(false, &[25, 70], &[1], &[1.0], 4);
    assert_eq!(status, fmi3OK, "{}", cs3.log());
    assert_eq!(d3[0], 1.0);
    assert!((d3[2] - 1.0 / mass).abs() < 1e-15, "{d3:?}");
    // AND a state is no known in Co-Simulation, in either version
    let (status, _) = cs2.directional_derivative(&unknowns2, &[vr("mass")], &[1.0]);
    assert_eq!(status, fmi2Error);
    assert!(cs2
        .last_message()
        .contains("continuous states under Model Exchange only"));
    let (status, _) = cs3.derivative(false, &[25], &[23], &[1.0], 1);
    assert_eq!(status, fmi3Error);
    assert!(cs3
        .log()
        .contains("known mass (vr 23) is a continuous state"));
}

#[test]
fn bad_arguments_are_refused_with_a_log_line_and_the_instance_stays_usable() {
    // FMI 2.0, Model Exchange
    let me = Me2::started();
    let fmu = &me.solver.instance;
    let thrust = vr("der_thrust_lag_state");
    let cases: [(&[u32], &[u32], &str); 4] = [
        (
            &[99_999],
            &[vr("thrust_cmd")],
            "unknown vr 99999: no Real variable has it",
        ),
        (
            &[thrust],
            &[vr("m0")],
            "known m0 (vr 113) is a fixed Real parameter",
        ),
        (
            &[vr("m0")],
            &[vr("thrust_cmd")],
            "unknown m0 (vr 113) is a fixed Real parameter",
        ),
        (
            &[thrust],
            &[vr("touchdown_time")],
            "known touchdown_time (vr 35) is a discrete Real output",
        ),
    ];
    for (unknowns, knowns, says) in cases {
        let (status, _) = fmu.directional_derivative(unknowns, knowns, &[1.0]);
        assert_eq!(status, fmi2Error, "{says}");
        assert!(fmu.last_message().contains(says), "{}", fmu.last_message());
    }
    // NULL arrays with a count
    let status = unsafe {
        (fmu.functions().get_directional_derivative)(
            fmu.component(),
            [thrust].as_ptr(),
            1,
            [vr("thrust_cmd")].as_ptr(),
            1,
            std::ptr::null(),
            [0.0].as_mut_ptr(),
        )
    };
    assert_eq!(status, fmi2Error);
    assert!(fmu.last_message().contains("argument dvKnown is NULL"));
    // AND the instance answers a good call
    let (status, d) = fmu.directional_derivative(&[thrust], &[vr("thrust_cmd")], &[1.0]);
    assert_eq!(status, fmi2OK, "{:?}", fmu.messages());
    assert_eq!(d, [1.0 / 0.2]);
    // AND before initialization the call is illegal (FMI 2.0: not in Instantiated)
    let fresh = common::Plant::new();
    let (status, _) = fresh.directional_derivative(&[thrust], &[vr("thrust_cmd")], &[1.0]);
    assert_eq!(status, fmi2Error);
    assert!(fresh
        .last_message()
        .contains("illegal call in state Instantiated"));

    // AND a configuration Model Exchange does not model (the gear) is refused naming it,
    // leaving the instance in its state: initialization still ends
    let guid = fmi2_export::guid::<fmu_plant::LanderPlant>();
    let geared = MeSolver::instantiate(
        &common::FUNCTIONS,
        fmi2_me_functions!(fmu_plant),
        &guid,
        NX,
        2,
    );
    assert_eq!(
        geared.instance.set_boolean(vr("gear_enabled"), true),
        fmi2OK
    );
    let (status, _) = geared.instance.directional_derivative(
        &[vr("der_mass")],
        &[vr("thrust_lag_state")],
        &[1.0],
    );
    assert_eq!(status, fmi2Error);
    let message = geared.instance.last_message();
    assert!(
        message.contains("parameter gear_enabled = true"),
        "{message}"
    );
    assert_eq!(geared.instance.exit_initialization_mode(), fmi2OK);

    // FMI 3.0, Model Exchange: wrong lengths, NULL, wrong state
    let fmu3 = me3();
    let refused = |unknowns: &[u32], knowns: &[u32], seed: &[f64], n: usize, says: &str| {
        let (status, _) = fmu3.derivative(false, unknowns, knowns, seed, n);
        assert_eq!(status, fmi3Error, "{says}");
        assert!(
            fmu3.last_message().contains(says),
            "{}",
            fmu3.last_message()
        );
    };
    refused(
        &[234],
        &[2],
        &[1.0],
        1,
        "nSeed = 1, but the knowns have 3 elements",
    );
    refused(
        &[226],
        &[1],
        &[1.0],
        1,
        "nSensitivity = 1, but the unknowns have 4 elements",
    );
    refused(
        &[234],
        &[113],
        &[1.0],
        1,
        "known m0 (vr 113) is a fixed Real parameter",
    );
    refused(
        &[234],
        &[12_345],
        &[1.0],
        1,
        "known vr 12345: no variable has it",
    );
    let status = unsafe {
        (fmu3.functions().derivatives.adjoint)(
            fmu3.instance(),
            [234].as_ptr(),
            1,
            [1].as_ptr(),
            1,
            [1.0].as_ptr(),
            1,
            std::ptr::null_mut(),
            1,
        )
    };
    assert_eq!(status, fmi3Error);
    assert!(fmu3.last_message().contains("argument sensitivity is NULL"));
    let (status, d) = fmu3.derivative(true, &[234], &[1], &[2.0], 1);
    assert_eq!(status, fmi3OK, "{}", fmu3.log());
    assert_eq!(d, [2.0 / 0.2]);
    let fresh3 = Plant3::model_exchange();
    let (status, _) = fresh3.derivative(false, &[234], &[1], &[1.0], 1);
    assert_eq!(status, fmi3Error);
    assert!(fresh3
        .last_message()
        .contains("illegal call in state Instantiated"));
}
