//! Hazard-avoidance retargeting (beyond the paper): a new landing site commanded in flight,
//! flown by a cubic divert whose duration is chosen so that its lateral acceleration stays
//! within what the thrust can give at the tilt limit and the current mass.
//!
//! The divert is the descent polynomial of [`super::polynomial`] through the new boundary
//! conditions (from the current estimated state and held command to the new site at rest,
//! zero final acceleration). Its duration is the shortest, on a grid of guidance cycles from
//! a lower bound, whose peak horizontal acceleration (bounded analytically per axis, see
//! [`peak_lateral_acceleration_bound_mps2`]) is within the lateral authority
//! ([`lateral_authority_mps2`]).
use super::polynomial::{solve_cubic, BoundaryConditions, CubicAcceleration};
use lander_math::frames::Nue;

/// The longest divert the re-plan considers, s; a divert that needs more (its start
/// acceleration alone beyond the authority, see [`divert_time_to_go_s`]) is flown over this.
pub const MAX_DIVERT_TIME_S: f64 = 1000.0;

/// The share of the lateral authority the divert is sized for; the rest is room for the
/// closed loop: the attitude lags the command (0.5 Hz), so the state falls behind the plan
/// and the re-solves of each guidance cycle ask a little more than the plan did.
pub const DIVERT_AUTHORITY_SHARE: f64 = 0.8;

/// The largest tilt limit the re-plan accepts, rad (80 deg): `tan` stays finite and the
/// divert a divert.
pub const MAX_RETARGET_TILT_RAD: f64 = 80.0 * std::f64::consts::PI / 180.0;

/// The horizontal thrust acceleration available while the vertical one cancels gravity,
/// m/s^2: the smaller of what the tilt limit allows (`g tan(tilt_max)`) and what the engines
/// can add to `m g` (`sqrt((T_max / m)^2 - g^2)`, 0 when they cannot even hover).
///
/// At the paper's numbers (1,600 N, 1.62 m/s^2): 0.73 m/s^2 at 900 kg, 1.00 m/s^2 at 840 kg
/// from the thrust; 0.43 m/s^2 from a 15 deg tilt limit.
pub fn lateral_authority_mps2(
    thrust_max_n: f64,
    mass_kg: f64,
    gravity_mps2: f64,
    max_tilt_rad: f64,
) -> f64 {
    let from_tilt = gravity_mps2 * libm::tan(max_tilt_rad);
    if mass_kg.is_nan() || mass_kg <= 0.0 {
        return from_tilt.max(0.0);
    }
    let a_max = thrust_max_n / mass_kg;
    let from_thrust = (a_max * a_max - gravity_mps2 * gravity_mps2)
        .max(0.0)
        .sqrt();
    from_tilt.min(from_thrust).max(0.0)
}

/// `a_thrust_nue` with its horizontal (North, East) part shortened to at most `limit_mps2`,
/// the Up component unchanged.
pub fn limit_horizontal(a_thrust_nue: &Nue, limit_mps2: f64) -> Nue {
    let a = &a_thrust_nue.0;
    let h = (a.x * a.x + a.z * a.z).sqrt();
    if h <= limit_mps2 || h == 0.0 {
        return *a_thrust_nue;
    }
    let scale = limit_mps2.max(0.0) / h;
    Nue::new(a.x * scale, a.y, a.z * scale)
}

/// The largest `|c0 + c1 s + c2 s^2 + c3 s^3|` over `s` in `[0, end_s]`: the end points and
/// the roots of the derivative `c1 + 2 c2 s + 3 c3 s^2` inside the interval.
pub fn cubic_peak_abs(c: [f64; 4], end_s: f64) -> f64 {
    let value = |s: f64| (c[0] + (c[1] + (c[2] + c[3] * s) * s) * s).abs();
    let mut peak = value(0.0).max(value(end_s));
    let (a, b, cc) = (3.0 * c[3], 2.0 * c[2], c[1]);
    let mut consider = |s: f64| {
        if s.is_finite() && s > 0.0 && s < end_s {
            peak = peak.max(value(s));
        }
    };
    if a == 0.0 {
        if b != 0.0 {
            consider(-cc / b);
        }
    } else {
        let disc = b * b - 4.0 * a * cc;
        if disc >= 0.0 {
            // The stable pair of roots: q / a and cc / q, no cancellation.
            let q = -0.5 * (b + disc.sqrt().copysign(if b == 0.0 { 1.0 } else { b }));
            consider(q / a);
            if q != 0.0 {
                consider(cc / q);
            }
        }
    }
    peak
}

/// An upper bound of the cubic's horizontal (North, East) acceleration over `[0, tgo_s]`:
/// `sqrt(peak_N^2 + peak_E^2)` of the per-axis peaks, exact when the divert is along a fixed
/// horizontal direction (rest to rest, or start velocity along the divert).
pub fn peak_lateral_acceleration_bound_mps2(cubic: &CubicAcceleration, tgo_s: f64) -> f64 {
    let axis = |i: usize| cubic_peak_abs(cubic.coeffs.map(|c| c.0[i]), tgo_s);
    let (north, east) = (axis(0), axis(2));
    (north * north + east * east).sqrt()
}

/// The divert's duration: the shortest `tgo = min_tgo_s + k cycle_s` (k = 0, 1, ...) whose
/// cubic through `bc` keeps [`peak_lateral_acceleration_bound_mps2`] within `authority_mps2`,
/// or within the start's own horizontal acceleration when that alone is larger (no duration
/// brings the peak below the acceleration it starts from).
///
/// Found by doubling `k` until the cubic fits, then bisecting between the last `k` that did not
/// and the first that did (some 40 solves however fine the cycle): the shortest on the grid
/// when the peak decreases as the divert lengthens, as it does from rest (`D / T^2`); any
/// returned duration fits. [`MAX_DIVERT_TIME_S`] when none up to it fits; never below
/// `min_tgo_s`.
pub fn divert_time_to_go_s(
    bc: &BoundaryConditions,
    min_tgo_s: f64,
    cycle_s: f64,
    authority_mps2: f64,
) -> f64 {
    let a0 = &bc.a0_net_nue.0;
    let limit = authority_mps2.max((a0.x * a0.x + a0.z * a0.z).sqrt());
    // Integer steps from the lower bound: no accumulated rounding in the grid.
    let tgo = |k: u64| min_tgo_s + k as f64 * cycle_s;
    let fits = |k: u64| {
        let tgo_s = tgo(k);
        peak_lateral_acceleration_bound_mps2(&solve_cubic(bc, tgo_s), tgo_s) <= limit
    };
    if fits(0) {
        return min_tgo_s;
    }
    let last = ((MAX_DIVERT_TIME_S - min_tgo_s) / cycle_s).ceil().max(0.0) as u64;
    // Invariant: `low` does not fit, `high` fits.
    let (mut low, mut high) = (0u64, 1u64);
    while !fits(high) {
        if high >= last {
            return MAX_DIVERT_TIME_S.max(min_tgo_s);
        }
        low = high;
        high = (2 * high).min(last);
    }
    while high - low > 1 {
        let mid = low + (high - low) / 2;
        if fits(mid) {
            high = mid;
        } else {
            low = mid;
        }
    }
    tgo(high)
}

/// A rest-to-rest divert of `distance_m` over `tgo_s` has the acceleration profile
/// `60 D/T^2 tau (1 - tau)(1 - 2 tau)`, `tau = s/T`, whose peak is `(10 / sqrt 3) D / T^2` at
/// `tau = 1/2 - sqrt(3)/6`: the shortest rest-to-rest divert within `authority_mps2` lasts
/// `sqrt(10 D / (sqrt(3) a))`.
pub fn rest_to_rest_divert_time_s(distance_m: f64, authority_mps2: f64) -> f64 {
    (10.0 * distance_m / (3.0f64.sqrt() * authority_mps2)).sqrt()
}

/// The horizontal distance from `r_nue` to `site_nue`, m.
pub fn horizontal_distance_m(r_nue: &Nue, site_nue: &Nue) -> f64 {
    let d = (*site_nue - *r_nue).0;
    (d.x * d.x + d.z * d.z).sqrt()
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;

    fn rest_to_rest(distance_north_m: f64) -> BoundaryConditions {
        BoundaryConditions {
            r0_nue: Nue::new(0.0, 150.0, 0.0),
            v0_nue: Nue::zeros(),
            a0_net_nue: Nue::zeros(),
            rf_nue: Nue::new(distance_north_m, 150.0, 0.0),
            vf_nue: Nue::zeros(),
            af_net_nue: Nue::zeros(),
        }
    }

    /// The largest horizontal acceleration on a dense grid: an independent reference.
    fn sampled_peak(cubic: &CubicAcceleration, tgo_s: f64) -> f64 {
        (0..=20_000)
            .map(|k| {
                let a = cubic.net_acceleration_nue(tgo_s * k as f64 / 20_000.0);
                a.0.x.hypot(a.0.z)
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn authority_is_the_smaller_of_the_tilt_and_the_thrust_limits() {
        let g: f64 = 1.62;
        // GIVEN the paper's engines at 900 kg with a generous tilt limit: thrust-limited
        let a = lateral_authority_mps2(1600.0, 900.0, g, 60f64.to_radians());
        let expected = ((1600.0f64 / 900.0).powi(2) - g * g).sqrt();
        assert!(
            (a - expected).abs() < 1e-12 && (a - 0.732).abs() < 1e-3,
            "{a}"
        );
        // AND at 840 kg about 1 m/s^2
        let a = lateral_authority_mps2(1600.0, 840.0, g, 60f64.to_radians());
        assert!((a - 1.0).abs() < 0.01, "{a}");
        // GIVEN a 15 deg tilt limit: tilt-limited, g tan 15 deg
        let a = lateral_authority_mps2(1600.0, 840.0, g, 15f64.to_radians());
        assert!((a - g * 15f64.to_radians().tan()).abs() < 1e-12, "{a}");
        // AND engines that cannot hover give none
        assert_eq!(lateral_authority_mps2(1000.0, 900.0, g, 0.3), 0.0);
        assert!(lateral_authority_mps2(1600.0, 0.0, g, 0.3).is_finite());
    }

    #[test]
    fn the_per_axis_peak_is_exact_on_known_cubics() {
        // GIVEN the rest-to-rest shape 60 (s - 3 s^2 + 2 s^3) on [0, 1]
        let peak = cubic_peak_abs([0.0, 60.0, -180.0, 120.0], 1.0);
        // THEN its peak is 10 / sqrt(3)
        assert!((peak - 10.0 / 3f64.sqrt()).abs() < 1e-12, "{peak}");
        // AND a constant, a line and a parabola with an inside vertex are right
        assert_eq!(cubic_peak_abs([-2.0, 0.0, 0.0, 0.0], 5.0), 2.0);
        assert_eq!(cubic_peak_abs([1.0, -1.0, 0.0, 0.0], 3.0), 2.0);
        assert!((cubic_peak_abs([0.0, 4.0, -1.0, 0.0], 10.0) - 60.0).abs() < 1e-12);
        assert!((cubic_peak_abs([0.0, 4.0, -1.0, 0.0], 3.0) - 4.0).abs() < 1e-12);
        // AND a tiny cubic term does not lose the parabola's vertex to cancellation
        let near = cubic_peak_abs([0.0, 4.0, -1.0, 1e-18], 3.0);
        assert!((near - 4.0).abs() < 1e-9, "{near}");
    }

    #[test]
    fn the_rest_to_rest_divert_meets_the_authority_exactly() {
        // GIVEN a 30 m divert at rest and a 0.434 m/s^2 authority (15 deg at 1.62 m/s^2)
        let authority = 1.62 * 15f64.to_radians().tan();
        let bc = rest_to_rest(30.0);
        // WHEN the re-plan chooses its duration on a 0.1 s grid
        let tgo = divert_time_to_go_s(&bc, 5.0, 0.1, authority);
        // THEN it is the closed-form sqrt(10 D / (sqrt 3 a)), rounded up to the grid
        let closed = rest_to_rest_divert_time_s(30.0, authority);
        assert!(
            tgo >= closed - 1e-9 && tgo < closed + 0.1 + 1e-9,
            "{tgo} {closed}"
        );
        assert!((closed - 19.98).abs() < 0.01, "{closed}");
        // AND the cubic over it peaks within the authority, one cycle shorter would not
        let cubic = solve_cubic(&bc, tgo);
        let peak = sampled_peak(&cubic, tgo);
        assert!(peak <= authority * (1.0 + 1e-9), "{peak} > {authority}");
        let shorter = solve_cubic(&bc, tgo - 0.1);
        assert!(sampled_peak(&shorter, tgo - 0.1) > authority);
        // AND the peak is where the closed form puts it: tau = 1/2 - sqrt(3)/6
        let tau = 0.5 - 3f64.sqrt() / 6.0;
        let at = cubic.net_acceleration_nue(tau * tgo).0.x;
        assert!((at - peak).abs() < 1e-6, "{at} {peak}");
    }

    #[test]
    fn the_divert_cubic_passes_through_the_new_boundary_conditions() {
        // GIVEN a lander moving and accelerating off the line to a site 30 m North, 10 m West
        let bc = BoundaryConditions {
            r0_nue: Nue::new(0.4, 151.0, -0.3),
            v0_nue: Nue::new(-0.2, -0.3, 0.1),
            a0_net_nue: Nue::new(0.01, 0.02, -0.01),
            rf_nue: Nue::new(30.0, 150.0, -10.0),
            vf_nue: Nue::zeros(),
            af_net_nue: Nue::zeros(),
        };
        let authority = 0.434;
        let tgo = divert_time_to_go_s(&bc, 5.0, 0.1, authority);
        let cubic = solve_cubic(&bc, tgo);
        // WHEN the double integrator is integrated analytically over the divert
        let (r, v) = super::super::polynomial::integrate_open_loop(&bc, &cubic, tgo);
        // THEN it ends on the new site at rest, starting from the held acceleration
        assert!((r - bc.rf_nue).norm() < 1e-9, "r = {r:?}");
        assert!(v.norm() < 1e-10, "v = {v:?}");
        assert!((cubic.net_acceleration_nue(0.0) - bc.a0_net_nue).norm() < 1e-15);
        assert!(cubic.net_acceleration_nue(tgo).norm() < 1e-12);
        // AND its true peak lateral acceleration is within the bound, the bound within authority
        let bound = peak_lateral_acceleration_bound_mps2(&cubic, tgo);
        let sampled = sampled_peak(&cubic, tgo);
        assert!(sampled <= bound * (1.0 + 1e-12), "{sampled} > {bound}");
        assert!(bound <= authority, "{bound}");
    }

    #[test]
    fn the_duration_grows_with_the_distance_and_never_drops_below_the_lower_bound() {
        let authority = 0.434;
        let short = divert_time_to_go_s(&rest_to_rest(1.0), 12.0, 0.1, authority);
        assert_eq!(short, 12.0, "a 1 m divert needs only the lower bound");
        let mut previous = 0.0;
        for d in [10.0, 30.0, 100.0, 300.0] {
            let tgo = divert_time_to_go_s(&rest_to_rest(d), 5.0, 0.1, authority);
            assert!(tgo > previous, "{d} m: {tgo}");
            previous = tgo;
        }
    }

    #[test]
    fn a_start_beyond_the_authority_is_not_refused() {
        // GIVEN a held command already 0.8 m/s^2 North, above a 0.434 authority
        let bc = BoundaryConditions {
            a0_net_nue: Nue::new(0.8, 0.0, 0.0),
            ..rest_to_rest(30.0)
        };
        // THEN the re-plan bounds the peak by the start's own acceleration, finitely
        let tgo = divert_time_to_go_s(&bc, 5.0, 0.1, 0.434);
        assert!(tgo < MAX_DIVERT_TIME_S, "{tgo}");
        let cubic = solve_cubic(&bc, tgo);
        assert!(peak_lateral_acceleration_bound_mps2(&cubic, tgo) <= 0.8);
        // AND a zero authority still gives a finite duration
        let none = divert_time_to_go_s(&rest_to_rest(30.0), 5.0, 0.1, 0.0);
        assert_eq!(none, MAX_DIVERT_TIME_S);
    }
}
