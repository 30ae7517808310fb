//! Values that are not numbers. An FMU may return NaN or an infinity with status OK, and no
//! status would then tell the master: a run that kept going would record rows of `nan` and
//! end green. So every Real the master reads after initialization (an output exchanged or
//! recorded, a recorded calculated parameter, a final value) is checked where it lands in the
//! exchange buffers, by one branch-free pass per read; which variable it was is worked out
//! only when that pass fails.
//!
//! The run stops at the row of the communication point the value was read for: that row is
//! still recorded (so the value is seen in the results), no step is taken after it. Variables
//! listed in the system's `allow_non_finite` (an FMU that means "no value" by NaN) are
//! reported by a warning instead, once per variable and run, with the time of their first row.
use crate::system::SystemDescription;
use fmi_import::{Fmu, VariableKind};

/// A value the run may not go on with: the first one a read found, named.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct NonFinite {
    pub instance: String,
    pub variable: String,
    pub time: f64,
    pub value: f64,
}

/// Whether every value is finite. A fold of `&` over `is_finite` has no early exit, so the
/// compiler turns it into a few vector compares: on the hot path this costs less than the
/// branch per value of `all`.
#[inline]
pub(super) fn all_finite(values: &[f64]) -> bool {
    values.iter().fold(true, |ok, x| ok & x.is_finite())
}

/// What the master knows to tell a value that is not a number from one it may ignore.
#[derive(Debug, Default)]
pub(super) struct Check {
    /// Off in Initialization Mode: FMI lets outputs be provisional until it ends, and the
    /// values a run acts on are those read after it.
    pub(super) armed: bool,
    /// Per unit: the Real variables (value reference, name) the master reads, to name one.
    names: Vec<Vec<(u32, String)>>,
    /// Per unit: the value references of the Real variables allowed to be non-finite.
    allowed: Vec<Vec<u32>>,
    /// (unit, value reference) of the allowed variables already reported this run.
    warned: Vec<(usize, u32)>,
    /// Non-finite values read since the last row: (unit, value reference, value).
    found: Vec<(usize, u32, f64)>,
}

impl Check {
    /// Resolves the system's `allow_non_finite` against the FMUs, adding a problem (with a
    /// suggestion for a misspelt name) for each name that does not resolve.
    pub(super) fn new(
        system: &SystemDescription,
        fmus: &[Fmu],
        problems: &mut Vec<String>,
    ) -> Self {
        let mut allowed = vec![Vec::new(); fmus.len()];
        for path in &system.allow_non_finite {
            let mut own = Vec::new();
            for port in super::resolve::ports(system, fmus, path, &[], &mut own) {
                if port.kind == VariableKind::Real {
                    allowed[port.instance].push(port.value_reference);
                }
            }
            problems.extend(own.into_iter().map(|p| format!("allow_non_finite: {p}")));
        }
        Self {
            names: vec![Vec::new(); fmus.len()],
            allowed,
            ..Self::default()
        }
    }

    /// Names a Real variable the master reads; the first name of a value reference stays.
    pub(super) fn name(&mut self, unit: usize, kind: VariableKind, vr: u32, name: &str) {
        let names = &mut self.names[unit];
        if kind == VariableKind::Real && !names.iter().any(|(v, _)| *v == vr) {
            names.push((vr, name.to_owned()));
        }
    }

    /// Before a run: disarmed until initialization ends, nothing found or reported yet.
    pub(super) fn reset(&mut self) {
        self.armed = false;
        self.warned.clear();
        self.found.clear();
    }

    /// Notes the values of `values` (read from `vrs` of `unit`) that are not finite; call it
    /// when [`all_finite`] failed.
    #[cold]
    pub(super) fn note(&mut self, unit: usize, vrs: &[u32], values: &[f64]) {
        for (&vr, &value) in vrs.iter().zip(values) {
            if !value.is_finite() {
                self.found.push((unit, vr, value));
            }
        }
    }

    /// Whether a value read since the last row was not finite.
    #[inline]
    pub(super) fn pending(&self) -> bool {
        !self.found.is_empty()
    }

    /// At the row of `time`: warns about the allowed variables not reported yet this run and
    /// returns the error for the first value that is not allowed.
    #[cold]
    /// Notes the Float32 outputs of unit `u` that are not numbers, as the Real ones are
    /// noted (they travel as words: `words` and `vrs` are the word buffer, `float32` the
    /// slots of the Float32 outputs in it).
    #[inline(never)]
    pub(super) fn note_float32(&mut self, float32: &[usize], words: &[u64], vrs: &[u32], u: usize) {
        for &slot in float32 {
            let value = f64::from_bits(words[slot]);
            if !value.is_finite() {
                self.note(u, &[vrs[slot]], &[value]);
            }
        }
    }

    pub(super) fn settle(&mut self, time: f64, units: &[String]) -> Result<(), NonFinite> {
        let mut error = None;
        for (unit, vr, value) in std::mem::take(&mut self.found) {
            let variable = self.names[unit]
                .iter()
                .find(|(v, _)| *v == vr)
                .map_or_else(|| format!("value reference {vr}"), |(_, n)| n.clone());
            if !self.allowed[unit].contains(&vr) {
                error.get_or_insert(NonFinite {
                    instance: units[unit].clone(),
                    variable,
                    time,
                    value,
                });
            } else if !self.warned.contains(&(unit, vr)) {
                self.warned.push((unit, vr));
                log::warn!(
                    "'{}.{variable}' is {value} at t = {time}; allow_non_finite lets the run \
                     go on (said once per run)",
                    units[unit]
                );
            }
        }
        error.map_or(Ok(()), Err)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_nan_and_the_infinities_are_not_finite() {
        assert!(all_finite(&[]));
        assert!(all_finite(&[
            0.0,
            -0.0,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            -1e300
        ]));
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -f64::NAN] {
            let mut values = vec![1.0; 37];
            values[29] = bad;
            assert!(!all_finite(&values), "{bad}");
        }
    }

    #[test]
    fn the_first_value_not_allowed_is_the_error_and_an_allowed_one_warns_once() {
        let mut check = Check {
            names: vec![vec![(3, "y".into()), (4, "w".into())]],
            allowed: vec![vec![4]],
            ..Check::default()
        };
        let units = ["src".to_owned()];
        check.note(0, &[3, 4, 5], &[1.0, f64::NAN, 2.0]);
        assert!(check.pending());
        assert!(check.settle(0.25, &units).is_ok());
        assert_eq!(check.warned, [(0, 4)]);
        check.note(0, &[4, 3], &[f64::NAN, f64::NEG_INFINITY]);
        match check.settle(0.5, &units) {
            Err(NonFinite {
                instance,
                variable,
                time,
                value,
            }) => {
                assert_eq!(
                    (instance.as_str(), variable.as_str(), time),
                    ("src", "y", 0.5)
                );
                assert_eq!(value, f64::NEG_INFINITY);
            }
            other => panic!("{other:?}"),
        }
        assert!(!check.pending());
        assert_eq!(check.warned, [(0, 4)]);
    }
}
