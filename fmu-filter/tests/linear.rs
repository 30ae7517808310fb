//! On a linear case the ESKF is the linear Kalman filter. With the attitude known exactly
//! (zero attitude and gyro-bias covariance, no gyro noise, a zero gyro reading) and a flat
//! terrain under an upright lander, position, velocity and accelerometer bias evolve
//! linearly and the altimeter and velocimeter are linear in them. The filter's estimate and
//! covariance must then equal an ordinary 9-state Kalman filter's, written here
//! independently (dense matrices, the measurements of a step as one batch update), to
//! 1e-12 relative to the size of each state vector and each covariance element's sigmas.
// std's transcendental functions here make test inputs, outside the model.
#![allow(clippy::disallowed_methods)]
use fmu_filter::fmu::{step, Measurements};
use fmu_filter::model::covariance::{BA, BG, R as IR, THETA};
use fmu_filter::model::{Eskf, FilterParameters, Imu};
use nalgebra::{DMatrix, DVector, SMatrix, SVector};

type M9 = SMatrix<f64, 9, 9>;
type V9 = SVector<f64, 9>;

fn params(h: f64) -> FilterParameters {
    let mut p = FilterParameters {
        sample_period_s: h,
        attitude0_sigma_rad: 0.0,
        altimeter_noise_proportional: 0.0,
        r0_nue_m: [12.0, 750.0, -4.0],
        v0_nue_mps: [1.0, -9.0, 0.5],
        ..FilterParameters::default()
    };
    p.gyro.bias_sigma = 0.0;
    p.gyro.noise_density = 0.0;
    p.gyro.bias_random_walk = 0.0;
    p
}

/// The measurements of step `k`: the altimeter every third step, the beams in turns.
fn measurements(k: usize) -> Measurements {
    let t = k as f64 * 0.1;
    Measurements {
        imu: Imu {
            accel_body_mps2: [0.02 * t.sin(), 1.62 + 0.05 * (0.3 * t).cos(), -0.01],
            gyro_body_radps: [0.0; 3],
        },
        altimeter_range_m: 750.0 - 9.0 * t + 0.3 * (7.0 * t).sin(),
        altimeter_valid: k.is_multiple_of(3),
        velocimeter_los_velocity_mps: [
            8.0 + 0.1 * t.cos(),
            8.5 - 0.05 * t,
            8.2 + 0.02 * (3.0 * t).sin(),
        ],
        velocimeter_valid: [k.is_multiple_of(2), k % 5 != 1, true],
    }
}

#[test]
fn the_eskf_equals_the_linear_kalman_filter_on_a_linear_case() {
    let h = 0.1;
    let p = params(h);
    let mut eskf = Eskf::start(&p);
    // The independent filter: x = (r, v, b_a), both in NUE = body (upright).
    let mut x = V9::zeros();
    for i in 0..3 {
        x[i] = p.r0_nue_m[i];
        x[3 + i] = p.v0_nue_mps[i];
    }
    let mut cov = M9::zeros();
    for i in 0..3 {
        cov[(i, i)] = p.r0_sigma_m * p.r0_sigma_m;
        cov[(3 + i, 3 + i)] = p.v0_sigma_mps * p.v0_sigma_mps;
        cov[(6 + i, 6 + i)] = p.accel.bias_sigma * p.accel.bias_sigma;
    }
    let i3 = SMatrix::<f64, 3, 3>::identity();
    let mut a = M9::identity();
    a.fixed_view_mut::<3, 3>(0, 3).copy_from(&(i3 * h));
    a.fixed_view_mut::<3, 3>(0, 6)
        .copy_from(&(i3 * (-0.5 * h * h)));
    a.fixed_view_mut::<3, 3>(3, 6).copy_from(&(i3 * -h));
    let mut q = M9::zeros();
    let va = p.accel.noise_density * p.accel.noise_density / p.sample_period_s;
    let wa = p.accel.bias_random_walk * p.accel.bias_random_walk * h;
    q.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(i3 * (h.powi(4) / 4.0 * va)));
    q.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&(i3 * (h.powi(3) / 2.0 * va)));
    q.fixed_view_mut::<3, 3>(3, 0)
        .copy_from(&(i3 * (h.powi(3) / 2.0 * va)));
    q.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&(i3 * (h * h * va)));
    q.fixed_view_mut::<3, 3>(6, 6).copy_from(&(i3 * wa));
    let g = V9::from_column_slice(&[0.0, -p.gravity_mps2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let beams = p.velocimeter_beams_body();

    let mut worst: f64 = 0.0;
    for k in 0..300 {
        let m = measurements(k);
        // The batch update of the independent filter.
        let mut rows = Vec::new();
        let mut ys = Vec::new();
        let mut noise = Vec::new();
        if m.altimeter_valid {
            let mut row = vec![0.0; 9];
            row[1] = 1.0;
            rows.push(row);
            ys.push(m.altimeter_range_m);
            noise.push(p.altimeter_noise_sigma_m * p.altimeter_noise_sigma_m);
        }
        for (i, b) in beams.iter().enumerate() {
            if m.velocimeter_valid[i] {
                let mut row = vec![0.0; 9];
                row[3..6].copy_from_slice(b);
                rows.push(row);
                ys.push(m.velocimeter_los_velocity_mps[i]);
                noise.push(p.velocimeter_noise_sigma_mps * p.velocimeter_noise_sigma_mps);
            }
        }
        let hm = DMatrix::from_fn(rows.len(), 9, |r, c| rows[r][c]);
        let rm = DMatrix::from_diagonal(&DVector::from_vec(noise));
        let pd = DMatrix::from_column_slice(9, 9, cov.as_slice());
        let s = &hm * &pd * hm.transpose() + &rm;
        let gain = &pd * hm.transpose() * s.try_inverse().unwrap();
        let xd = DVector::from_column_slice(x.as_slice());
        let xd = &xd + &gain * (DVector::from_vec(ys) - &hm * &xd);
        let ikh = DMatrix::identity(9, 9) - &gain * &hm;
        let pd = &ikh * &pd * ikh.transpose() + &gain * &rm * gain.transpose();
        x = V9::from_column_slice(xd.as_slice());
        cov = M9::from_column_slice(pd.as_slice());
        // Its propagation.
        let mut u = V9::zeros();
        for i in 0..3 {
            let f = m.imu.accel_body_mps2[i] + g[i];
            u[i] = 0.5 * h * h * f;
            u[3 + i] = h * f;
        }
        x = a * x + u;
        cov = a * cov * a.transpose() + q;

        // The ESKF, as the FMU steps it.
        step(&mut eskf, &p, &m, h);

        // THEN the same estimate and covariance, and an attitude untouched.
        let est: Vec<f64> = eskf
            .r_nue_m
            .iter()
            .chain(&eskf.v_nue_mps)
            .chain(&eskf.accel_bias_mps2)
            .copied()
            .collect();
        let sd: Vec<f64> = (0..9).map(|i| cov[(i, i)].sqrt()).collect();
        // Relative to the size of the element's vector (a component can pass through zero).
        let size = |i: usize| x.fixed_rows::<3>(i / 3 * 3).norm();
        for i in 0..9 {
            let err = (est[i] - x[i]).abs() / (size(i) + sd[i]);
            worst = worst.max(err);
            assert!(err < 1e-12, "step {k}, state {i}: {} vs {}", est[i], x[i]);
        }
        let map = |i: usize| if i < 6 { IR + i } else { BA + i - 6 };
        for i in 0..9 {
            for j in 0..9 {
                let got = eskf.p[map(i)][map(j)];
                let err = (got - cov[(i, j)]).abs() / (sd[i] * sd[j]);
                worst = worst.max(err);
                assert!(
                    err < 1e-12,
                    "step {k}, P[{i}][{j}]: {got} vs {}",
                    cov[(i, j)]
                );
            }
        }
        assert_eq!(eskf.q_body_to_nue, [1.0, 0.0, 0.0, 0.0]);
        for i in THETA..THETA + 3 {
            assert_eq!(eskf.p[i][i], 0.0);
        }
        assert_eq!(eskf.gyro_bias_radps, [0.0; 3]);
        assert_eq!(eskf.p[BG][BG], 0.0);
    }
    println!("largest relative difference: {worst:e}");
}
