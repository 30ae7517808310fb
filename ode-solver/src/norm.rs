//! The one error measure both methods accept or reject steps by.

use crate::Tolerances;

/// RMS over the states of err_i / (atol + rtol * max(|y0_i|, |y1_i|)): a step is good when
/// this is at most 1. Taking the larger of the two ends keeps a state that passes through
/// zero from demanding absolute accuracy it does not need.
pub(crate) fn error_norm(err: &[f64], y0: &[f64], y1: &[f64], tol: &Tolerances) -> f64 {
    let sum: f64 = err
        .iter()
        .zip(y0.iter().zip(y1))
        .map(|(e, (a, b))| {
            let w = e / (tol.absolute + tol.relative * a.abs().max(b.abs()));
            w * w
        })
        .sum();
    rms_of_sum(sum, err.len())
}

/// RMS of v_i / scale_i.
pub(crate) fn scaled_rms(v: &[f64], scale: &[f64]) -> f64 {
    let sum: f64 = v
        .iter()
        .zip(scale)
        .map(|(a, s)| {
            let w = a / s;
            w * w
        })
        .sum();
    rms_of_sum(sum, v.len())
}

fn rms_of_sum(sum: f64, n: usize) -> f64 {
    if n == 0 {
        0.0
    } else {
        (sum / n as f64).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_by_the_larger_end() {
        let tol = Tolerances {
            relative: 0.1,
            absolute: 1.0,
            event_time: 1.0,
        };
        // Weights 1 + 0.1 * 10 = 2 and 1 + 0.1 * 30 = 4.
        let e = error_norm(&[2.0, 4.0], &[10.0, -30.0], &[-5.0, 0.0], &tol);
        assert_eq!(e, 1.0);
        assert_eq!(scaled_rms(&[3.0, -4.0], &[1.0, 1.0]), 12.5f64.sqrt());
        assert_eq!(scaled_rms(&[], &[]), 0.0);
    }
}
