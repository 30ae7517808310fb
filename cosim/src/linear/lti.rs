//! Linear time-invariant systems, sampled: the zero-order-hold discretization of a continuous
//! model, eigenvalues, the frequency response of a single loop and its gain and phase
//! margins. Dense matrices (nalgebra); a lander's closed loop is some twenty states.
// An analysis printed to a few digits, never a trajectory: std's transcendental functions
// (and nalgebra's matrix exponential over them) may differ in the last bits between
// platforms without changing a reported margin.
#![allow(clippy::disallowed_methods)]
use nalgebra::{Complex, DMatrix, DVector};

/// `x' = A x + B u` sampled with period `h` and inputs held over each period:
/// `x[k+1] = Phi x[k] + Gamma u[k]`, from the exponential of `[[A, B], [0, 0]] h`.
pub fn zero_order_hold(a: &DMatrix<f64>, b: &DMatrix<f64>, h: f64) -> (DMatrix<f64>, DMatrix<f64>) {
    let (n, m) = (a.nrows(), b.ncols());
    let mut augmented = DMatrix::zeros(n + m, n + m);
    augmented.view_mut((0, 0), (n, n)).copy_from(&(a * h));
    augmented.view_mut((0, n), (n, m)).copy_from(&(b * h));
    let exp = augmented.exp();
    (
        exp.view((0, 0), (n, n)).into_owned(),
        exp.view((0, n), (n, m)).into_owned(),
    )
}

/// A discrete single-input single-output loop `x[k+1] = A x + b v`, `w = c x + d v`, period
/// `h`; its loop transfer function is `L(z) = -(c (zI - A)^-1 b + d)`, so that the loop
/// closes as `v = w` (negative feedback of `L`, as margins are defined).
#[derive(Debug, Clone)]
pub struct SampledLoop {
    pub a: DMatrix<f64>,
    pub b: DVector<f64>,
    pub c: DVector<f64>,
    pub d: f64,
    pub period_s: f64,
}

/// Gain and phase margins of a loop, with the frequencies they are read at.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Margins {
    /// `1 / |L|` in dB where the phase crosses -180 deg with `|L| < 1`: how much the loop gain
    /// may grow (the smallest such margin up to the Nyquist frequency); `None` when there is
    /// no such crossing.
    pub gain_margin_db: Option<f64>,
    pub phase_crossover_radps: Option<f64>,
    /// The same where `|L| > 1` (negative dB): how much the loop gain may shrink, as a
    /// conditionally stable loop (an inner loop around an outer one) has; `None` when none.
    pub gain_reduction_margin_db: Option<f64>,
    pub reduction_crossover_radps: Option<f64>,
    /// `180 deg + arg L` where `|L|` crosses 1 (the lowest such frequency); `None` when it never
    /// does.
    pub phase_margin_deg: Option<f64>,
    pub gain_crossover_radps: Option<f64>,
}

impl SampledLoop {
    /// `L(e^{j omega h})`.
    pub fn response(&self, omega_radps: f64) -> Complex<f64> {
        let n = self.a.nrows();
        let z = Complex::from_polar(1.0, omega_radps * self.period_s);
        let mut m: DMatrix<Complex<f64>> = self.a.map(|v| Complex::new(-v, 0.0));
        for i in 0..n {
            m[(i, i)] += z;
        }
        let b = self.b.map(|v| Complex::new(v, 0.0));
        let x = m
            .lu()
            .solve(&b)
            .unwrap_or_else(|| DVector::from_element(n, Complex::new(f64::NAN, f64::NAN)));
        let cx: Complex<f64> = self.c.iter().zip(x.iter()).map(|(c, x)| x * *c).sum();
        -(cx + Complex::new(self.d, 0.0))
    }

    /// Margins read on a logarithmic grid from `omega_min` to just below the Nyquist
    /// frequency, each crossing refined by bisection.
    pub fn margins(&self, omega_min_radps: f64) -> Margins {
        let nyquist = std::f64::consts::PI / self.period_s;
        let points = 4000;
        let grid: Vec<f64> = (0..=points)
            .map(|i| {
                let f = i as f64 / points as f64;
                omega_min_radps * (nyquist * 0.9999 / omega_min_radps).powf(f)
            })
            .collect();
        let magnitude = |w: f64| self.response(w).norm().ln();
        // The phase crosses -180 deg where L is real and negative: Im L changes sign with
        // Re L < 0.
        let imaginary = |w: f64| self.response(w).im;
        let mut margins = Margins {
            gain_margin_db: None,
            phase_crossover_radps: None,
            gain_reduction_margin_db: None,
            reduction_crossover_radps: None,
            phase_margin_deg: None,
            gain_crossover_radps: None,
        };
        for pair in grid.windows(2) {
            let (w0, w1) = (pair[0], pair[1]);
            if margins.gain_crossover_radps.is_none() && magnitude(w0) * magnitude(w1) <= 0.0 {
                let w = bisect(magnitude, w0, w1);
                let l = self.response(w);
                margins.gain_crossover_radps = Some(w);
                margins.phase_margin_deg = Some(wrap_deg(180.0 + l.arg().to_degrees()));
            }
            if imaginary(w0) * imaginary(w1) <= 0.0 {
                let w = bisect(imaginary, w0, w1);
                let l = self.response(w);
                if l.re < 0.0 {
                    margins.phase_crossing(-20.0 * l.norm().log10(), w);
                }
            }
        }
        // At the Nyquist frequency a real loop's response is real: a phase of -180 deg there
        // is a crossing the grid's sign test cannot see.
        let l = self.response(nyquist);
        if l.re < 0.0 && l.im.abs() <= 1e-9 * l.norm() {
            margins.phase_crossing(-20.0 * l.norm().log10(), nyquist);
        }
        margins
    }
}

impl Margins {
    /// A crossing of -180 deg with the margin `margin_db` at `omega`: kept if it is the
    /// nearest to 0 dB of its sign.
    fn phase_crossing(&mut self, margin_db: f64, omega: f64) {
        if margin_db >= 0.0 {
            if self.gain_margin_db.is_none_or(|best| margin_db < best) {
                self.gain_margin_db = Some(margin_db);
                self.phase_crossover_radps = Some(omega);
            }
        } else if self
            .gain_reduction_margin_db
            .is_none_or(|best| margin_db > best)
        {
            self.gain_reduction_margin_db = Some(margin_db);
            self.reduction_crossover_radps = Some(omega);
        }
    }
}

fn bisect(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let f_lo = f(lo);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if (f(mid) <= 0.0) == (f_lo <= 0.0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// An angle in degrees into (-180, 180].
fn wrap_deg(angle: f64) -> f64 {
    let wrapped = angle.rem_euclid(360.0);
    if wrapped > 180.0 {
        wrapped - 360.0
    } else {
        wrapped
    }
}

/// The eigenvalues of a square matrix.
pub fn eigenvalues(a: &DMatrix<f64>) -> Vec<Complex<f64>> {
    a.clone().complex_eigenvalues().iter().copied().collect()
}

/// A discrete eigenvalue `z` as the continuous one it samples, `ln(z) / h`.
pub fn continuous_eigenvalue(z: Complex<f64>, period_s: f64) -> Complex<f64> {
    z.ln() / period_s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The single-axis rigid-body loop `L(s) = (Kd s + Kp) / (I s^2)` sampled with period `h`:
    /// states angle and rate, torque held over the period, the PD law acting on the state
    /// at the sample.
    fn rigid_body_loop(inertia: f64, kp: f64, kd: f64, h: f64) -> SampledLoop {
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
        let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0 / inertia]);
        let (phi, gamma) = zero_order_hold(&a, &b, h);
        SampledLoop {
            a: phi,
            b: gamma.column(0).into_owned(),
            // w = -(Kp theta + Kd omega): the command the controller would send
            c: DVector::from_vec(vec![-kp, -kd]),
            d: 0.0,
            period_s: h,
        }
    }

    #[test]
    fn the_hold_of_a_double_integrator_is_the_textbook_one() {
        let (h, inertia) = (0.01, 300.0);
        let l = rigid_body_loop(inertia, 1.0, 1.0, h);
        let expected_phi = DMatrix::from_row_slice(2, 2, &[1.0, h, 0.0, 1.0]);
        assert!((l.a - expected_phi).norm() < 1e-14);
        assert!((l.b[0] - h * h / (2.0 * inertia)).abs() < 1e-15);
        assert!((l.b[1] - h / inertia).abs() < 1e-15);
    }

    #[test]
    fn slow_sampling_approaches_the_continuous_margins_of_a_pd_loop() {
        // GIVEN omega_n = pi rad/s, zeta = 0.8 (the paper's 0.5 Hz) on I = 300 kg m^2
        let (inertia, zeta) = (300.0, 0.8);
        let wn = std::f64::consts::PI;
        let (kp, kd) = (inertia * wn * wn, 2.0 * zeta * wn * inertia);
        // Continuous: |L| = 1 at w^2 = wn^2 (2 zeta^2 + sqrt(4 zeta^4 + 1)), PM = atan(2 zeta w / wn)
        let wc = wn * (2.0 * zeta * zeta + (4.0 * zeta.powi(4) + 1.0).sqrt()).sqrt();
        let pm = (2.0 * zeta * wc / wn).atan().to_degrees();
        // WHEN sampled fast (1 ms)
        let m = rigid_body_loop(inertia, kp, kd, 1e-3).margins(1e-2);
        // THEN the crossover is the continuous one and the phase margin is short by the
        // hold's half-period delay, w h / 2
        let wc_fmu = m.gain_crossover_radps.unwrap();
        assert!((wc_fmu - wc).abs() < 1e-3 * wc, "{wc_fmu} vs {wc}");
        let lag = (wc * 1e-3 / 2.0).to_degrees();
        let pm_fmu = m.phase_margin_deg.unwrap();
        assert!(
            (pm_fmu - (pm - lag)).abs() < 0.05,
            "{pm_fmu} vs {pm} - {lag}"
        );
        // AND the sampled loop has a finite gain margin (the continuous one has none)
        assert!(m.gain_margin_db.unwrap() > 20.0);
    }

    #[test]
    fn a_pure_gain_loop_has_the_gain_margin_of_its_gain() {
        // L(z) = k / z (one-sample delay): phase -180 deg at Nyquist... and the loop
        // x[k+1] = v, w = -k x: |L| = k everywhere
        let l = SampledLoop {
            a: DMatrix::zeros(1, 1),
            b: DVector::from_vec(vec![1.0]),
            c: DVector::from_vec(vec![-0.5]),
            d: 0.0,
            period_s: 0.1,
        };
        assert!((l.response(3.0).norm() - 0.5).abs() < 1e-12);
        let m = l.margins(1e-3);
        assert_eq!(m.gain_crossover_radps, None);
        assert_eq!(m.phase_margin_deg, None);
        // arg(1/z) = -w h reaches -180 deg at the Nyquist frequency: 1 / 0.5 is 6.02 dB
        assert!((m.gain_margin_db.unwrap() - 20.0 * 2f64.log10()).abs() < 1e-9);
        assert_eq!(m.phase_crossover_radps, Some(std::f64::consts::PI / 0.1));
        assert_eq!(m.gain_reduction_margin_db, None);
    }

    #[test]
    fn eigenvalues_of_a_rotation_and_their_continuous_counterparts() {
        let h = 0.1;
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -4.0, -0.4]);
        let (phi, _) = zero_order_hold(&a, &DMatrix::zeros(2, 1), h);
        let mut s: Vec<_> = eigenvalues(&phi)
            .into_iter()
            .map(|z| continuous_eigenvalue(z, h))
            .collect();
        s.sort_by(|a, b| a.im.total_cmp(&b.im));
        // s^2 + 0.4 s + 4 = 0: -0.2 +- j sqrt(3.96)
        assert!(
            (s[1] - Complex::new(-0.2, 3.96f64.sqrt())).norm() < 1e-10,
            "{s:?}"
        );
    }
}
