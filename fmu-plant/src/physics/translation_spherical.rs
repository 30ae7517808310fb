//! Translation over a spherical, rotating Moon: paper eq. 1 with the ERRATA (item 10).
//!
//! State `[r, lon, lat, u, v, w]`: radius from the Moon's centre (m), longitude and latitude
//! (rad), and the velocity relative to the rotating Moon resolved in the local horizon frame
//! at the lander: `u` tangential (East), `v` cross (North), `w` radial (Up), in m/s.
//! The paper's text swaps latitude and longitude (its equations do not: `lon' = u/(r cos lat)`),
//! and its v-dot line misses a `+` before the transport term; both are corrected here.
//!
//! One more sign differs from the paper: the radial Coriolis term is `+2 omega_m u cos(lat)`
//! (an eastward velocity is pushed outwards, the Eötvös effect), not `-2 u omega_m cos(lat)`.
//! The Coriolis force does no work, so its radial term must cancel the `-2 omega_m w cos(lat)`
//! the paper itself prints in u-dot: `u (-2 omega_m w cos) + w (+2 omega_m u cos) = 0`. The
//! test against an inertial Cartesian integration below settles every sign independently.
//!
//! Gravity is central, `mu / r^2` with `mu = g R^2`, so that the single gravity parameter
//! means the surface gravity in both translation models and they differ only by the terms
//! the flat model neglects. Inputs and outputs are in the landing site's NUE frame, which is
//! fixed to the Moon; the velocity is relative to the Moon's surface in both models.
//! Limitation: `lon' = u / (r cos lat)` is singular at the poles; the site latitude is
//! restricted to |lat| <= 85 deg by the parameter check.
use super::dual::Scalar;
use super::frames::Nue;
use nalgebra::{Matrix3, Vector3, Vector6};

/// The Moon as a rotating sphere and the landing site on it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SphericalMoon {
    pub radius_m: f64,
    /// Gravitational parameter in m^3/s^2.
    pub mu_m3ps2: f64,
    /// Rotation rate about the Moon's north pole in rad/s.
    pub rotation_rate_radps: f64,
    /// Site position in Moon-fixed Cartesian coordinates (X: lon 0 on the equator, Z: north pole).
    site_mf: Vector3<f64>,
    /// Rows North, Up, East at the site: maps Moon-fixed vectors to site NUE.
    mf_to_site_nue: Matrix3<f64>,
}

/// Local horizon unit vectors at `(lon, lat)` in Moon-fixed coordinates.
struct Horizon {
    east: Vector3<f64>,
    north: Vector3<f64>,
    up: Vector3<f64>,
}

impl Horizon {
    fn at(lon: f64, lat: f64) -> Self {
        let (slon, clon) = libm::sincos(lon);
        let (slat, clat) = libm::sincos(lat);
        Self {
            east: Vector3::new(-slon, clon, 0.0),
            north: Vector3::new(-slat * clon, -slat * slon, clat),
            up: Vector3::new(clat * clon, clat * slon, slat),
        }
    }
}

impl SphericalMoon {
    /// `gravity_mps2` is the surface gravity g; `mu = g R^2`.
    pub fn new(
        radius_m: f64,
        gravity_mps2: f64,
        rotation_rate_radps: f64,
        site_latitude_rad: f64,
        site_longitude_rad: f64,
    ) -> Self {
        let site = Horizon::at(site_longitude_rad, site_latitude_rad);
        Self {
            radius_m,
            mu_m3ps2: gravity_mps2 * radius_m * radius_m,
            rotation_rate_radps,
            site_mf: site.up * radius_m,
            mf_to_site_nue: Matrix3::from_rows(&[
                site.north.transpose(),
                site.up.transpose(),
                site.east.transpose(),
            ]),
        }
    }

    /// State from a position and a Moon-relative velocity in site NUE.
    pub fn from_nue(&self, r_nue: &Nue, v_nue: &Nue) -> Vector6<f64> {
        let site_nue_to_mf = self.mf_to_site_nue.transpose();
        let p_mf = self.site_mf + site_nue_to_mf * r_nue.0;
        let v_mf = site_nue_to_mf * v_nue.0;
        let r = p_mf.norm();
        let lon = libm::atan2(p_mf.y, p_mf.x);
        let lat = libm::asin((p_mf.z / r).clamp(-1.0, 1.0));
        let h = Horizon::at(lon, lat);
        Vector6::new(
            r,
            lon,
            lat,
            h.east.dot(&v_mf),
            h.north.dot(&v_mf),
            h.up.dot(&v_mf),
        )
    }

    /// Position and Moon-relative velocity in site NUE.
    pub fn to_nue(&self, x: &Vector6<f64>) -> (Nue, Nue) {
        let h = Horizon::at(x[1], x[2]);
        let p_mf = h.up * x[0];
        let v_mf = h.east * x[3] + h.north * x[4] + h.up * x[5];
        (
            Nue(self.mf_to_site_nue * (p_mf - self.site_mf)),
            Nue(self.mf_to_site_nue * v_mf),
        )
    }

    /// Height above the spherical surface in m.
    pub fn altitude(&self, x: &Vector6<f64>) -> f64 {
        x[0] - self.radius_m
    }

    /// Time derivative for the thrust acceleration `a_thrust_nue` (site NUE, m/s^2).
    pub fn derivative(&self, x: &Vector6<f64>, a_thrust_nue: &Nue) -> Vector6<f64> {
        let (r, lon, lat, u, v, w) = (x[0], x[1], x[2], x[3], x[4], x[5]);
        let h = Horizon::at(lon, lat);
        let a_mf = self.mf_to_site_nue.transpose() * a_thrust_nue.0;
        let (a_east, a_north, a_up) = (h.east.dot(&a_mf), h.north.dot(&a_mf), h.up.dot(&a_mf));
        let (slat, clat) = libm::sincos(lat);
        let tan_lat = slat / clat;
        let om = self.rotation_rate_radps;

        let w_dot = a_up - self.mu_m3ps2 / (r * r)
            + (u * u + v * v) / r
            + (2.0 * om * u * clat + r * om * om * clat * clat);
        let u_dot =
            a_east + (-u * w + u * v * tan_lat) / r + (-2.0 * om * w * clat + 2.0 * om * v * slat);
        let v_dot = a_north
            + (-v * w - u * u * tan_lat) / r
            + (-2.0 * om * u * slat - r * om * om * slat * clat);
        Vector6::new(w, u / (r * clat), v / r, u_dot, v_dot, w_dot)
    }
}

/// [`SphericalMoon::derivative`] and [`SphericalMoon::to_nue`] on any [`Scalar`] (dual
/// numbers for their derivatives): the same equations, term for term.
impl SphericalMoon {
    /// Local horizon `(east, north, up)` at `(lon, lat)`, Moon-fixed.
    fn horizon_of<S: Scalar>(lon: S, lat: S) -> [[S; 3]; 3] {
        let (slon, clon) = lon.sin_cos();
        let (slat, clat) = lat.sin_cos();
        let zero = S::from(0.0);
        [
            [-slon, clon, zero],
            [-slat * clon, -slat * slon, clat],
            [clat * clon, clat * slon, slat],
        ]
    }

    /// `mf_to_site_nue^T a`: a site NUE vector in Moon-fixed axes.
    fn site_nue_to_mf<S: Scalar>(&self, a: &[S; 3]) -> [S; 3] {
        let m = &self.mf_to_site_nue;
        std::array::from_fn(|j| a[0] * m[(0, j)] + a[1] * m[(1, j)] + a[2] * m[(2, j)])
    }

    /// `mf_to_site_nue v`.
    fn mf_to_site<S: Scalar>(&self, v: &[S; 3]) -> [S; 3] {
        let m = &self.mf_to_site_nue;
        std::array::from_fn(|i| v[0] * m[(i, 0)] + v[1] * m[(i, 1)] + v[2] * m[(i, 2)])
    }

    /// [`SphericalMoon::derivative`] on [`Scalar`]s.
    pub fn derivative_of<S: Scalar>(&self, x: &[S; 6], a_thrust_nue: &[S; 3]) -> [S; 6] {
        let [r, lon, lat, u, v, w] = *x;
        let [east, north, up] = Self::horizon_of(lon, lat);
        let a_mf = self.site_nue_to_mf(a_thrust_nue);
        let dot = |a: &[S; 3], b: &[S; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let (a_east, a_north, a_up) = (dot(&east, &a_mf), dot(&north, &a_mf), dot(&up, &a_mf));
        let (slat, clat) = lat.sin_cos();
        let tan_lat = slat / clat;
        let om = self.rotation_rate_radps;
        let w_dot = a_up - S::from(self.mu_m3ps2) / (r * r)
            + (u * u + v * v) / r
            + (u * clat * (2.0 * om) + r * clat * clat * (om * om));
        let u_dot = a_east
            + (-u * w + u * v * tan_lat) / r
            + (-(w * clat * (2.0 * om)) + v * slat * (2.0 * om));
        let v_dot = a_north + (-v * w - u * u * tan_lat) / r
            - (u * slat * (2.0 * om) + r * slat * clat * (om * om));
        [w, u / (r * clat), v / r, u_dot, v_dot, w_dot]
    }

    /// [`SphericalMoon::to_nue`] on [`Scalar`]s: position and velocity in site NUE.
    pub fn to_nue_of<S: Scalar>(&self, x: &[S; 6]) -> ([S; 3], [S; 3]) {
        let [east, north, up] = Self::horizon_of(x[1], x[2]);
        let p_mf: [S; 3] = std::array::from_fn(|i| up[i] * x[0] - self.site_mf[i]);
        let v_mf: [S; 3] = std::array::from_fn(|i| east[i] * x[3] + north[i] * x[4] + up[i] * x[5]);
        (self.mf_to_site(&p_mf), self.mf_to_site(&v_mf))
    }
}

#[cfg(test)]
// std's functions here are a reference independent of the libm the model uses.
#[allow(clippy::disallowed_methods)]
mod tests {
    use super::*;
    use crate::physics::integrator::rk4_step;
    use nalgebra::Rotation3;

    const RADIUS_M: f64 = 1_737_400.0;

    fn moon(rate: f64) -> SphericalMoon {
        SphericalMoon::new(RADIUS_M, 1.62, rate, 0.6, -1.1)
    }

    #[test]
    fn nue_round_trip_is_exact_to_round_off() {
        let m = moon(2.66e-6);
        let r = Vector3::new(1200.0, 800.0, -350.0);
        let v = Vector3::new(-3.0, -20.0, 7.5);
        let (r2, v2) = m.to_nue(&m.from_nue(&Nue(r), &Nue(v)));
        let (r2, v2) = (r2.0, v2.0);
        assert!((r2 - r).norm() < 1e-8, "{r2} vs {r}");
        assert!((v2 - v).norm() < 1e-11, "{v2} vs {v}");
    }

    #[test]
    fn the_site_is_the_origin_and_altitude_there_is_zero() {
        let m = moon(0.0);
        let x = m.from_nue(&Nue::zeros(), &Nue::zeros());
        assert!(m.altitude(&x).abs() < 1e-9);
        assert!((x[2] - 0.6).abs() < 1e-15 && (x[1] + 1.1).abs() < 1e-15);
    }

    /// Integrates the same motion as a point mass in a Moon-centred inertial frame (whose
    /// axes coincide with the Moon-fixed ones at t = 0) and maps the result back to site NUE.
    /// Shares no equation with eq. 1 except Newton's law, so it checks every sign.
    fn inertial_reference(
        m: &SphericalMoon,
        r0_nue: Vector3<f64>,
        v0_nue: Vector3<f64>,
        a_thrust_nue: Vector3<f64>,
        t_end: f64,
        dt: f64,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let spin = Vector3::z() * m.rotation_rate_radps;
        let nue_to_mf = m.mf_to_site_nue.transpose();
        let p0 = m.site_mf + nue_to_mf * r0_nue;
        let v0 = nue_to_mf * v0_nue + spin.cross(&p0);
        let mut x = Vector6::new(p0.x, p0.y, p0.z, v0.x, v0.y, v0.z);
        let f = |t: f64, x: &Vector6<f64>| {
            let p = Vector3::new(x[0], x[1], x[2]);
            let moon_to_inertial =
                Rotation3::from_axis_angle(&Vector3::z_axis(), m.rotation_rate_radps * t);
            let a = -p * (m.mu_m3ps2 / p.norm().powi(3))
                + moon_to_inertial * (nue_to_mf * a_thrust_nue);
            Vector6::new(x[3], x[4], x[5], a.x, a.y, a.z)
        };
        let n = (t_end / dt).round() as usize;
        for k in 0..n {
            x = rk4_step(f, k as f64 * dt, &x, dt);
        }
        let inertial_to_moon =
            Rotation3::from_axis_angle(&Vector3::z_axis(), -m.rotation_rate_radps * t_end);
        let p = Vector3::new(x[0], x[1], x[2]);
        let v = Vector3::new(x[3], x[4], x[5]);
        let p_mf = inertial_to_moon * p;
        let v_mf = inertial_to_moon * (v - spin.cross(&p));
        (
            m.mf_to_site_nue * (p_mf - m.site_mf),
            m.mf_to_site_nue * v_mf,
        )
    }

    #[test]
    fn eq1_agrees_with_an_inertial_cartesian_integration_on_a_fast_spinning_moon() {
        // A Moon spinning 400x faster than the real one makes Coriolis and centrifugal terms
        // of the order of gravity, so that any sign error shows up far above the RK4 error.
        let m = moon(1e-3);
        let r0 = Vector3::new(2_000.0, 5_000.0, -1_000.0);
        let v0 = Vector3::new(150.0, 20.0, 300.0);
        let a_thrust = Vector3::new(0.4, 1.0, -0.3);
        let (t_end, dt): (f64, f64) = (200.0, 0.05);
        let mut x = m.from_nue(&Nue(r0), &Nue(v0));
        for _ in 0..(t_end / dt).round() as usize {
            x = rk4_step(|_t, x| m.derivative(x, &Nue(a_thrust)), 0.0, &x, dt);
        }
        let (r, v) = m.to_nue(&x);
        let (r, v) = (r.0, v.0);
        let (r_ref, v_ref) = inertial_reference(&m, r0, v0, a_thrust, t_end, dt);
        // The trajectory spans ~ 60 km; both integrations carry RK4 errors ~ 1e-6 m here.
        assert!((r - r_ref).norm() < 1e-4, "r {r} vs {r_ref}");
        assert!((v - v_ref).norm() < 1e-6, "v {v} vs {v_ref}");
        // The rotation matters at this rate: ignoring it would be off by kilometres.
        let (r_norot, _) = inertial_reference(&moon(0.0), r0, v0, a_thrust, t_end, dt);
        assert!((r - r_norot).norm() > 1_000.0);
    }

    #[test]
    fn printed_radial_coriolis_sign_would_violate_the_inertial_reference() {
        // An eastward velocity with w = 0 at the equator: the radial acceleration must
        // contain +2 omega u (the Eötvös effect), not -2 omega u as printed in the paper.
        let m = SphericalMoon::new(RADIUS_M, 1.62, 1e-3, 0.0, 0.0);
        let u = 100.0;
        let x = Vector6::new(RADIUS_M, 0.0, 0.0, u, 0.0, 0.0);
        let w_dot = m.derivative(&x, &Nue::zeros())[5];
        // Inertial speed of a point moving east at u on the equator: omega R + u; the net
        // inward acceleration of that circular motion is (omega R + u)^2 / R, so the
        // Moon-relative radial acceleration is -g + (omega R + u)^2 / R.
        let om = 1e-3;
        let expected = -1.62 + (om * RADIUS_M + u).powi(2) / RADIUS_M;
        assert!((w_dot - expected).abs() < 1e-12, "{w_dot} vs {expected}");
    }
}
