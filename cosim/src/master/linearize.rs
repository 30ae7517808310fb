//! A run held at one communication point, and the linear model of the system there
//! (`crate::linear`): each instance's Jacobians from its directional derivatives when its
//! description declares them, else from central differences of what it computes (named as
//! such in the model). A Model Exchange instance gives `A, B, C, D` (its states perturbed with
//! `set_continuous_states`, its inputs with sets); a Co-Simulation one the partials of its
//! outputs with respect to its inputs at the point, its memory held: the static gain a sampled
//! controller is between two steps.
use super::{call, MasterError, Recorder, Simulation};
use crate::linear::{Source, SystemModel, UnitModel};
use fmi_import::{CallError, Instance, MeVector};
use nalgebra::DMatrix;

/// How the Jacobians are obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Jacobians {
    /// The FMU's directional derivatives where its description declares them, else
    /// differences.
    #[default]
    Fmu,
    /// Central differences for every instance.
    Differences,
}

/// Relative step of the central differences (times `max(1, |value|)`): the truncation error
/// of a smooth model is of its square, the rounding error of `1e-16 / step`.
const RELATIVE_STEP: f64 = 1e-6;

impl Simulation {
    /// Runs from the start and stops at the communication point at `time` (the nearest one of
    /// the grid), inputs set for it, the scenario events due up to and at it applied (those
    /// after it not) and nothing stepped, the instances kept for
    /// [`Simulation::linearize`]. `Ok(None)` when the run ended before (an instance stopped
    /// it, or `time` is past the stop time).
    pub fn run_to(
        &mut self,
        time: f64,
        recorder: &mut dyn Recorder,
    ) -> Result<Option<f64>, MasterError> {
        self.hold_at = Some(time);
        let ran = self.run(recorder);
        self.hold_at = None;
        ran?;
        Ok(self.held_at)
    }

    /// The linear model of the system at the point the last [`Simulation::run_to`] held at:
    /// every instance with a connected Real input or output, over its connected Real inputs
    /// and outputs (and, for Model Exchange, its continuous states).
    pub fn linearize(&mut self, jacobians: Jacobians) -> Result<SystemModel, MasterError> {
        let time_s = self.held_at.ok_or_else(|| MasterError::Call {
            instance: String::new(),
            context: "linearize: no run is held at a communication point (run_to first)".into(),
            source: Box::new(CallError::InvalidArgument {
                function: "linearize",
                instance: String::new(),
                reason: "no held run".into(),
            }),
        })?;
        let connections = self.connection_names.clone();
        let mut units = Vec::new();
        for u in 0..self.units.len() {
            let name = self.units[u].name.clone();
            let prefix = format!("{name}.");
            let ends = |pick: fn(&(String, String)) -> &String| -> Vec<String> {
                let mut names: Vec<String> = Vec::new();
                for connection in &connections {
                    let end = pick(connection);
                    if end.starts_with(&prefix) && !names.contains(end) {
                        names.push(end.clone());
                    }
                }
                names
            };
            let inputs = ends(|(_, to)| to);
            let outputs = ends(|(from, _)| from);
            let real = |instance: &Instance, names: &[String]| -> Result<Vec<u32>, CallError> {
                names
                    .iter()
                    .map(|n| {
                        let info = instance.variable(&n[prefix.len()..])?;
                        match info.kind {
                            fmi_import::VariableKind::Real => Ok(info.value_reference),
                            other => Err(CallError::InvalidArgument {
                                function: "linearize",
                                instance: instance.name().to_owned(),
                                reason: format!(
                                    "'{n}' is {other:?}; only Real connections are linearized"
                                ),
                            }),
                        }
                    })
                    .collect()
            };
            let model_exchange = self.units[u].model_exchange.is_some();
            let unit = &mut self.units[u];
            let fmu = &self.fmus[u];
            let in_vrs = real(&unit.instance, &inputs).map_err(|e| call(&name, "linearize", e))?;
            let out_vrs =
                real(&unit.instance, &outputs).map_err(|e| call(&name, "linearize", e))?;
            let (state_vrs, derivative_vrs) = if model_exchange {
                let structure = unit.instance.derivative_structure().map_err(|reason| {
                    call(
                        &name,
                        "linearize",
                        CallError::InvalidArgument {
                            function: "linearize",
                            instance: name.clone(),
                            reason,
                        },
                    )
                })?;
                let derivatives = structure.derivatives.iter().map(|d| d.unknown).collect();
                (structure.states, derivatives)
            } else {
                (Vec::new(), Vec::new())
            };
            let state_names: Vec<String> = state_vrs
                .iter()
                .map(|vr| {
                    fmu.model_description()
                        .model_variables
                        .variables
                        .iter()
                        .find(|v| v.value_reference == *vr && v.real.is_some())
                        .map_or_else(
                            || format!("{prefix}#{vr}"),
                            |v| format!("{prefix}{}", v.name),
                        )
                })
                .collect();
            let refusal = unit.instance.derivative_refusal(false);
            let source = match (jacobians, refusal) {
                (Jacobians::Fmu, None) => Source::DirectionalDerivatives,
                (Jacobians::Fmu, Some(reason)) => Source::FiniteDifferences { reason },
                (Jacobians::Differences, _) => Source::FiniteDifferences {
                    reason: "differences asked for".into(),
                },
            };
            let mut probe = Probe {
                instance: &mut unit.instance,
                model_exchange,
                states: state_vrs.len(),
                in_vrs: &in_vrs,
                out_vrs: &out_vrs,
            };
            let (source, matrices) = match source {
                Source::DirectionalDerivatives => match probe.exact(&state_vrs, &derivative_vrs) {
                    Ok(matrices) => (Source::DirectionalDerivatives, Ok(matrices)),
                    // An FMU may refuse some partials at some points (a sample that solves
                    // more than it differentiates): differences then, saying why.
                    Err(refused) => (
                        Source::FiniteDifferences {
                            reason: format!(
                                "the FMU refused its directional derivatives: {refused}"
                            ),
                        },
                        probe.differences(),
                    ),
                },
                forced => (forced, probe.differences()),
            };
            let (a, b, c, d) = matrices.map_err(|e| call(&name, "linearize", e))?;
            units.push(UnitModel {
                instance: name,
                model_exchange,
                source,
                states: state_names,
                inputs,
                outputs,
                a,
                b,
                c,
                d,
            });
        }
        Ok(SystemModel {
            time_s,
            period_s: self.system.step_size,
            ordering: self.system.ordering,
            units,
            connections,
        })
    }
}

type Matrices = (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>, DMatrix<f64>);

/// One instance at the held point, asked for its partials.
struct Probe<'a> {
    instance: &'a mut Instance,
    model_exchange: bool,
    states: usize,
    in_vrs: &'a [u32],
    out_vrs: &'a [u32],
}

impl Probe<'_> {
    /// Column by column from unit seeds: `[der; y]` with respect to `[x; u]`.
    fn exact(&mut self, state_vrs: &[u32], derivative_vrs: &[u32]) -> Result<Matrices, CallError> {
        let unknowns: Vec<u32> = derivative_vrs.iter().chain(self.out_vrs).copied().collect();
        let knowns: Vec<u32> = state_vrs.iter().chain(self.in_vrs).copied().collect();
        let mut jacobian = DMatrix::zeros(unknowns.len(), knowns.len());
        let mut column = vec![0.0; unknowns.len()];
        for (j, known) in knowns.iter().enumerate() {
            self.instance
                .get_directional_derivative(&unknowns, &[*known], &[1.0], &mut column)?;
            jacobian.column_mut(j).copy_from_slice(&column);
        }
        Ok(self.split(jacobian))
    }

    /// `[der; y]` at the point, through the FMU's own calls.
    fn evaluate(&mut self) -> Result<Vec<f64>, CallError> {
        let mut values = vec![0.0; self.states + self.out_vrs.len()];
        if self.model_exchange {
            self.instance
                .get_vector(MeVector::Derivatives, &mut values[..self.states])?;
        }
        self.instance
            .get_real(self.out_vrs, &mut values[self.states..])?;
        Ok(values)
    }

    /// Central differences of [`Probe::evaluate`] in each state and input, each put back.
    fn differences(&mut self) -> Result<Matrices, CallError> {
        let mut x = vec![0.0; self.states];
        if self.model_exchange {
            self.instance.get_vector(MeVector::States, &mut x)?;
        }
        let mut u = vec![0.0; self.in_vrs.len()];
        self.instance.get_real(self.in_vrs, &mut u)?;
        let rows = self.states + self.out_vrs.len();
        let mut jacobian = DMatrix::zeros(rows, self.states + u.len());
        for j in 0..self.states + u.len() {
            let value = if j < self.states {
                x[j]
            } else {
                u[j - self.states]
            };
            let step = RELATIVE_STEP * value.abs().max(1.0);
            let side = |delta: f64, probe: &mut Self| -> Result<Vec<f64>, CallError> {
                if j < probe.states {
                    let mut moved = x.clone();
                    moved[j] += delta;
                    probe.instance.set_continuous_states(&moved)?;
                } else {
                    let k = j - probe.states;
                    probe
                        .instance
                        .set_real(&[probe.in_vrs[k]], &[u[k] + delta])?;
                }
                probe.evaluate()
            };
            let plus = side(step, self)?;
            let minus = side(-step, self)?;
            for i in 0..rows {
                jacobian[(i, j)] = (plus[i] - minus[i]) / (2.0 * step);
            }
            if j < self.states {
                self.instance.set_continuous_states(&x)?;
            } else {
                let k = j - self.states;
                self.instance.set_real(&[self.in_vrs[k]], &[u[k]])?;
            }
        }
        Ok(self.split(jacobian))
    }

    fn split(&self, jacobian: DMatrix<f64>) -> Matrices {
        let (n, m, p) = (self.states, self.in_vrs.len(), self.out_vrs.len());
        (
            jacobian.view((0, 0), (n, n)).into_owned(),
            jacobian.view((0, n), (n, m)).into_owned(),
            jacobian.view((n, 0), (p, n)).into_owned(),
            jacobian.view((n, n), (p, m)).into_owned(),
        )
    }
}
