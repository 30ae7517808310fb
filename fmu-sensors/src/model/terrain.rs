//! The terrain: a plane through `(0, terrain_height, 0)` in NUE with an upward unit normal
//! `n`. A beam from the lander at `r` along the unit direction `d` (NUE) meets it at the slant
//! range `rho = h / cos(angle(d, -n))` with `h = n . (r - p0)` the lander's height above the
//! plane along its normal; it misses when the lander is on or below the plane (`h <= 0`) or
//! the beam does not point towards it (`-n . d <= 0`, at or above the plane's horizon).
use lander_math::frames::Nue;
use lander_math::quaternion::direction;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Terrain {
    pub point_nue: Nue,
    pub normal_nue: Nue,
}

impl Terrain {
    /// `None` for a normal without a direction (the parameters' validation refuses it).
    pub fn new(height_m: f64, normal_nue: &[f64; 3]) -> Option<Terrain> {
        Some(Terrain {
            point_nue: Nue::new(0.0, height_m, 0.0),
            normal_nue: Nue(direction(normal_nue)?),
        })
    }

    /// Height of `r` above the plane, along its normal.
    pub fn height(&self, r_nue: &Nue) -> f64 {
        self.normal_nue.dot(&(*r_nue - self.point_nue))
    }

    /// Slant range from `r` along the unit `d` to the plane, or `None` if the beam misses.
    pub fn slant_range(&self, r_nue: &Nue, d_nue: &Nue) -> Option<f64> {
        let h = self.height(r_nue);
        let cos = -self.normal_nue.dot(d_nue);
        (h > 0.0 && cos > 0.0).then(|| h / cos)
    }
}
