//! The linear model of a co-simulated system at one communication point: each instance's
//! Jacobians (a Model Exchange instance's `A, B, C, D`; a Co-Simulation instance's outputs
//! with respect to its inputs, a static gain sampled at the communication step), and the
//! closed loop the master's exchange makes of them: inputs held over each step (zero-order
//! hold), the instances' outputs exchanged at the same point (Gauss-Seidel) or one step
//! late (Jacobi). No FMI here: `master/linearize.rs` fills [`SystemModel`] from the
//! instances.
pub mod lti;

use crate::system::Ordering;
use lti::SampledLoop;
use nalgebra::{DMatrix, DVector};

/// Where an instance's Jacobians came from.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Source {
    /// The FMU's directional derivatives (`fmi2GetDirectionalDerivative`,
    /// `fmi3GetDirectionalDerivative`).
    DirectionalDerivatives,
    /// Central differences of the FMU's outputs and derivatives, and why.
    FiniteDifferences { reason: String },
}

/// One instance linearized: `x' = A x + B u`, `y = C x + D u` (a Co-Simulation instance has no
/// states: `y = D u`), deviations from the values at the point.
#[derive(Debug, Clone)]
pub struct UnitModel {
    pub instance: String,
    pub model_exchange: bool,
    pub source: Source,
    /// `instance.variable` names.
    pub states: Vec<String>,
    pub inputs: Vec<String>,
    pub outputs: Vec<String>,
    pub a: DMatrix<f64>,
    pub b: DMatrix<f64>,
    pub c: DMatrix<f64>,
    pub d: DMatrix<f64>,
}

/// The linearized system: its instances and their connections at `time_s`.
#[derive(Debug, Clone)]
pub struct SystemModel {
    pub time_s: f64,
    pub period_s: f64,
    pub ordering: Ordering,
    pub units: Vec<UnitModel>,
    /// `(from output, to input)` among the units' outputs and inputs.
    pub connections: Vec<(String, String)>,
}

/// The system's matrices stacked: states, inputs and outputs of every unit in unit order.
struct Stacked {
    a: DMatrix<f64>,
    b: DMatrix<f64>,
    c: DMatrix<f64>,
    d: DMatrix<f64>,
    /// `u = m y`: which output feeds each input.
    m: DMatrix<f64>,
    inputs: Vec<String>,
}

impl SystemModel {
    fn stacked(&self) -> Result<Stacked, String> {
        let n: usize = self.units.iter().map(|u| u.states.len()).sum();
        let m: usize = self.units.iter().map(|u| u.inputs.len()).sum();
        let p: usize = self.units.iter().map(|u| u.outputs.len()).sum();
        let mut stacked = Stacked {
            a: DMatrix::zeros(n, n),
            b: DMatrix::zeros(n, m),
            c: DMatrix::zeros(p, n),
            d: DMatrix::zeros(p, m),
            m: DMatrix::zeros(m, p),
            inputs: Vec::with_capacity(m),
        };
        let mut outputs = Vec::with_capacity(p);
        let (mut x0, mut u0, mut y0) = (0, 0, 0);
        for unit in &self.units {
            let (nx, nu, ny) = (unit.states.len(), unit.inputs.len(), unit.outputs.len());
            stacked.a.view_mut((x0, x0), (nx, nx)).copy_from(&unit.a);
            stacked.b.view_mut((x0, u0), (nx, nu)).copy_from(&unit.b);
            stacked.c.view_mut((y0, x0), (ny, nx)).copy_from(&unit.c);
            stacked.d.view_mut((y0, u0), (ny, nu)).copy_from(&unit.d);
            stacked.inputs.extend(unit.inputs.iter().cloned());
            outputs.extend(unit.outputs.iter().cloned());
            (x0, u0, y0) = (x0 + nx, u0 + nu, y0 + ny);
        }
        for (from, to) in &self.connections {
            let (Some(i), Some(o)) = (
                stacked.inputs.iter().position(|name| name == to),
                outputs.iter().position(|name| name == from),
            ) else {
                continue;
            };
            stacked.m[(i, o)] = 1.0;
        }
        Ok(stacked)
    }

    /// Every state of the system, in order (`instance.variable`).
    pub fn states(&self) -> Vec<String> {
        self.units.iter().flat_map(|u| u.states.clone()).collect()
    }

    /// The closed loop's state matrix over one communication step, `x[k+1] = A x[k]`
    /// (Jacobi: the state extended by the inputs of the step before).
    pub fn closed_loop(&self) -> Result<DMatrix<f64>, String> {
        Ok(self.sampled(None)?.a)
    }

    /// The loop broken at the connected input `input` (`instance.variable`): what is injected
    /// there to what the connection would deliver, every other connection closed.
    pub fn broken_at(&self, input: &str) -> Result<SampledLoop, String> {
        self.sampled(Some(input))
    }

    fn sampled(&self, broken: Option<&str>) -> Result<SampledLoop, String> {
        let s = self.stacked()?;
        let (n, m) = (s.a.nrows(), s.b.ncols());
        let mut q = DMatrix::<f64>::identity(m, m);
        let mut e = DVector::<f64>::zeros(m);
        if let Some(name) = broken {
            let j = s.inputs.iter().position(|i| i == name).ok_or_else(|| {
                format!(
                    "'{name}' is not a connected input of the linearized system (its inputs: {})",
                    s.inputs.join(", ")
                )
            })?;
            if s.m.row(j).iter().all(|v| *v == 0.0) {
                return Err(format!("'{name}' is an input no connection feeds"));
            }
            q[(j, j)] = 0.0;
            e[j] = 1.0;
        }
        let (phi, gamma) = lti::zero_order_hold(&s.a, &s.b, self.period_s);
        let qm = &q * &s.m;
        let em = e.transpose() * &s.m;
        match self.ordering {
            Ordering::GaussSeidel => {
                // y = C x + D u, u = Q M y + e v: y = S (C x + D e v), S = (I - D Q M)^-1.
                let p = s.c.nrows();
                let s_inv = (DMatrix::<f64>::identity(p, p) - &s.d * &qm)
                    .try_inverse()
                    .ok_or("the instances' feedthrough makes an algebraic loop with no solution")?;
                let sc = &s_inv * &s.c;
                let sde = &s_inv * &s.d * &e;
                let a = &phi + &gamma * &qm * &sc;
                let b = &gamma * (&qm * &sde + &e);
                let c = (&em * &sc).transpose();
                let d = (&em * &sde)[(0, 0)];
                Ok(SampledLoop {
                    a,
                    b,
                    c: DVector::from_column_slice(c.as_slice()),
                    d,
                    period_s: self.period_s,
                })
            }
            Ordering::Jacobi => {
                // u[k] = Q M (C x[k] + D u[k-1]) + e v[k]; the state is (x, u[k-1]).
                let mut a = DMatrix::zeros(n + m, n + m);
                a.view_mut((0, 0), (n, n))
                    .copy_from(&(&phi + &gamma * &qm * &s.c));
                a.view_mut((0, n), (n, m)).copy_from(&(&gamma * &qm * &s.d));
                a.view_mut((n, 0), (m, n)).copy_from(&(&qm * &s.c));
                a.view_mut((n, n), (m, m)).copy_from(&(&qm * &s.d));
                let mut b = DVector::zeros(n + m);
                b.rows_mut(0, n).copy_from(&(&gamma * &e));
                b.rows_mut(n, m).copy_from(&e);
                let mut c = DVector::zeros(n + m);
                c.rows_mut(0, n)
                    .copy_from(&(&em * &s.c).transpose().column(0));
                c.rows_mut(n, m)
                    .copy_from(&(&em * &s.d).transpose().column(0));
                Ok(SampledLoop {
                    a,
                    b,
                    c,
                    d: 0.0,
                    period_s: self.period_s,
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A double integrator (angle, rate) under a PD controller, as two units.
    fn rigid_body(ordering: Ordering, inertia: f64, kp: f64, kd: f64) -> SystemModel {
        SystemModel {
            time_s: 0.0,
            period_s: 0.01,
            ordering,
            units: vec![
                UnitModel {
                    instance: "gnc".into(),
                    model_exchange: false,
                    source: Source::DirectionalDerivatives,
                    states: vec![],
                    inputs: vec!["gnc.theta".into(), "gnc.omega".into()],
                    outputs: vec!["gnc.torque".into()],
                    a: DMatrix::zeros(0, 0),
                    b: DMatrix::zeros(0, 2),
                    c: DMatrix::zeros(1, 0),
                    d: DMatrix::from_row_slice(1, 2, &[-kp, -kd]),
                },
                UnitModel {
                    instance: "plant".into(),
                    model_exchange: true,
                    source: Source::DirectionalDerivatives,
                    states: vec!["plant.theta".into(), "plant.omega".into()],
                    inputs: vec!["plant.torque".into()],
                    outputs: vec!["plant.theta".into(), "plant.omega".into()],
                    a: DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]),
                    b: DMatrix::from_row_slice(2, 1, &[0.0, 1.0 / inertia]),
                    c: DMatrix::identity(2, 2),
                    d: DMatrix::zeros(2, 1),
                },
            ],
            connections: vec![
                ("plant.theta".into(), "gnc.theta".into()),
                ("plant.omega".into(), "gnc.omega".into()),
                ("gnc.torque".into(), "plant.torque".into()),
            ],
        }
    }

    #[test]
    fn gauss_seidel_closes_the_loop_without_delay() {
        let (inertia, kp, kd, h) = (300.0, 3000.0, 1500.0, 0.01);
        let system = rigid_body(Ordering::GaussSeidel, inertia, kp, kd);
        // Phi - Gamma K with the hold of the double integrator
        let expected = DMatrix::from_row_slice(
            2,
            2,
            &[
                1.0 - h * h / (2.0 * inertia) * kp,
                h - h * h / (2.0 * inertia) * kd,
                -h / inertia * kp,
                1.0 - h / inertia * kd,
            ],
        );
        assert!((system.closed_loop().unwrap() - expected).norm() < 1e-12);
        // Broken at the torque: L(z) = K (zI - Phi)^-1 Gamma
        let l = system.broken_at("plant.torque").unwrap();
        assert_eq!(l.a.nrows(), 2);
        assert!((l.c - DVector::from_vec(vec![-kp, -kd])).norm() < 1e-12);
        assert!(system.broken_at("gnc.nothing").is_err());
    }

    #[test]
    fn jacobi_adds_the_step_of_delay() {
        let system = rigid_body(Ordering::Jacobi, 300.0, 3000.0, 1500.0);
        let gauss = rigid_body(Ordering::GaussSeidel, 300.0, 3000.0, 1500.0);
        let w = 4.0;
        let (lj, lg) = (
            system.broken_at("plant.torque").unwrap().response(w),
            gauss.broken_at("plant.torque").unwrap().response(w),
        );
        // Jacobi: the command of step k acts on the measurement of step k - 1 (the
        // controller's feedthrough answers the inputs set a step before): h of lag
        assert!((lj.norm() - lg.norm()).abs() < 1e-9);
        let lag = (lg.arg() - lj.arg()).rem_euclid(std::f64::consts::TAU);
        assert!((lag - w * 0.01).abs() < 1e-9, "{lag}");
    }
}
