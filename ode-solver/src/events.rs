//! State-event detection and location, kept apart from the ODE backend so the FMI rule
//! lives in one place.

use crate::SolverError;

/// FMI's rule (FMI 2.0, 3.1; FMI 3.0, 3.1.1): an event is a change of the domain of an
/// indicator from `z > 0` to `z <= 0` or back, so reaching zero from above is an event and
/// leaving zero downwards is not.
pub(crate) fn crossed(before: f64, after: f64) -> bool {
    (before > 0.0) != (after > 0.0)
}

pub(crate) fn any_crossed(before: &[f64], after: &[f64]) -> bool {
    before.iter().zip(after).any(|(b, a)| crossed(*b, *a))
}

pub(crate) fn which_crossed(before: &[f64], after: &[f64]) -> Vec<usize> {
    (0..before.len())
        .filter(|&j| crossed(before[j], after[j]))
        .collect()
}

/// Bisect (lo, hi] down to `width`, where `z_before` holds the indicators at the step start
/// (no crossing at `lo`) and `z_hi` those at `hi` (some crossing). Returns the new `hi`, the
/// earliest time found with a crossing, and leaves its indicators in `z_hi`.
///
/// Bisection, not secant: it needs no continuity of z and its cost is bounded,
/// log2(step / width) indicator calls.
pub(crate) fn locate(
    mut lo: f64,
    mut hi: f64,
    z_before: &[f64],
    z_hi: &mut [f64],
    width: f64,
    mut eval: impl FnMut(f64, &mut [f64]) -> Result<(), SolverError>,
) -> Result<f64, SolverError> {
    let mut z_mid = vec![0.0; z_before.len()];
    while hi - lo > width {
        let mid = lo + 0.5 * (hi - lo);
        // Adjacent floats: the bracket cannot shrink further.
        if mid <= lo || mid >= hi {
            break;
        }
        eval(mid, &mut z_mid)?;
        let crossed_now = (0..z_mid.len()).any(|j| crossed(z_before[j], z_mid[j]));
        if crossed_now {
            hi = mid;
            z_hi.copy_from_slice(&z_mid);
        } else {
            lo = mid;
        }
    }
    Ok(hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rule() {
        assert!(crossed(1.0, -1.0));
        assert!(crossed(-1.0, 1.0));
        // Reaching zero from above enters the domain z <= 0; moving within it is no event.
        assert!(crossed(1.0, 0.0));
        assert!(!crossed(0.0, -1.0));
        assert!(crossed(0.0, 1.0));
        assert!(!crossed(0.0, 0.0));
        assert!(!crossed(1.0, 2.0));
        assert!(!crossed(-1.0, -2.0));
    }

    #[test]
    fn bisection_brackets_root() {
        let root = 0.3;
        let mut z_hi = [0.7];
        let t = locate(0.0, 1.0, &[-0.3], &mut z_hi, 1e-12, |t, z| {
            z[0] = t - root;
            Ok(())
        })
        .unwrap();
        assert!(t >= root && t - root <= 1e-12);
        assert!(z_hi[0] >= 0.0);
    }

    #[test]
    fn an_exact_zero_from_above_is_the_event() {
        // Bisection of [0, 1] hits t = 0.5 exactly, where z = 0: already the domain z <= 0.
        let mut z_hi = [-0.5];
        let t = locate(0.0, 1.0, &[0.5], &mut z_hi, 1e-9, |t, z| {
            z[0] = 0.5 - t;
            Ok(())
        })
        .unwrap();
        assert_eq!(t, 0.5);
        assert_eq!(z_hi[0], 0.0);
    }
}
