//! LanderPlant's exact directional derivatives against differences of the equations the
//! trajectories run on: at seeded random admissible states and commands, in every
//! configuration Model Exchange admits (flat and spherical Moon, lags, a rate limit, mass
//! properties, a misaligned thrust line, RCS propellant, the thruster model), the Jacobian
//! of the state derivatives and outputs with respect to the states and inputs equals
//! central differences of `derivatives()` and of the outputs, and Richardson-extrapolated
//! central differences closer still; its nonzeros lie inside the dependencies the model
//! description declares. On the landing gear (Co-Simulation), the outputs' derivatives with
//! respect to the inputs agree the same way.
use fmi_model::{ContinuousModel, Kind, Log, Model, ScalarRef};
use fmu_plant::LanderPlant;
use std::collections::{BTreeMap, BTreeSet};

fn index(name: &str) -> usize {
    LanderPlant::declarations()
        .iter()
        .position(|d| d.name == name)
        .unwrap_or_else(|| panic!("{name} is not declared"))
}

fn set(m: &mut LanderPlant, name: &str, element: usize, value: f64) {
    match LanderPlant::declarations()[index(name)].kind {
        Kind::Real { set: Some(set), .. } => set(m, element, value),
        Kind::Enumeration { set: Some(set), .. } | Kind::Integer { set: Some(set), .. } => {
            set(m, value as i32)
        }
        Kind::Boolean { set: Some(set), .. } => set(m, value != 0.0),
        _ => panic!("{name} cannot be set"),
    }
}

fn get(m: &LanderPlant, r: ScalarRef) -> f64 {
    match LanderPlant::declarations()[r.declaration].kind {
        Kind::Real { get, .. } => get(m, r.element),
        _ => panic!("not a Real"),
    }
}

/// Every element of the named declarations.
fn elements(names: &[&str]) -> Vec<ScalarRef> {
    names
        .iter()
        .flat_map(|n| {
            let i = index(n);
            (0..LanderPlant::declarations()[i].shape().len()).map(move |e| ScalarRef::new(i, e))
        })
        .collect()
}

fn label(r: ScalarRef) -> String {
    let d = &LanderPlant::declarations()[r.declaration];
    format!("{}[{}]", d.name, r.element + 1)
}

const STATES: [&str; 6] = [
    "translation_state",
    "attitude_state",
    "omega_body",
    "mass",
    "thrust_lag_state",
    "torque_lag_state_body",
];
const INPUTS: [&str; 3] = ["thrust_cmd", "torque_cmd_body", "rcs_duty"];
const DERIVATIVES: [&str; 6] = [
    "der_translation_state",
    "der_attitude_state",
    "der_omega_body",
    "der_mass",
    "der_thrust_lag_state",
    "der_torque_lag_state_body",
];
const OUTPUTS: [&str; 14] = [
    "r_nue",
    "v_nue",
    "q_body_to_nue",
    "omega_body",
    "mass",
    "altitude",
    "thrust_actual",
    "torque_actual_body",
    "rcs_force_body",
    "specific_force_body",
    "omega_mean_body",
    "engine_torque_body",
    "propellant_used",
    "leg_stroke",
];

/// A seeded xorshift: the same points on every run.
struct Random(u64);

impl Random {
    fn uniform(&mut self, low: f64, high: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        low + (high - low) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// A configuration: parameters by name.
type Configuration = &'static [(&'static str, usize, f64)];

const CONFIGURATIONS: [(&str, Configuration); 4] = [
    ("default (flat, no lags, torque RCS)", &[]),
    (
        "flat, engine and RCS lags, throttle rate limit, RCS propellant",
        &[
            ("engine_time_constant", 0, 0.2),
            ("rcs_time_constant", 0, 0.1),
            ("throttle_rate_limit", 0, 3000.0),
            ("rcs_isp", 0, 220.0),
        ],
    ),
    (
        "spherical Moon, mass properties, misaligned offset thrust line",
        &[
            ("translation_model", 0, 2.0),
            ("inertia_dry_body", 0, 300.0),
            ("inertia_dry_body", 1, 220.0),
            ("inertia_dry_body", 2, 340.0),
            ("com_offset_dry_body", 0, 0.02),
            ("com_offset_dry_body", 1, 0.1),
            ("com_offset_dry_body", 2, -0.03),
            ("thrust_misalignment", 0, 0.01),
            ("thrust_misalignment_azimuth", 0, 0.7),
            ("thrust_point_body", 0, 0.03),
            ("thrust_point_body", 2, -0.02),
            ("rcs_isp", 0, 220.0),
        ],
    ),
    (
        "spherical Moon, thruster RCS, engine lag, misaligned thrust",
        &[
            ("translation_model", 0, 2.0),
            ("rcs_model", 0, 2.0),
            ("engine_time_constant", 0, 0.3),
            ("thrust_misalignment", 0, 0.02),
            ("thrust_misalignment_azimuth", 0, -0.4),
            ("thrust_point_body", 2, 0.04),
        ],
    ),
];

/// A running Model Exchange-able plant in `configuration` at a random admissible state and
/// random commands, away from the kinks (saturation edges, the dry mass).
fn sample(configuration: Configuration, random: &mut Random) -> LanderPlant {
    let mut m = LanderPlant::default();
    for &(name, element, value) in configuration {
        set(&mut m, name, element, value);
    }
    m.exit_initialization(0.0, &mut Log::default()).unwrap();
    let mut x = [0.0; 18];
    m.states(&mut x);
    let spherical = configuration.iter().any(|c| c.0 == "translation_model");
    if spherical {
        x[0] += random.uniform(100.0, 3000.0);
        x[1] += random.uniform(-1e-3, 1e-3);
        x[2] += random.uniform(-1e-3, 1e-3);
    } else {
        x[0] = random.uniform(-2000.0, 2000.0);
        x[1] = random.uniform(50.0, 3000.0);
        x[2] = random.uniform(-2000.0, 2000.0);
    }
    for v in &mut x[3..6] {
        *v = random.uniform(-60.0, 60.0);
    }
    // A quaternion off the unit sphere by up to 2 %: the norm term is exercised too.
    let q: [f64; 4] = std::array::from_fn(|_| random.uniform(-1.0, 1.0));
    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt() / random.uniform(0.98, 1.02);
    for (slot, v) in x[6..10].iter_mut().zip(q) {
        *slot = v / norm;
    }
    for v in &mut x[10..13] {
        *v = random.uniform(-0.5, 0.5);
    }
    x[13] = random.uniform(620.0, 990.0);
    x[14] = random.uniform(0.0, 1800.0);
    for v in &mut x[15..18] {
        *v = random.uniform(-100.0, 100.0);
    }
    m.set_states(&x).unwrap();
    // Thrust inside the throttle range (720..1600 N), or saturated high, or off.
    let thrust = match (random.uniform(0.0, 3.0)) as u32 {
        0 => random.uniform(740.0, 1580.0),
        1 => random.uniform(1700.0, 2500.0),
        _ => random.uniform(-100.0, 0.5),
    };
    set(&mut m, "thrust_cmd", 0, thrust);
    for axis in 0..3 {
        let torque = if random.uniform(0.0, 1.0) < 0.7 {
            random.uniform(-110.0, 110.0)
        } else {
            random.uniform(125.0, 300.0) * if axis == 1 { -1.0 } else { 1.0 }
        };
        set(&mut m, "torque_cmd_body", axis, torque);
    }
    for k in 0..8 {
        set(&mut m, "rcs_duty", k, random.uniform(0.1, 0.9));
    }
    m
}

/// The values of `unknowns` at the model's current state and commands.
fn values(m: &mut LanderPlant, unknowns: &[ScalarRef]) -> Vec<f64> {
    let mut dx = [0.0; 18];
    let derivatives = elements(&DERIVATIVES);
    if unknowns.iter().any(|u| derivatives.contains(u)) {
        m.derivatives(&mut dx).unwrap();
    }
    m.calculate_values(&mut Log::default());
    let derivative_of = |r: ScalarRef| {
        let d = LanderPlant::declarations()[r.declaration].name;
        DERIVATIVES.iter().position(|n| *n == d).map(|k| {
            let start = [0, 6, 10, 13, 14, 15][k];
            dx[start + r.element]
        })
    };
    unknowns
        .iter()
        .map(|&r| derivative_of(r).unwrap_or_else(|| get(m, r)))
        .collect()
}

/// Where a known sits and its typical size (the difference step is 1e-6 of it).
fn perturbed(m: &LanderPlant, known: ScalarRef, delta: f64) -> LanderPlant {
    let mut copy = m.clone();
    let name = LanderPlant::declarations()[known.declaration].name;
    if let Some(k) = STATES.iter().position(|s| *s == name) {
        let mut x = [0.0; 18];
        copy.states(&mut x);
        x[[0, 6, 10, 13, 14, 15][k] + known.element] += delta;
        copy.set_states(&x).unwrap();
    } else {
        let value = get(&copy, known);
        set(&mut copy, name, known.element, value + delta);
    }
    copy
}

fn step_of(m: &LanderPlant, known: ScalarRef) -> f64 {
    let mut x = [0.0; 18];
    m.states(&mut x);
    let name = LanderPlant::declarations()[known.declaration].name;
    let size = match STATES.iter().position(|s| *s == name) {
        Some(k) => x[[0, 6, 10, 13, 14, 15][k] + known.element].abs().max(1.0),
        None => get(m, known).abs().max(1.0),
    };
    1e-6 * size
}

/// Central difference of the unknowns along `known` with step `h`.
fn central(m: &LanderPlant, unknowns: &[ScalarRef], known: ScalarRef, h: f64) -> Vec<f64> {
    let plus = values(&mut perturbed(m, known, h), unknowns);
    let minus = values(&mut perturbed(m, known, -h), unknowns);
    plus.iter()
        .zip(&minus)
        .map(|(p, q)| (p - q) / (2.0 * h))
        .collect()
}

/// The exact Jacobian, column by column through the model's directional derivative.
fn exact(m: &mut LanderPlant, unknowns: &[ScalarRef], knowns: &[ScalarRef]) -> Vec<Vec<f64>> {
    knowns
        .iter()
        .map(|&k| {
            let mut column = vec![0.0; unknowns.len()];
            m.directional_derivative(unknowns, &[k], &[1.0], &mut column)
                .unwrap_or_else(|e| panic!("d/d{}: {e}", label(k)));
            column
        })
        .collect()
}

/// Largest errors seen, relative to the entry or, for small entries, to the row's largest
/// contribution of any known (`|J_ij| h_j` against `max_j |J_ij| h_j`).
#[derive(Debug, Default)]
struct Agreement {
    central: f64,
    richardson: f64,
}

fn compare(
    m: &mut LanderPlant,
    unknowns: &[ScalarRef],
    knowns: &[ScalarRef],
    what: &str,
    agreement: &mut Agreement,
) {
    let jacobian = exact(m, unknowns, knowns);
    let steps: Vec<f64> = knowns.iter().map(|&k| step_of(m, k)).collect();
    let row_scale: Vec<f64> = (0..unknowns.len())
        .map(|i| {
            (0..knowns.len())
                .map(|j| (jacobian[j][i] * steps[j]).abs())
                .fold(0.0, f64::max)
        })
        .collect();
    for (j, &known) in knowns.iter().enumerate() {
        let h = steps[j];
        let d1 = central(m, unknowns, known, h);
        // Richardson's extrapolation cancels the h^2 term: with steps 1000 times larger its
        // truncation (h^4) and round-off (1/h) errors are both far below central's.
        let coarse = central(m, unknowns, known, 1e3 * h);
        let fine = central(m, unknowns, known, 0.5e3 * h);
        for (i, &unknown) in unknowns.iter().enumerate() {
            let exact = jacobian[j][i];
            let richardson = (4.0 * fine[i] - coarse[i]) / 3.0;
            // The error as a fraction of max(|J_ij|, 1e-3 of the row's largest per unit).
            let floor = 1e-3 * row_scale[i] / h;
            let reference = exact.abs().max(floor).max(f64::MIN_POSITIVE);
            let e_central = (d1[i] - exact).abs() / reference;
            let e_richardson = (richardson - exact).abs() / reference;
            assert!(
                e_central <= 1e-6,
                "{what}: d {} / d {}: exact {exact:e}, central {:e} (error {e_central:e})",
                label(unknown),
                label(known),
                d1[i]
            );
            assert!(
                e_richardson <= 1e-8,
                "{what}: d {} / d {}: exact {exact:e}, Richardson {richardson:e} (error \
                 {e_richardson:e})",
                label(unknown),
                label(known)
            );
            agreement.central = agreement.central.max(e_central);
            agreement.richardson = agreement.richardson.max(e_richardson);
        }
    }
}

#[test]
fn the_model_exchange_jacobian_equals_central_and_richardson_differences() {
    let mut random = Random(0x5eed_1a2d_e2f0_0d01);
    let unknowns: Vec<ScalarRef> = elements(&DERIVATIVES)
        .into_iter()
        .chain(elements(&OUTPUTS))
        .collect();
    let knowns: Vec<ScalarRef> = elements(&STATES)
        .into_iter()
        .chain(elements(&INPUTS))
        .collect();
    for (what, configuration) in CONFIGURATIONS {
        let mut agreement = Agreement::default();
        for _ in 0..12 {
            let mut m = sample(configuration, &mut random);
            compare(&mut m, &unknowns, &knowns, what, &mut agreement);
        }
        println!(
            "{what}: largest error central {:.1e}, Richardson {:.1e}",
            agreement.central, agreement.richardson
        );
    }
}

#[test]
fn on_the_landing_gear_the_outputs_derivatives_by_the_inputs_equal_central_differences() {
    // GIVEN a Co-Simulation plant standing on its gear (footpads pressed into the terrain)
    let mut random = Random(0x0ea7_ed00_0000_0001);
    let unknowns = elements(&[
        "thrust_actual",
        "torque_actual_body",
        "specific_force_body",
        "engine_torque_body",
        "leg_stroke",
    ]);
    let knowns = elements(&INPUTS);
    let mut agreement = Agreement::default();
    for _ in 0..8 {
        let mut m = LanderPlant::default();
        set(&mut m, "gear_enabled", 0, 1.0);
        set(&mut m, "r0_nue", 1, random.uniform(0.95, 0.99));
        set(&mut m, "v0_nue", 1, random.uniform(-1.0, 0.0));
        m.exit_initialization(0.0, &mut Log::default()).unwrap();
        m.do_step(0.0, 0.01, &mut Log::default()).unwrap();
        let thrust = random.uniform(740.0, 1580.0);
        set(&mut m, "thrust_cmd", 0, thrust);
        set(&mut m, "torque_cmd_body", 0, random.uniform(-100.0, 100.0));
        m.calculate_values(&mut Log::default());
        assert!(
            get(&m, ScalarRef::new(index("leg_stroke"), 0)) > 0.0,
            "on the gear"
        );
        // WHEN the Jacobian is computed THEN it equals differences of the outputs
        compare(&mut m, &unknowns, &knowns, "on the gear", &mut agreement);
    }
    println!(
        "on the gear: largest error central {:.1e}, Richardson {:.1e}",
        agreement.central, agreement.richardson
    );
}

/// The nonzeros the declared dependencies allow: unknown -> knowns, by scalar name, from the
/// FMI 2.0 description (outputs and derivatives).
fn declared() -> BTreeMap<String, BTreeSet<String>> {
    let md = fmi2_export::model_description_me::<LanderPlant>();
    let names: Vec<String> = md
        .model_variables
        .variables
        .iter()
        .map(|v| v.name.clone())
        .collect();
    let structure = md.model_structure;
    structure
        .outputs
        .into_iter()
        .chain(structure.derivatives)
        .flat_map(|list| list.unknowns)
        .map(|u| {
            let deps = u
                .dependencies
                .expect("every unknown lists its dependencies")
                .split_whitespace()
                .map(|i| names[i.parse::<usize>().unwrap() - 1].clone())
                .collect();
            (names[u.index as usize - 1].clone(), deps)
        })
        .collect()
}

/// The FMI 2.0 name of a scalar: `r_nue[2]`, `mass`.
fn scalar_name(r: ScalarRef) -> String {
    let d = &LanderPlant::declarations()[r.declaration];
    if d.shape().len() > 1 {
        format!("{}[{}]", d.name, r.element + 1)
    } else {
        d.name.to_string()
    }
}

#[test]
fn no_nonzero_lies_outside_the_declared_dependencies() {
    let declared = declared();
    let mut random = Random(0x5a25_e000_0000_0003);
    let unknowns: Vec<ScalarRef> = elements(&DERIVATIVES)
        .into_iter()
        .chain(elements(&OUTPUTS))
        .collect();
    let knowns: Vec<ScalarRef> = elements(&STATES)
        .into_iter()
        .chain(elements(&INPUTS))
        .collect();
    let mut nonzeros = 0;
    for (_, configuration) in CONFIGURATIONS {
        for _ in 0..6 {
            let mut m = sample(configuration, &mut random);
            let jacobian = exact(&mut m, &unknowns, &knowns);
            for (j, &known) in knowns.iter().enumerate() {
                for (i, &unknown) in unknowns.iter().enumerate() {
                    if jacobian[j][i] != 0.0 {
                        nonzeros += 1;
                        let allowed = &declared[&scalar_name(unknown)];
                        assert!(
                            allowed.contains(&scalar_name(known)),
                            "d {} / d {} = {:e}, but the description declares {allowed:?}",
                            scalar_name(unknown),
                            scalar_name(known),
                            jacobian[j][i]
                        );
                    }
                }
            }
        }
    }
    assert!(nonzeros > 1000, "{nonzeros} nonzeros: too few to tell");
}

#[test]
fn the_equations_on_dual_numbers_are_the_trajectorys_equations() {
    // The second copy of the equations (physics::sensitivity) evaluated on f64 equals the
    // state derivative and outputs of the path the trajectories run on.
    let mut random = Random(0x0005_a3e0_0000_0004);
    let unknowns: Vec<ScalarRef> = elements(&DERIVATIVES)
        .into_iter()
        .chain(elements(&OUTPUTS))
        .collect();
    for (what, configuration) in CONFIGURATIONS {
        for _ in 0..10 {
            let mut m = sample(configuration, &mut random);
            let production = values(&mut m, &unknowns);
            let mirrored = m.values_on_dual_numbers(&unknowns);
            let compared = production.iter().zip(&mirrored).zip(&unknowns);
            for ((p, q), &r) in compared.filter_map(|((p, q), r)| Some(((p, (*q)?), r))) {
                // Round-off of sums whose terms are far larger than the result: positions
                // on the spherical Moon come from Moon-fixed vectors of 1.7e6 m.
                let scale = if label(r).starts_with("r_nue") || label(r).starts_with("altitude") {
                    1e7
                } else {
                    100.0
                };
                assert!(
                    (p - q).abs() <= 1e-13 * p.abs() + 1e-15 * scale,
                    "{what}: {} = {p:e} on the trajectory's path, {q:e} on dual numbers",
                    label(r)
                );
            }
        }
    }
}

#[test]
fn every_declared_dependency_on_a_state_or_a_continuous_command_is_a_nonzero_somewhere() {
    // The other direction: what the description declares is no loose superset. Each pair of
    // an unknown and a state (or thrust or torque command) it declares is nonzero at one of
    // the random states of the four configurations. (rcs_duty switches thrusters on or off:
    // the outputs it is declared for change in steps, never with a slope.)
    let declared = declared();
    let mut random = Random(0x0e4a_c700_0000_0005);
    let unknowns: Vec<ScalarRef> = elements(&DERIVATIVES)
        .into_iter()
        .chain(elements(&OUTPUTS))
        .collect();
    let knowns: Vec<ScalarRef> = elements(&STATES)
        .into_iter()
        .chain(elements(&INPUTS[..2]))
        .collect();
    let mut seen: BTreeSet<(String, String)> = BTreeSet::new();
    for (_, configuration) in CONFIGURATIONS {
        for _ in 0..12 {
            let mut m = sample(configuration, &mut random);
            let jacobian = exact(&mut m, &unknowns, &knowns);
            for (j, &known) in knowns.iter().enumerate() {
                for (i, &unknown) in unknowns.iter().enumerate() {
                    if jacobian[j][i] != 0.0 {
                        seen.insert((scalar_name(unknown), scalar_name(known)));
                    }
                }
            }
        }
    }
    let known_names: BTreeSet<String> = knowns.iter().map(|&k| scalar_name(k)).collect();
    let mut never = Vec::new();
    for &unknown in &unknowns {
        let name = scalar_name(unknown);
        for known in &declared[&name] {
            if known_names.contains(known) && !seen.contains(&(name.clone(), known.clone())) {
                never.push(format!("{name} <- {known}"));
            }
        }
    }
    assert!(never.is_empty(), "declared but never nonzero: {never:?}");
}
