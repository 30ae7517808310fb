//! Requirements of a run continued from a saved one (`master/saved.rs`): a requirement is
//! judged at the start of the run over rows up to its horizon, so the continued run takes
//! the rows the saved run kept before the saved point and judges exactly as the
//! uninterrupted run would.
use super::Kept;
use crate::master::SavedRows;

impl Kept {
    /// The rows kept before `time` (the saved point), to go into the saved run.
    pub fn rows_before(&self, time: f64) -> SavedRows {
        let width = self.rows.names.len();
        let count = self.rows.times.iter().take_while(|&&t| t < time).count();
        SavedRows {
            names: self.rows.names.clone(),
            times: self.rows.times[..count].to_vec(),
            values: self.rows.values[..count * width].to_vec(),
        }
    }

    /// Continues from the rows a saved run kept, before any row of this run; refused when
    /// they are not of these requirements' columns.
    pub fn continue_from(&mut self, saved: &SavedRows) -> Result<(), String> {
        if saved.names != self.rows.names {
            return Err(format!(
                "it was saved with requirements reading {:?}; this run's read {:?}",
                saved.names, self.rows.names
            ));
        }
        let (Some(&first), Some(&last)) = (saved.times.first(), saved.times.last()) else {
            return Ok(());
        };
        self.rows.times.clone_from(&saved.times);
        self.rows.values.clone_from(&saved.values);
        self.recorded_s = Some((first, last));
        self.until_s = self.until_after(first);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::master::Recorder;
    use crate::requirements::from_toml;

    fn fly(kept: &mut Kept, steps: std::ops::Range<u32>) {
        for k in steps {
            let t = f64::from(k) * 0.1;
            kept.record(t, &[libm::sin(t * 0.7), 7.0]);
        }
    }

    #[test]
    fn a_continued_run_judges_its_requirements_as_the_uninterrupted_one() {
        // GIVEN a requirement early in the run and one late in it
        let requirements = from_toml(
            r#"
            [[requirement]]
            name = "early"
            formula = "always [1, 2] a.x < 0.9"
            [[requirement]]
            name = "late"
            formula = "eventually [5, 8] a.x > 0.99"
            "#,
        )
        .unwrap();
        let columns = ["a.x".to_owned(), "b.y".to_owned()];
        let mut whole = Kept::new(&requirements, &columns);
        fly(&mut whole, 0..100);
        // WHEN a run saved at t = 4 s (its rows before 4 s kept) is continued
        let mut saved = Kept::new(&requirements, &columns);
        fly(&mut saved, 0..41);
        let rows = saved.rows_before(4.0);
        assert_eq!(rows.times.len(), 40);
        let mut continued = Kept::new(&requirements, &columns);
        continued.continue_from(&rows).unwrap();
        fly(&mut continued, 40..100);
        // THEN it judges as the uninterrupted run, which the rows after 4 s alone do not
        assert_eq!(continued.judge(&requirements), whole.judge(&requirements));
        let mut alone = Kept::new(&requirements, &columns);
        fly(&mut alone, 40..100);
        assert_ne!(alone.judge(&requirements), whole.judge(&requirements));
        // AND rows of other requirements' columns are refused
        let other =
            from_toml("[[requirement]]\nname = \"b\"\nformula = \"always [0, 1] b.y > 0\"\n")
                .unwrap();
        let error = Kept::new(&other, &columns)
            .continue_from(&rows)
            .unwrap_err();
        assert!(error.contains("a.x"), "{error}");
    }
}
