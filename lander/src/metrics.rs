//! Figures of merit of one descent, computed from a recorded trajectory: what the paper's
//! comparison (and our acceptance test) looks at.
use cosim::master::Trajectory;

/// Column names the metrics read (instance names as in the shipped scenarios).
pub struct Columns<'a> {
    pub plant: &'a str,
    pub gnc: &'a str,
}

impl Default for Columns<'_> {
    fn default() -> Self {
        Self {
            plant: "plant",
            gnc: "gnc",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Metrics {
    /// Largest horizontal distance from the vertical through the landing site, whole flight (m).
    pub max_horizontal_deviation_m: f64,
    /// The same during the polynomial descent (guidance phase 2) (m).
    pub max_horizontal_deviation_descent_m: f64,
    /// |r_final - target| (m).
    pub terminal_position_error_m: f64,
    /// |v_final| (m/s): the target is a hover.
    pub terminal_velocity_error_mps: f64,
    pub final_altitude_m: f64,
    /// Largest |omega_body| (rad/s).
    pub max_body_rate_radps: f64,
    pub propellant_used_kg: f64,
    /// Time from the start of the run until the thrust-axis (roll) error stays within 2 deg
    /// (s); NaN if it never settles.
    pub roll_settling_time_s: f64,
    /// Final thrust-axis angle phi_b (rad).
    pub final_phi_b_rad: f64,
    /// Largest tilt of the thrust axis from the commanded direction after the first 30 s
    /// and before touchdown (rad).
    pub max_tilt_error_after_30s_rad: f64,
    /// Largest tilt of the thrust axis from the commanded direction, whole flight before
    /// touchdown (rad): how far the attitude law lets the thrust point away from what guidance
    /// asks while it turns. On the ground (a plant with landing gear flies on after its first
    /// footpad contact) the lander stands as the terrain holds it and no law steers.
    pub max_tilt_error_rad: f64,
    /// Horizontal speed at the first sample of the polynomial descent (m/s): the state the
    /// hover hands to the descent guidance, which the cubic then carries over its whole
    /// time-to-go. NaN without a descent.
    pub handover_horizontal_speed_mps: f64,
    pub end_time_s: f64,
    /// |r - descent target| at the last sample of the polynomial descent (m): what the
    /// controller leaves to the guidance, before any hover corrects it. NaN without a descent.
    pub descent_end_position_error_m: f64,
    /// North and East of the lander at that sample (m): the dispersion ellipse's points.
    pub descent_end_north_m: f64,
    pub descent_end_east_m: f64,
    /// Largest horizontal speed while the thrust-axis manoeuvre is under way, i.e. until the
    /// roll error settles within 2 deg (the whole run if it never does) (m/s).
    pub max_lateral_speed_manoeuvre_mps: f64,
    /// Time integral of the thrust axis's angle from its commanded direction, whole flight
    /// before touchdown (rad s, trapezoidal).
    pub tilt_error_integral_rad_s: f64,
    /// Touchdown state as the plant reports it; NaN when the run did not touch down (or the
    /// touchdown columns were not recorded).
    pub touchdown_vertical_speed_mps: f64,
    pub touchdown_horizontal_speed_mps: f64,
    pub touchdown_tilt_rad: f64,
    pub touchdown_body_rate_radps: f64,
    pub touchdown_north_m: f64,
    pub touchdown_east_m: f64,
    /// The divert of a scenario that commands a retarget (LanderGnc's `retarget_time`), from
    /// the command on: largest distance past the new site along the line from the position
    /// at the command (m), largest distance off that line (m), time from the command until
    /// the lander stays within 1 m of the new site (s; +inf when it is not within it at the
    /// end of the run) and largest tilt of the thrust axis from vertical (rad). NaN without
    /// a retarget command ([`crate::retarget::divert_metrics`] computes them).
    pub divert_overshoot_m: f64,
    pub divert_cross_track_m: f64,
    pub divert_settle_time_s: f64,
    pub divert_peak_tilt_rad: f64,
}

impl Metrics {
    /// These metrics with the divert's.
    pub fn with_divert(self, divert: &crate::retarget::DivertMetrics) -> Self {
        Self {
            divert_overshoot_m: divert.overshoot_m,
            divert_cross_track_m: divert.cross_track_m,
            divert_settle_time_s: if divert.settle_time_s.is_nan() {
                f64::INFINITY
            } else {
                divert.settle_time_s
            },
            divert_peak_tilt_rad: divert.peak_tilt_deg.to_radians(),
            ..self
        }
    }
}

/// Number of metric columns.
pub const METRIC_COUNT: usize = 28;

/// The metric columns (of a campaign's manifest.csv, say), named as the [`Metrics`] fields.
pub const METRIC_NAMES: [&str; METRIC_COUNT] = [
    "max_horizontal_deviation_m",
    "max_horizontal_deviation_descent_m",
    "terminal_position_error_m",
    "terminal_velocity_error_mps",
    "final_altitude_m",
    "max_body_rate_radps",
    "propellant_used_kg",
    "roll_settling_time_s",
    "final_phi_b_rad",
    "max_tilt_error_after_30s_rad",
    "end_time_s",
    "descent_end_position_error_m",
    "descent_end_north_m",
    "descent_end_east_m",
    "max_lateral_speed_manoeuvre_mps",
    "tilt_error_integral_rad_s",
    "touchdown_vertical_speed_mps",
    "touchdown_horizontal_speed_mps",
    "touchdown_tilt_rad",
    "touchdown_body_rate_radps",
    "touchdown_north_m",
    "touchdown_east_m",
    "max_tilt_error_rad",
    "handover_horizontal_speed_mps",
    "divert_overshoot_m",
    "divert_cross_track_m",
    "divert_settle_time_s",
    "divert_peak_tilt_rad",
];

pub fn metric_values(m: &Metrics) -> [f64; METRIC_COUNT] {
    [
        m.max_horizontal_deviation_m,
        m.max_horizontal_deviation_descent_m,
        m.terminal_position_error_m,
        m.terminal_velocity_error_mps,
        m.final_altitude_m,
        m.max_body_rate_radps,
        m.propellant_used_kg,
        m.roll_settling_time_s,
        m.final_phi_b_rad,
        m.max_tilt_error_after_30s_rad,
        m.end_time_s,
        m.descent_end_position_error_m,
        m.descent_end_north_m,
        m.descent_end_east_m,
        m.max_lateral_speed_manoeuvre_mps,
        m.tilt_error_integral_rad_s,
        m.touchdown_vertical_speed_mps,
        m.touchdown_horizontal_speed_mps,
        m.touchdown_tilt_rad,
        m.touchdown_body_rate_radps,
        m.touchdown_north_m,
        m.touchdown_east_m,
        m.max_tilt_error_rad,
        m.handover_horizontal_speed_mps,
        m.divert_overshoot_m,
        m.divert_cross_track_m,
        m.divert_settle_time_s,
        m.divert_peak_tilt_rad,
    ]
}

pub fn metrics_from(v: [f64; METRIC_COUNT]) -> Metrics {
    Metrics {
        max_horizontal_deviation_m: v[0],
        max_horizontal_deviation_descent_m: v[1],
        terminal_position_error_m: v[2],
        terminal_velocity_error_mps: v[3],
        final_altitude_m: v[4],
        max_body_rate_radps: v[5],
        propellant_used_kg: v[6],
        roll_settling_time_s: v[7],
        final_phi_b_rad: v[8],
        max_tilt_error_after_30s_rad: v[9],
        end_time_s: v[10],
        descent_end_position_error_m: v[11],
        descent_end_north_m: v[12],
        descent_end_east_m: v[13],
        max_lateral_speed_manoeuvre_mps: v[14],
        tilt_error_integral_rad_s: v[15],
        touchdown_vertical_speed_mps: v[16],
        touchdown_horizontal_speed_mps: v[17],
        touchdown_tilt_rad: v[18],
        touchdown_body_rate_radps: v[19],
        touchdown_north_m: v[20],
        touchdown_east_m: v[21],
        max_tilt_error_rad: v[22],
        handover_horizontal_speed_mps: v[23],
        divert_overshoot_m: v[24],
        divert_cross_track_m: v[25],
        divert_settle_time_s: v[26],
        divert_peak_tilt_rad: v[27],
    }
}

/// Metrics of a flight that produced none.
pub fn nan_metrics() -> Metrics {
    metrics_from([f64::NAN; METRIC_COUNT])
}

/// Error naming the missing column.
#[derive(Debug, thiserror::Error)]
#[error("trajectory has no column '{0}' (record it, or record all outputs)")]
pub struct MissingColumn(pub String);

/// Computes the metrics against the terminal hover target `target_nue`.
pub fn compute(
    trajectory: &Trajectory,
    columns: &Columns<'_>,
    target_nue: [f64; 3],
) -> Result<Metrics, MissingColumn> {
    compute_with_final(trajectory, trajectory, columns, target_nue)
}

/// [`compute`], with the touchdown state read from the last row of `final_row` (a run's
/// final values, which may hold columns `trajectory` does not record at every step).
pub fn compute_with_final(
    trajectory: &Trajectory,
    final_row: &Trajectory,
    columns: &Columns<'_>,
    target_nue: [f64; 3],
) -> Result<Metrics, MissingColumn> {
    // Columns are read in place (row-major, strided): a flight's metrics copy nothing.
    let col = |instance: &str, name: &str| {
        let full = format!("{instance}.{name}");
        let j = trajectory.column_index(&full).ok_or(MissingColumn(full))?;
        Ok::<_, MissingColumn>(Column {
            values: &trajectory.values,
            width: trajectory.names.len(),
            j,
        })
    };
    let p = columns.plant;
    let g = columns.gnc;
    let r: Vec<_> = (1..=3)
        .map(|i| col(p, &format!("r_nue[{i}]")))
        .collect::<Result<_, _>>()?;
    let v: Vec<_> = (1..=3)
        .map(|i| col(p, &format!("v_nue[{i}]")))
        .collect::<Result<_, _>>()?;
    let w: Vec<_> = (1..=3)
        .map(|i| col(p, &format!("omega_body[{i}]")))
        .collect::<Result<_, _>>()?;
    let propellant = col(p, "propellant_used")?;
    let phase = col(g, "guidance_phase")?;
    let err_roll = col(g, "err_roll")?;
    let phi_b = col(g, "phi_b")?;
    let tilt = col(g, "tilt_error")?;
    let n = trajectory.len();
    // Samples up to and including the touchdown (all of them where the plant records no
    // touchdown flag): the touchdown sample still ends a steered flight.
    let touched = col(p, "touchdown").ok();
    let airborne = |k: usize| {
        touched
            .as_ref()
            .is_none_or(|c| c[k] == 0.0 || (k > 0 && c[k - 1] == 0.0))
    };
    let last = n.saturating_sub(1);
    let max_over = |it: &mut dyn Iterator<Item = f64>| it.fold(0.0_f64, f64::max);
    let settle_limit = 2f64.to_radians();
    let settle_index = (0..n).rev().find(|&k| err_roll[k].abs() > settle_limit);
    let roll_settling_time_s = match settle_index {
        None => trajectory.times.first().copied().unwrap_or(f64::NAN),
        Some(k) if k + 1 < n => trajectory.times[k + 1],
        Some(_) => f64::NAN,
    };
    let t0 = trajectory.times.first().copied().unwrap_or(0.0);
    let times = &trajectory.times;
    let descent_end = (0..n).rev().find(|&k| phase[k] == 2.0);
    let descent_start = (0..n).find(|&k| phase[k] == 2.0);
    let at_descent_end = |f: &dyn Fn(usize) -> f64| descent_end.map_or(f64::NAN, f);
    let manoeuvre_end = settle_index.map_or(0, |k| k + 1);
    let tilt_error_integral_rad_s = (1..n)
        .filter(|&k| airborne(k))
        .map(|k| 0.5 * (tilt[k] + tilt[k - 1]) * (times[k] - times[k - 1]))
        .sum();
    let touchdown = touchdown_state(final_row, p);
    Ok(Metrics {
        max_horizontal_deviation_m: max_hypot(0..n, r[0], r[2]),
        max_horizontal_deviation_descent_m: max_hypot(
            (0..n).filter(|&k| phase[k] == 2.0),
            r[0],
            r[2],
        ),
        terminal_position_error_m: (0..3)
            .map(|i| (r[i][last] - target_nue[i]).powi(2))
            .sum::<f64>()
            .sqrt(),
        terminal_velocity_error_mps: (0..3).map(|i| v[i][last].powi(2)).sum::<f64>().sqrt(),
        final_altitude_m: r[1][last],
        max_body_rate_radps: max_over(
            &mut (0..n).map(|k| (w[0][k].powi(2) + w[1][k].powi(2) + w[2][k].powi(2)).sqrt()),
        ),
        propellant_used_kg: propellant[last],
        roll_settling_time_s,
        final_phi_b_rad: phi_b[last],
        max_tilt_error_after_30s_rad: max_over(
            &mut (0..n)
                .filter(|&k| trajectory.times[k] - t0 >= 30.0 && airborne(k))
                .map(|k| tilt[k]),
        ),
        max_tilt_error_rad: max_over(&mut (0..n).filter(|&k| airborne(k)).map(|k| tilt[k])),
        handover_horizontal_speed_mps: descent_start.map_or(f64::NAN, |k| v[0][k].hypot(v[2][k])),
        end_time_s: trajectory.times.last().copied().unwrap_or(f64::NAN),
        descent_end_position_error_m: at_descent_end(&|k| {
            (0..3)
                .map(|i| (r[i][k] - target_nue[i]).powi(2))
                .sum::<f64>()
                .sqrt()
        }),
        descent_end_north_m: at_descent_end(&|k| r[0][k]),
        descent_end_east_m: at_descent_end(&|k| r[2][k]),
        max_lateral_speed_manoeuvre_mps: max_hypot(0..n.min(manoeuvre_end.max(1)), v[0], v[2]),
        tilt_error_integral_rad_s,
        touchdown_vertical_speed_mps: touchdown[0],
        touchdown_horizontal_speed_mps: touchdown[1],
        touchdown_tilt_rad: touchdown[2],
        touchdown_body_rate_radps: touchdown[3],
        touchdown_north_m: touchdown[4],
        touchdown_east_m: touchdown[5],
        divert_overshoot_m: f64::NAN,
        divert_cross_track_m: f64::NAN,
        divert_settle_time_s: f64::NAN,
        divert_peak_tilt_rad: f64::NAN,
    })
}

/// One column of a row-major trajectory, indexed by row, read in place.
#[derive(Clone, Copy)]
struct Column<'a> {
    values: &'a [f64],
    width: usize,
    j: usize,
}

impl std::ops::Index<usize> for Column<'_> {
    type Output = f64;
    fn index(&self, k: usize) -> &f64 {
        &self.values[k * self.width + self.j]
    }
}

/// The largest `x[k].hypot(y[k])` over `rows`, 0 if none (NaNs skipped): exactly what
/// folding `f64::max` over every hypot from 0 gives, with hypot (a libm call) evaluated only
/// at the rows whose `x^2 + y^2` comes within 1e-9 of the largest. That sum is within a few
/// ulps of the exact square and hypot within one ulp of the exact norm, so the row of the
/// largest hypot is always among them. Squares that overflow, underflow to the subnormals or
/// are NaN fall back to evaluating every row.
fn max_hypot(rows: impl Iterator<Item = usize> + Clone, x: Column, y: Column) -> f64 {
    let square = |k: usize| x[k] * x[k] + y[k] * y[k];
    let every_row = |rows: &mut dyn Iterator<Item = usize>| {
        rows.map(|k| x[k].hypot(y[k])).fold(0.0_f64, f64::max)
    };
    let mut largest = 0.0_f64;
    for k in rows.clone() {
        let s = square(k);
        if !s.is_finite() {
            return every_row(&mut rows.clone());
        }
        largest = largest.max(s);
    }
    if largest < f64::MIN_POSITIVE * 2f64.powi(60) {
        return every_row(&mut rows.clone());
    }
    let threshold = largest * (1.0 - 1e-9);
    every_row(&mut rows.filter(|&k| square(k) >= threshold))
}

/// Vertical (down) and horizontal speed, tilt, body rate, North and East at touchdown, from
/// the plant's touchdown outputs in the last row; NaN without a recorded touchdown.
fn touchdown_state(trajectory: &Trajectory, plant: &str) -> [f64; 6] {
    let last = |name: &str| {
        let full = format!("{plant}.{name}");
        trajectory
            .column_index(&full)
            .filter(|_| !trajectory.is_empty())
            .map(|j| trajectory.row(trajectory.len() - 1)[j])
    };
    if last("touchdown").is_none_or(|flag| flag == 0.0) {
        return [f64::NAN; 6];
    }
    let get = |name: &str| last(name).unwrap_or(f64::NAN);
    let w = |i: usize| get(&format!("touchdown_omega_body[{i}]"));
    [
        -get("touchdown_v_nue[2]"),
        get("touchdown_v_nue[1]").hypot(get("touchdown_v_nue[3]")),
        get("touchdown_tilt"),
        (w(1).powi(2) + w(2).powi(2) + w(3).powi(2)).sqrt(),
        get("r_nue[1]"),
        get("r_nue[3]"),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metric_names_are_the_metrics_fields_in_order() {
        let m = metrics_from(std::array::from_fn(|i| i as f64));
        let table = toml::Value::try_from(m).unwrap();
        let table = table.as_table().unwrap();
        assert_eq!(table.len(), METRIC_NAMES.len());
        for (i, name) in METRIC_NAMES.iter().enumerate() {
            assert_eq!(table[*name].as_float(), Some(i as f64), "{name}");
        }
    }

    /// A hand-made two-row trajectory whose metrics are known by inspection.
    fn sample() -> Trajectory {
        let names = [
            "plant.r_nue[1]",
            "plant.r_nue[2]",
            "plant.r_nue[3]",
            "plant.v_nue[1]",
            "plant.v_nue[2]",
            "plant.v_nue[3]",
            "plant.omega_body[1]",
            "plant.omega_body[2]",
            "plant.omega_body[3]",
            "plant.propellant_used",
            "gnc.guidance_phase",
            "gnc.err_roll",
            "gnc.phi_b",
            "gnc.tilt_error",
        ];
        Trajectory {
            names: names.iter().map(|s| s.to_string()).collect(),
            times: vec![0.0, 40.0, 80.0],
            values: [
                [
                    3.0, 800.0, 4.0, 0.0, 0.0, 0.0, 0.0, 0.3, 0.4, 0.0, 1.0, 1.0, 0.0, 0.2,
                ],
                [
                    6.0, 500.0, 8.0, 0.3, -5.0, 0.4, 0.0, 0.0, 0.0, 5.0, 2.0, 0.01, 1.0, 0.1,
                ],
                [
                    0.0, 152.0, 0.0, 0.0, 0.0, 0.6, 0.0, 0.0, 0.0, 9.0, 3.0, 0.0, 2.6, 0.05,
                ],
            ]
            .concat(),
        }
    }

    #[test]
    fn the_tilt_metrics_stop_at_touchdown_when_the_plant_records_it() {
        // GIVEN the hand-checked flight touching down at t = 40 and still on the ground at
        // t = 80 (a landing gear's plant goes on after the first footpad contact), standing
        // 0.3 rad off the last command
        let mut t = sample();
        let width = t.names.len();
        t.names.push("plant.touchdown".into());
        let tilt = width - 1;
        let mut values = Vec::new();
        for (k, row) in t.values.chunks(width).enumerate() {
            values.extend_from_slice(row);
            if k == 2 {
                values[k * (width + 1) + tilt] = 0.3;
            }
            values.push(if k >= 1 { 1.0 } else { 0.0 });
        }
        t.values = values;
        // WHEN the metrics are computed
        let m = compute(&t, &Columns::default(), [0.0, 150.0, 0.0]).unwrap();
        // THEN the touchdown sample counts and the one after it in none of the tilt metrics
        assert_eq!(m.max_tilt_error_after_30s_rad, 0.1);
        assert_eq!(m.max_tilt_error_rad, 0.2);
        assert!((m.tilt_error_integral_rad_s - 6.0).abs() < 1e-12);
        // and the flag is what excludes it
        t.names.pop();
        let mut without = Vec::new();
        for row in t.values.chunks(width + 1) {
            without.extend_from_slice(&row[..width]);
        }
        t.values = without;
        let m = compute(&t, &Columns::default(), [0.0, 150.0, 0.0]).unwrap();
        assert_eq!(m.max_tilt_error_after_30s_rad, 0.3);
    }

    #[test]
    fn metrics_of_a_hand_checked_trajectory() {
        let m = compute(&sample(), &Columns::default(), [0.0, 150.0, 0.0]).unwrap();
        assert_eq!(m.max_horizontal_deviation_m, 10.0); // (6, 8) at t = 40
        assert_eq!(m.max_horizontal_deviation_descent_m, 10.0);
        assert_eq!(m.terminal_position_error_m, 2.0);
        assert_eq!(m.terminal_velocity_error_mps, 0.6);
        assert_eq!(m.final_altitude_m, 152.0);
        assert_eq!(m.max_body_rate_radps, 0.5);
        assert_eq!(m.propellant_used_kg, 9.0);
        assert_eq!(m.roll_settling_time_s, 40.0);
        assert_eq!(m.final_phi_b_rad, 2.6);
        assert_eq!(m.max_tilt_error_after_30s_rad, 0.1);
        // 0.2 at t = 0, before the 30 s the other tilt metric waits for
        assert_eq!(m.max_tilt_error_rad, 0.2);
        // the descent (phase 2) starts at t = 40 with v = (0.3, -5, 0.4): 0.5 m/s across
        assert_eq!(m.handover_horizontal_speed_mps, 0.5);
        // the descent (phase 2) ends at t = 40 at (6, 500, 8): |(6, 350, 8)|
        assert_eq!(
            m.descent_end_position_error_m,
            (36.0f64 + 350.0 * 350.0 + 64.0).sqrt()
        );
        assert_eq!((m.descent_end_north_m, m.descent_end_east_m), (6.0, 8.0));
        // the roll error settles at t = 40: only row 0 (at rest) is in the manoeuvre
        assert_eq!(m.max_lateral_speed_manoeuvre_mps, 0.0);
        // trapezoids: 40 (0.2 + 0.1) / 2 + 40 (0.1 + 0.05) / 2
        assert!((m.tilt_error_integral_rad_s - 9.0).abs() < 1e-12);
        assert!(
            m.touchdown_vertical_speed_mps.is_nan(),
            "no touchdown columns"
        );
    }

    #[test]
    fn the_lateral_speed_counts_only_while_the_manoeuvre_is_under_way() {
        let mut t = sample();
        // 0.6 m/s East in the last row: after the manoeuvre settled (t = 40), not counted
        let m = compute(&t, &Columns::default(), [0.0, 150.0, 0.0]).unwrap();
        assert_eq!(m.max_lateral_speed_manoeuvre_mps, 0.0);
        // a roll error still large at the end: the whole run is the manoeuvre
        t.values[2 * 14 + 11] = 1.0;
        let m = compute(&t, &Columns::default(), [0.0, 150.0, 0.0]).unwrap();
        assert_eq!(m.max_lateral_speed_manoeuvre_mps, 0.6);
    }

    #[test]
    fn the_touchdown_state_is_read_from_the_plant_outputs() {
        let mut t = sample();
        let extra = [
            ("plant.touchdown", 1.0),
            ("plant.touchdown_v_nue[1]", 0.3),
            ("plant.touchdown_v_nue[2]", -1.2),
            ("plant.touchdown_v_nue[3]", 0.4),
            ("plant.touchdown_tilt", 0.05),
            ("plant.touchdown_omega_body[1]", 0.0),
            ("plant.touchdown_omega_body[2]", 0.03),
            ("plant.touchdown_omega_body[3]", 0.04),
        ];
        let width = t.names.len();
        let mut values = Vec::new();
        for k in 0..t.len() {
            values.extend_from_slice(&t.values[k * width..(k + 1) * width]);
            values.extend(extra.iter().map(|(_, x)| *x));
        }
        t.names.extend(extra.iter().map(|(n, _)| n.to_string()));
        t.values = values;
        let m = compute(&t, &Columns::default(), [0.0, 150.0, 0.0]).unwrap();
        assert_eq!(m.touchdown_vertical_speed_mps, 1.2);
        assert_eq!(m.touchdown_horizontal_speed_mps, 0.5);
        assert_eq!(m.touchdown_tilt_rad, 0.05);
        assert!((m.touchdown_body_rate_radps - 0.05).abs() < 1e-15);
        assert_eq!((m.touchdown_north_m, m.touchdown_east_m), (0.0, 0.0));
    }

    /// What `max_hypot` must equal: hypot at every row, folded with `f64::max` from 0.
    fn every_row(xs: &[f64], ys: &[f64]) -> f64 {
        xs.iter()
            .zip(ys)
            .map(|(x, y)| x.hypot(*y))
            .fold(0.0_f64, f64::max)
    }

    fn max_hypot_of(xs: &[f64], ys: &[f64]) -> f64 {
        let values: Vec<f64> = xs.iter().zip(ys).flat_map(|(x, y)| [*x, *y]).collect();
        let x = Column {
            values: &values,
            width: 2,
            j: 0,
        };
        let y = Column { j: 1, ..x };
        max_hypot(0..xs.len(), x, y)
    }

    #[test]
    fn max_hypot_equals_hypot_at_every_row_bit_for_bit() {
        // Near-ties within rounding of each other, from a deterministic sequence.
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for scale in [1e-3, 1.0, 800.0, 1e150] {
            let base: Vec<f64> = (0..2000).map(|_| scale * (1.0 + next())).collect();
            let xs: Vec<f64> = base.iter().map(|b| b * 0.6).collect();
            // y chosen so every row's norm is within a few ulps of `base`.
            let ys: Vec<f64> = base
                .iter()
                .map(|b| b * 0.8 * (1.0 + 1e-16 * next()))
                .collect();
            let want = every_row(&xs, &ys);
            assert_eq!(max_hypot_of(&xs, &ys).to_bits(), want.to_bits(), "{scale}");
            let flat = vec![scale; 500];
            assert_eq!(
                max_hypot_of(&flat, &flat).to_bits(),
                every_row(&flat, &flat).to_bits()
            );
        }
        // Squares that overflow, underflow, or are NaN; no rows at all.
        let cases: [(&[f64], &[f64]); 5] = [
            (&[1e200, 3.0], &[1e200, 4.0]),
            (&[1e-200, 0.0], &[0.0, 1e-201]),
            (&[f64::NAN, 3.0], &[f64::INFINITY, 4.0]),
            (&[0.0, -0.0], &[-0.0, 0.0]),
            (&[], &[]),
        ];
        for (xs, ys) in cases {
            assert_eq!(
                max_hypot_of(xs, ys).to_bits(),
                every_row(xs, ys).to_bits(),
                "{xs:?} {ys:?}"
            );
        }
    }

    #[test]
    fn a_missing_column_is_named() {
        let mut t = sample();
        t.names[11] = "gnc.other".into();
        let e = compute(&t, &Columns::default(), [0.0; 3]).unwrap_err();
        assert!(e.to_string().contains("gnc.err_roll"));
    }
}
