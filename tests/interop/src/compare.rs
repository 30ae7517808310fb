//! Trajectories compared at every communication point: the largest difference per variable.
use cosim::master::Trajectory;
use std::fmt;

/// One column's agreement over all paired rows.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnDiff {
    pub name: String,
    /// Largest |reference - other|; infinite when one side is NaN and the other is not.
    pub max_abs: f64,
    /// Reference time of the row where `max_abs` occurs.
    pub at_time: f64,
    /// Rows whose values are not equal (NaN equals NaN here).
    pub differing_rows: usize,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    pub rows: usize,
    pub columns: Vec<ColumnDiff>,
}

impl Comparison {
    /// The largest difference over all columns.
    pub fn max_abs(&self) -> f64 {
        self.columns.iter().map(|c| c.max_abs).fold(0.0, f64::max)
    }

    /// True when every paired value is equal: the masters computed the same numbers.
    pub fn identical(&self) -> bool {
        self.columns.iter().all(|c| c.differing_rows == 0)
    }
}

impl fmt::Display for Comparison {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{:<32} {:>12} {:>10} {:>8}   ({} rows compared)",
            "variable", "max |diff|", "at t (s)", "rows !=", self.rows
        )?;
        for c in &self.columns {
            let at = if c.differing_rows == 0 {
                "-".to_owned()
            } else {
                format!("{:.2}", c.at_time)
            };
            writeln!(
                f,
                "{:<32} {:>12.3e} {:>10} {:>8}",
                c.name, c.max_abs, at, c.differing_rows
            )?;
        }
        Ok(())
    }
}

/// Pairs `other`'s row k with `reference`'s row `k + offset` (a master that records after
/// stepping is one row ahead) for as many rows as both have, and compares `columns`, which
/// both must hold.
pub fn compare(
    reference: &Trajectory,
    other: &Trajectory,
    offset: usize,
    columns: &[String],
) -> Comparison {
    let rows = other.len().min(reference.len().saturating_sub(offset));
    let mut diffs = Vec::with_capacity(columns.len());
    for name in columns {
        let index = |t: &Trajectory, which: &str| {
            t.column_index(name)
                .unwrap_or_else(|| panic!("the {which} trajectory has no column {name}"))
        };
        let (j_ref, j_other) = (index(reference, "reference"), index(other, "other"));
        let mut diff = ColumnDiff {
            name: name.clone(),
            max_abs: 0.0,
            at_time: f64::NAN,
            differing_rows: 0,
        };
        for k in 0..rows {
            let a = reference.row(k + offset)[j_ref];
            let b = other.row(k)[j_other];
            if a == b || (a.is_nan() && b.is_nan()) {
                continue;
            }
            diff.differing_rows += 1;
            let d = if a.is_nan() || b.is_nan() {
                f64::INFINITY
            } else {
                (a - b).abs()
            };
            if d > diff.max_abs || diff.at_time.is_nan() {
                diff.max_abs = d;
                diff.at_time = reference.times[k + offset];
            }
        }
        diffs.push(diff);
    }
    Comparison {
        rows,
        columns: diffs,
    }
}

/// Checks a master that records after each step (`other`'s row k holds the outputs after step
/// k) against the harness's `reference` (row k + 1), requiring bit-identical values in every
/// row, the last included (the harness's Jacobi run records the outputs of its last step
/// without a final exchange, as these masters do), and returns the comparison it printed.
pub fn assert_identical_after_steps(
    title: &str,
    reference: &Trajectory,
    other: &Trajectory,
) -> Comparison {
    assert_eq!(
        reference.len(),
        other.len() + 1,
        "{title}: the harness has one row per step plus the initial one"
    );
    for k in 0..other.len() {
        assert_eq!(
            other.times[k],
            reference.times[k + 1],
            "{title}: the time after step {k}"
        );
    }
    let comparison = compare(reference, other, 1, &other.names);
    println!("{title}:\n{comparison}");
    assert!(
        comparison.identical(),
        "{title}: expected bit-identical trajectories:\n{comparison}"
    );
    comparison
}

#[cfg(test)]
mod tests {
    use super::*;

    fn trajectory(names: &[&str], rows: &[(f64, &[f64])]) -> Trajectory {
        let mut t = Trajectory {
            names: names.iter().map(|n| n.to_string()).collect(),
            ..Default::default()
        };
        for (time, values) in rows {
            t.times.push(*time);
            t.values.extend_from_slice(values);
        }
        t
    }

    #[test]
    fn columns_are_matched_by_name_and_rows_by_offset() {
        let reference = trajectory(
            &["a", "b"],
            &[
                (0.0, &[1.0, 10.0]),
                (1.0, &[2.0, 20.0]),
                (2.0, &[3.0, 30.5]),
            ],
        );
        // Recorded after stepping and in another column order: row k is reference row k + 1.
        let other = trajectory(&["b", "a"], &[(0.0, &[20.0, 2.0]), (1.0, &[30.0, 3.0])]);
        let c = compare(&reference, &other, 1, &["a".into(), "b".into()]);
        assert_eq!(c.rows, 2);
        assert_eq!(c.columns[0].differing_rows, 0);
        assert_eq!(c.columns[1].max_abs, 0.5);
        assert_eq!(c.columns[1].at_time, 2.0);
        assert_eq!(c.columns[1].differing_rows, 1);
        assert!(!c.identical());
        assert_eq!(c.max_abs(), 0.5);
    }

    #[test]
    fn nan_against_a_number_is_an_infinite_difference_and_nan_against_nan_none() {
        let reference = trajectory(&["a"], &[(0.0, &[f64::NAN]), (1.0, &[f64::NAN])]);
        let other = trajectory(&["a"], &[(0.0, &[f64::NAN]), (1.0, &[1.0])]);
        let c = compare(&reference, &other, 0, &["a".into()]);
        assert_eq!(c.columns[0].differing_rows, 1);
        assert_eq!(c.max_abs(), f64::INFINITY);
    }
}
