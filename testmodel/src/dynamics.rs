//! m x'' = -k x - c x' + u, integrated with classical RK4.

/// Position (m) and velocity (m/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    pub x_m: f64,
    pub v_m_per_s: f64,
}

/// Constant coefficients over one sub-step (the input is held, zero-order hold).
#[derive(Debug, Clone, Copy)]
pub struct Coefficients {
    pub mass_kg: f64,
    pub k_n_per_m: f64,
    pub c_ns_per_m: f64,
    pub u_n: f64,
}

impl Coefficients {
    fn derivative(&self, s: State) -> State {
        State {
            x_m: s.v_m_per_s,
            v_m_per_s: (-self.k_n_per_m * s.x_m - self.c_ns_per_m * s.v_m_per_s + self.u_n)
                / self.mass_kg,
        }
    }

    /// One RK4 step of `dt_s` from `s`.
    pub fn rk4(&self, s: State, dt_s: f64) -> State {
        let at = |base: State, d: State, f: f64| State {
            x_m: base.x_m + f * d.x_m,
            v_m_per_s: base.v_m_per_s + f * d.v_m_per_s,
        };
        let k1 = self.derivative(s);
        let k2 = self.derivative(at(s, k1, dt_s / 2.0));
        let k3 = self.derivative(at(s, k2, dt_s / 2.0));
        let k4 = self.derivative(at(s, k3, dt_s));
        State {
            x_m: s.x_m + dt_s / 6.0 * (k1.x_m + 2.0 * k2.x_m + 2.0 * k3.x_m + k4.x_m),
            v_m_per_s: s.v_m_per_s
                + dt_s / 6.0
                    * (k1.v_m_per_s + 2.0 * k2.v_m_per_s + 2.0 * k3.v_m_per_s + k4.v_m_per_s),
        }
    }
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;

    /// RK4 is fourth order: halving the step cuts the error after a fixed time ~16x.
    #[test]
    fn rk4_error_falls_sixteenfold_when_the_step_halves() {
        let c = Coefficients {
            mass_kg: 1.0,
            k_n_per_m: 4.0,
            c_ns_per_m: 0.0,
            u_n: 0.0,
        };
        let error = |n: usize| {
            let dt = 1.0 / n as f64;
            let mut s = State {
                x_m: 1.0,
                v_m_per_s: 0.0,
            };
            for _ in 0..n {
                s = c.rk4(s, dt);
            }
            (s.x_m - (2.0f64).cos()).abs()
        };
        let ratio = error(20) / error(40);
        assert!((14.0..18.0).contains(&ratio), "ratio {ratio}");
    }
}
