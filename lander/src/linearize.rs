//! `harness linearize`: a scenario flown to a time, the system linearized there
//! (`cosim::linear`), the closed loop's eigenvalues, and per attitude axis the margins of the
//! loop broken at the torque command, beside the margins the controller's design values give
//! the rigid body (`L(s) = (Kd s + Kp) / (I s^2)`, sampled and held as the loop is). See
//! docs/linearize.md.
use cosim::linear::lti::{self, Margins, SampledLoop};
use cosim::linear::{Source, SystemModel};
use cosim::master::{Jacobians, Simulation};
use cosim::system::{Ordering, ParamValue, SystemDescription};
use nalgebra::{Complex, DMatrix, DVector};
use std::path::Path;

/// The attitude axes, body x, y, z, as the torque command's elements name them.
pub const AXES: [&str; 3] = [
    "body x (yaw)",
    "body y (roll, thrust axis)",
    "body z (pitch)",
];

/// What the command was asked.
#[derive(Debug, Clone)]
pub struct Request<'a> {
    pub scenario: &'a str,
    pub at_s: f64,
    pub sets: &'a [String],
    pub jacobians: Jacobians,
}

/// The margins of one attitude axis: the system's and the design's.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Axis {
    pub axis: &'static str,
    /// The input the loop is broken at.
    pub broken_at: String,
    pub margins: Margins,
    /// The rigid-body loop of the controller's gains on the plant's inertia, sampled as the
    /// system is; `None` when the system has no such parameters.
    pub design: Option<Margins>,
}

/// One eigenvalue of the closed loop over a communication step, and the continuous one it
/// samples.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct Eigenvalue {
    pub z_re: f64,
    pub z_im: f64,
    pub s_re: f64,
    pub s_im: f64,
}

/// One scenario event and whether the run to the point applied it.
#[derive(Debug, Clone, serde::Serialize)]
pub struct EventAt {
    pub name: String,
    /// `instance.variable = value`.
    pub set: String,
    pub time_s: f64,
    /// The communication point it was applied at; `None`: due after the held point.
    pub applied_at_s: Option<f64>,
}

/// The result of the command.
#[derive(Debug, Clone)]
pub struct Linearized {
    pub scenario: String,
    pub model: SystemModel,
    /// The scenario's events, in its order.
    pub events: Vec<EventAt>,
    pub closed_loop: DMatrix<f64>,
    pub eigenvalues: Vec<Eigenvalue>,
    pub axes: Vec<Axis>,
}

/// Flies the scenario to `request.at_s` and linearizes it there. Instances whose FMU offers
/// Model Exchange run through it (the linear model needs their continuous states); every
/// error names what is wrong (an unknown scenario, a time outside the run, a `--set`).
pub fn linearize(request: &Request, fmu_dir: &Path) -> anyhow::Result<Linearized> {
    let (mut system, _) = crate::scenarios::spec::load(request.scenario)?;
    let (problems, _) = crate::overrides::apply_sets(&mut system, request.sets, &[]);
    if !problems.is_empty() {
        anyhow::bail!("{}", problems.join("\n"));
    }
    let at = request.at_s;
    if !at.is_finite() || at < system.start_time || at > system.stop_time {
        anyhow::bail!(
            "--at {at}: outside the run of scenario '{}' ({} s to {} s)",
            system.name,
            system.start_time,
            system.stop_time
        );
    }
    prefer_model_exchange(&mut system, fmu_dir)?;
    let design = Design::of(&system, fmu_dir);
    // Each event's point, on the master's grid (cosim/src/system/event.rs).
    let mut events: Vec<EventAt> = system
        .events
        .iter()
        .map(|e| EventAt {
            name: e.name.clone(),
            set: e.describe(),
            time_s: e.time_s,
            applied_at_s: cosim::system::event::application_time(&system, e.time_s),
        })
        .collect();
    let half_step = 0.5 * system.step_size;
    let mut simulation = Simulation::new(system, fmu_dir)?;
    let mut nothing = Discard;
    let Some(held) = simulation.run_to(at, &mut nothing)? else {
        anyhow::bail!(
            "--at {at}: the run of scenario '{}' ended before it (an instance stopped it)",
            request.scenario
        );
    };
    let model = simulation.linearize(request.jacobians)?;
    let closed_loop = model.closed_loop().map_err(anyhow::Error::msg)?;
    let eigenvalues = lti::eigenvalues(&closed_loop)
        .into_iter()
        .map(|z| {
            let s = lti::continuous_eigenvalue(z, model.period_s);
            Eigenvalue {
                z_re: z.re,
                z_im: z.im,
                s_re: s.re,
                s_im: s.im,
            }
        })
        .collect();
    let mut axes = Vec::new();
    for (i, axis) in AXES.iter().enumerate() {
        let Some(input) = torque_input(&model, i) else {
            continue;
        };
        let broken = model.broken_at(&input).map_err(anyhow::Error::msg)?;
        axes.push(Axis {
            axis,
            broken_at: input,
            margins: broken.margins(OMEGA_MIN_RADPS),
            design: design.as_ref().map(|d| {
                d.sampled(i, model.period_s, model.ordering)
                    .margins(OMEGA_MIN_RADPS)
            }),
        });
    }
    // The run held after the events due at its point (cosim/src/master/events.rs).
    for event in &mut events {
        event.applied_at_s = event.applied_at_s.filter(|&t_k| t_k <= held + half_step);
    }
    Ok(Linearized {
        scenario: request.scenario.to_owned(),
        model,
        events,
        closed_loop,
        eigenvalues,
        axes,
    })
}

/// The lowest frequency the margins are looked for at, rad/s: well below any attitude
/// loop's crossover, above the slow modes (mass, position under held guidance).
const OMEGA_MIN_RADPS: f64 = 1e-2;

/// A recorder that keeps nothing: the command needs the point, not the way there.
struct Discard;

impl cosim::master::Recorder for Discard {
    fn record(&mut self, _time: f64, _values: &[f64]) {}
}

/// The connected input `…torque_cmd_body[i+1]` of a Model Exchange instance (the plant).
fn torque_input(model: &SystemModel, i: usize) -> Option<String> {
    let suffix = format!(".torque_cmd_body[{}]", i + 1);
    model
        .units
        .iter()
        .filter(|u| u.model_exchange)
        .flat_map(|u| &u.inputs)
        .find(|name| name.ends_with(&suffix))
        .cloned()
}

/// Every instance whose FMU offers Model Exchange and whose interface the scenario leaves
/// open runs through it.
fn prefer_model_exchange(system: &mut SystemDescription, fmu_dir: &Path) -> anyhow::Result<()> {
    for desc in &mut system.instances {
        if desc.interface_named || desc.model_exchange.is_some() {
            continue;
        }
        let path = cosim::master::fmu_path(fmu_dir, &desc.fmu);
        let (_, description) = fmi_import::peek_description(&path)
            .map_err(|e| anyhow::anyhow!("instance '{}': {e}", desc.name))?;
        if description.model_exchange.is_some() {
            desc.model_exchange = Some(Default::default());
        }
    }
    Ok(())
}

/// The controller's design: its PD gains (from `control_bandwidth`, `control_damping` and
/// `inertia_body` of the instance `gnc`) acting on a rigid body of the plant's inertia
/// (`inertia_body` of the instance `plant`, else the controller's).
#[derive(Debug, Clone)]
struct Design {
    kp: [f64; 3],
    kd: [f64; 3],
    inertia: [f64; 3],
}

impl Design {
    fn of(system: &SystemDescription, fmu_dir: &Path) -> Option<Self> {
        let value = |instance: &str, name: &str| parameter(system, fmu_dir, instance, name);
        let bandwidth = value("gnc", "control_bandwidth")?;
        let damping = value("gnc", "control_damping")?;
        let omega = std::f64::consts::TAU * bandwidth;
        let mut design = Design {
            kp: [0.0; 3],
            kd: [0.0; 3],
            inertia: [0.0; 3],
        };
        for i in 0..3 {
            let element = format!("inertia_body[{}]", i + 1);
            let gains_for = value("gnc", &element)?;
            design.kp[i] = gains_for * omega * omega;
            design.kd[i] = 2.0 * damping * omega * gains_for;
            design.inertia[i] = value("plant", &element).unwrap_or(gains_for);
        }
        Some(design)
    }

    /// Axis `i`: angle and rate of `I theta'' = tau`, the torque held over the period (one
    /// period late in a Jacobi exchange), `tau = -(Kp theta + Kd omega)` at each sample.
    fn sampled(&self, i: usize, period_s: f64, ordering: Ordering) -> SampledLoop {
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
        let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0 / self.inertia[i]]);
        let (phi, gamma) = lti::zero_order_hold(&a, &b, period_s);
        let gains = DVector::from_vec(vec![-self.kp[i], -self.kd[i]]);
        match ordering {
            Ordering::GaussSeidel => SampledLoop {
                a: phi,
                b: gamma.column(0).into_owned(),
                c: gains,
                d: 0.0,
                period_s,
            },
            Ordering::Jacobi => {
                // The command acts on the measurement of the step before: the state carries it.
                let mut a = DMatrix::zeros(4, 4);
                a.view_mut((0, 0), (2, 2)).copy_from(&phi);
                a[(2, 0)] = 1.0;
                a[(3, 1)] = 1.0;
                let mut b = DVector::zeros(4);
                b.rows_mut(0, 2).copy_from(&gamma.column(0));
                let mut c = DVector::zeros(4);
                c.rows_mut(2, 2).copy_from(&gains);
                SampledLoop {
                    a,
                    b,
                    c,
                    d: 0.0,
                    period_s,
                }
            }
        }
    }
}

/// A Real parameter of an instance: the scenario's value, else its FMU's start value.
fn parameter(
    system: &SystemDescription,
    fmu_dir: &Path,
    instance: &str,
    name: &str,
) -> Option<f64> {
    let desc = system.instance(instance)?;
    if let Some((_, value)) = desc.parameters.iter().find(|(n, _)| n == name) {
        return match value {
            ParamValue::Real(v) => Some(*v),
            ParamValue::Integer(v) => Some(*v as f64),
            _ => None,
        };
    }
    let path = cosim::master::fmu_path(fmu_dir, &desc.fmu);
    let (_, description) = fmi_import::peek_description(&path).ok()?;
    description
        .model_variables
        .variables
        .iter()
        .find(|v| v.name == name)?
        .real
        .as_ref()?
        .start
}

impl Linearized {
    /// Everything as JSON (docs/linearize.md lists the fields).
    pub fn to_json(&self) -> serde_json::Value {
        let matrix = |m: &DMatrix<f64>| -> serde_json::Value {
            (0..m.nrows())
                .map(|i| m.row(i).iter().copied().collect::<Vec<f64>>())
                .collect::<Vec<_>>()
                .into()
        };
        let model = &self.model;
        let instances: Vec<serde_json::Value> = model
            .units
            .iter()
            .map(|u| {
                serde_json::json!({
                    "instance": u.instance,
                    "interface": if u.model_exchange { "model-exchange" } else { "co-simulation" },
                    "source": u.source,
                    "states": u.states,
                    "inputs": u.inputs,
                    "outputs": u.outputs,
                    "A": matrix(&u.a),
                    "B": matrix(&u.b),
                    "C": matrix(&u.c),
                    "D": matrix(&u.d),
                })
            })
            .collect();
        let mut states = model.states();
        if model.ordering == Ordering::Jacobi {
            states.extend(
                model
                    .units
                    .iter()
                    .flat_map(|u| u.inputs.iter().map(|i| format!("{i} (step before)"))),
            );
        }
        serde_json::json!({
            "scenario": self.scenario,
            "time_s": model.time_s,
            "period_s": model.period_s,
            "ordering": match model.ordering {
                Ordering::GaussSeidel => "gauss-seidel",
                Ordering::Jacobi => "jacobi",
            },
            "events": self.events,
            "instances": instances,
            "closed_loop": {
                "states": states,
                "A": matrix(&self.closed_loop),
                "eigenvalues": self.eigenvalues,
            },
            "attitude_axes": self.axes,
        })
    }

    /// The human summary `harness linearize` prints.
    pub fn summary(&self) -> String {
        use std::fmt::Write;
        let model = &self.model;
        let mut text = String::new();
        let _ = writeln!(
            text,
            "{} linearized at t = {} s (communication step {} s, {:?})",
            self.scenario, model.time_s, model.period_s, model.ordering
        );
        for e in &self.events {
            let applied = match e.applied_at_s {
                Some(t_k) => format!("applied at {t_k} s"),
                None => "due after this point, not applied".to_owned(),
            };
            let _ = writeln!(
                text,
                "  event '{}' ({}) due at {} s: {applied}",
                e.name, e.set, e.time_s
            );
        }
        for u in &model.units {
            let source = match &u.source {
                Source::DirectionalDerivatives => "the FMU's directional derivatives".to_owned(),
                Source::FiniteDifferences { reason } => {
                    format!("central finite differences ({reason})")
                }
            };
            let _ = writeln!(
                text,
                "  {}: {} states, {} inputs, {} outputs; Jacobians from {source}",
                u.instance,
                u.states.len(),
                u.inputs.len(),
                u.outputs.len()
            );
        }
        let margin = |m: Option<f64>, unit: &str| {
            m.map_or_else(|| "none".to_owned(), |v| format!("{v:.2} {unit}"))
        };
        let _ = writeln!(text, "attitude loops broken at the torque command:");
        for axis in &self.axes {
            let line = |label: &str, m: &Margins| {
                let mut line = format!(
                    "    {label:<7} gain margin {} (at {}), phase margin {} (crossover {})",
                    margin(m.gain_margin_db, "dB"),
                    margin(m.phase_crossover_radps, "rad/s"),
                    margin(m.phase_margin_deg, "deg"),
                    margin(m.gain_crossover_radps, "rad/s"),
                );
                if let Some(reduction) = m.gain_reduction_margin_db {
                    line.push_str(&format!(
                        ", gain reduction margin {reduction:.2} dB (at {})",
                        margin(m.reduction_crossover_radps, "rad/s")
                    ));
                }
                line
            };
            let _ = writeln!(text, "  {} (broken at {})", axis.axis, axis.broken_at);
            let _ = writeln!(text, "{}", line("system", &axis.margins));
            if let Some(d) = &axis.design {
                let _ = writeln!(text, "{}", line("design", d));
            }
        }
        let mut eigenvalues = self.eigenvalues.clone();
        eigenvalues.sort_by(|a, b| b.s_re.total_cmp(&a.s_re));
        let largest = self
            .eigenvalues
            .iter()
            .map(|e| Complex::new(e.z_re, e.z_im).norm())
            .fold(0.0, f64::max);
        let _ = writeln!(
            text,
            "closed loop: {} eigenvalues, largest |z| = {largest:.6}; the least damped (s = ln z / h):",
            eigenvalues.len()
        );
        for e in eigenvalues.iter().take(8) {
            let _ = writeln!(
                text,
                "  s = {:+.4} {:+.4}j  (z = {:.6} {:+.6}j)",
                e.s_re, e.s_im, e.z_re, e.z_im
            );
        }
        text
    }
}
