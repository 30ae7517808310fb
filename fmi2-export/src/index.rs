//! Value reference -> table row, one lookup per FMI base type. Integer and Enumeration
//! share one value-reference space, as they share `fmi2Get/SetInteger`.
//!
//! This sits on the hot path of every `fmi2Get*`/`fmi2Set*` (a master exchanges a dozen
//! values per variable per step), so the usual case is a direct array access: value
//! references are small integers chosen by the model author, and a table indexed by them
//! costs a few bytes per unused slot. Sparse references (a model numbering its variables
//! by hash, say) fall back to a binary search so that memory stays proportional to the
//! table.
//!
//! Reals, the bulk of what a co-simulation exchanges, also get a [`RealSlot`] each: their
//! accessors and the value checks in a form that needs no matching on the table row.
use crate::state::{State, StateMask};
use crate::variable::{Access, Limit, Variable};
use fmi_export::setters::settable;

/// The four base types of the C API.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BaseType {
    Real,
    Integer,
    Boolean,
    String,
}

impl BaseType {
    pub fn of<M>(access: &Access<M>) -> BaseType {
        match access {
            Access::Real { .. } => BaseType::Real,
            Access::Integer { .. } | Access::Enumeration { .. } => BaseType::Integer,
            Access::Boolean { .. } => BaseType::Boolean,
            Access::String { .. } => BaseType::String,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            BaseType::Real => "Real",
            BaseType::Integer => "Integer",
            BaseType::Boolean => "Boolean",
            BaseType::String => "String",
        }
    }
}

/// A dense table is used while it has at most this many slots per variable of its type
/// (plus a fixed allowance for small tables), i.e. while it is a few times larger than
/// the sorted list it replaces.
const DENSE_SLOTS_PER_VARIABLE: usize = 8;
const DENSE_SLOTS_ALLOWANCE: usize = 256;

/// Marks an unused slot of a dense table.
const NO_ROW: u32 = u32::MAX;

#[derive(Debug)]
enum Lookup {
    /// `rows[vr]` is the row of `vr`, or `NO_ROW`.
    Dense(Box<[u32]>),
    /// `(vr, row)` sorted by `vr`.
    Sorted(Box<[(u32, u32)]>),
}

impl Lookup {
    fn new(mut pairs: Vec<(u32, u32)>) -> Lookup {
        // A table with a reference used twice is refused by `check_table`; should one get
        // here anyway, the first row declared wins, as it would in a linear search.
        pairs.sort_by_key(|&(vr, row)| (vr, row));
        pairs.dedup_by_key(|&mut (vr, _)| vr);
        let slots = pairs.last().map_or(0, |&(vr, _)| vr as usize + 1);
        if slots <= DENSE_SLOTS_PER_VARIABLE * pairs.len() + DENSE_SLOTS_ALLOWANCE {
            let mut rows = vec![NO_ROW; slots].into_boxed_slice();
            for (vr, row) in pairs {
                rows[vr as usize] = row;
            }
            Lookup::Dense(rows)
        } else {
            Lookup::Sorted(pairs.into_boxed_slice())
        }
    }

    #[inline]
    fn row(&self, vr: u32) -> Option<usize> {
        match self {
            Lookup::Dense(rows) => match rows.get(vr as usize) {
                Some(&row) if row != NO_ROW => Some(row as usize),
                _ => None,
            },
            Lookup::Sorted(pairs) => pairs
                .binary_search_by_key(&vr, |&(v, _)| v)
                .ok()
                .map(|i| pairs[i].1 as usize),
        }
    }
}

/// What `fmi2GetReal` and `fmi2SetReal` need of one Real variable, taken from its table row.
pub struct RealSlot<M> {
    /// The row in the table, for the messages of a refused value.
    pub row: usize,
    pub get: fn(&M, usize) -> f64,
    pub set: Option<fn(&mut M, usize, f64)>,
    /// The element of the declaration, passed to `get` and `set`.
    pub element: usize,
    pub place: fmi_export::prepared::Place<M>,
    /// The lowest and highest finite values the declared bounds admit (an exclusive bound
    /// moved one ulp inwards; no bound: the largest finite magnitude); NaN for a NaN bound.
    pub lowest: f64,
    pub highest: f64,
    /// The states in which [`check_settable`] accepts the variable.
    pub settable_in: StateMask,
}

impl<M> RealSlot<M> {
    fn new(row: usize, var: &Variable<M>) -> Option<RealSlot<M>> {
        let Access::Real {
            min,
            max,
            get,
            set,
            element,
            place,
            ..
        } = var.access
        else {
            return None;
        };
        let settable_in: Vec<State> = State::ALL
            .into_iter()
            .filter(|&state| settable(var.causality, var.variability, state).is_ok())
            .collect();
        Some(RealSlot {
            row,
            get,
            set,
            element,
            place,
            lowest: Limit::lowest_admitted(min),
            highest: Limit::highest_admitted(max),
            settable_in: StateMask::of(&settable_in),
        })
    }

    /// Whether `value` may be set in `state`: exactly when [`settable`] and
    /// `real_in_range` accept it, for bounds that are not NaN (a NaN bound sends every value
    /// to those checks, which then decide).
    #[inline]
    pub fn accepts(&self, value: f64, state: State) -> bool {
        // Two comparisons: the bounds are folded into the closed range of finite values
        // they admit, so infinities and NaN fail them too.
        self.settable_in.contains(state) && value >= self.lowest && value <= self.highest
    }

    #[inline]
    pub fn read(&self, model: &M) -> f64 {
        (self.get)(model, self.element)
    }
}

/// Lookup built once per instance from the static table.
pub struct VariableIndex<M> {
    /// Maps to table rows, except `Real`, which maps to positions in `reals`.
    by_type: [Lookup; 4],
    reals: Box<[RealSlot<M>]>,
}

impl<M> VariableIndex<M> {
    pub fn new(table: &[Variable<M>]) -> VariableIndex<M> {
        // Rows are stored as u32; no table comes near 4 billion variables.
        assert!(u32::try_from(table.len()).is_ok_and(|n| n < NO_ROW));
        let mut pairs: [Vec<(u32, u32)>; 4] = Default::default();
        let mut reals = Vec::new();
        for (row, var) in table.iter().enumerate() {
            let base = BaseType::of(&var.access);
            let entry = match RealSlot::new(row, var) {
                Some(slot) => {
                    reals.push(slot);
                    reals.len() - 1
                }
                None => row,
            };
            pairs[base as usize].push((var.value_reference, entry as u32));
        }
        VariableIndex {
            by_type: pairs.map(Lookup::new),
            reals: reals.into_boxed_slice(),
        }
    }

    /// The table row of `vr` among the variables of `base_type`.
    #[inline]
    pub fn row(&self, base_type: BaseType, vr: u32) -> Option<usize> {
        let entry = self.by_type[base_type as usize].row(vr)?;
        Some(match base_type {
            BaseType::Real => self.reals[entry].row,
            _ => entry,
        })
    }

    /// The Real variable `vr`.
    #[inline]
    pub fn real(&self, vr: u32) -> Option<&RealSlot<M>> {
        let entry = self.by_type[BaseType::Real as usize].row(vr)?;
        self.reals.get(entry)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every reference of every type against a linear search of the pairs, for a dense
    /// and a sparse set of references.
    #[test]
    fn lookup_agrees_with_a_linear_search() {
        let dense: Vec<(u32, u32)> = [7, 0, 3, 200, 12, 5, 1].into_iter().zip(0..).collect();
        let sparse: Vec<(u32, u32)> = [4_000_000_000, 17, 1 << 20, 0, 99_999]
            .into_iter()
            .zip(10..)
            .collect();
        for (pairs, expect_dense) in [(dense, true), (sparse, false)] {
            let lookup = Lookup::new(pairs.clone());
            assert_eq!(matches!(lookup, Lookup::Dense(_)), expect_dense);
            let probes = pairs
                .iter()
                .flat_map(|&(vr, _)| [vr, vr.wrapping_add(1), vr.wrapping_sub(1)])
                .chain([0, 2, 1000, u32::MAX - 1, u32::MAX]);
            for vr in probes {
                let linear = pairs
                    .iter()
                    .find(|&&(v, _)| v == vr)
                    .map(|&(_, r)| r as usize);
                assert_eq!(lookup.row(vr), linear, "vr {vr}");
            }
        }
    }

    /// `accepts` against the checks it stands in for, over every state, a grid of
    /// variables (causality, variability, bounds) and awkward values.
    #[test]
    fn a_real_slot_accepts_exactly_what_the_checks_accept() {
        use crate::variable::{Causality, Variability};
        use fmi_export::setters::real_in_range;
        use Limit::{Exclusive, Inclusive};
        let bounds = [
            (None, None),
            (Some(Inclusive(-1.0)), Some(Inclusive(2.0))),
            (Some(Inclusive(0.0)), None),
            (None, Some(Inclusive(0.0))),
            (Some(Exclusive(0.0)), None),
            (Some(Exclusive(-1.0)), Some(Exclusive(2.0))),
            (Some(Inclusive(f64::NAN)), Some(Inclusive(1.0))),
            (
                Some(Inclusive(f64::NEG_INFINITY)),
                Some(Inclusive(f64::INFINITY)),
            ),
            (
                Some(Exclusive(f64::NEG_INFINITY)),
                Some(Exclusive(f64::MAX)),
            ),
            (Some(Exclusive(-f64::MAX)), Some(Exclusive(0.0))),
        ];
        let values = [
            0.0,
            -0.0,
            -1.0,
            2.0,
            -1.0000000000000002,
            2.0000000000000004,
            1e308,
            -1e308,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE,
            f64::MAX,
            -f64::MAX,
            5e-324,
            -5e-324,
        ];
        let mut checked = 0;
        for causality in [
            Causality::Input,
            Causality::Parameter,
            Causality::Output,
            Causality::Local,
            Causality::CalculatedParameter,
            Causality::Independent,
        ] {
            for variability in [
                Variability::Constant,
                Variability::Fixed,
                Variability::Tunable,
                Variability::Discrete,
                Variability::Continuous,
            ] {
                for (min, max) in bounds {
                    let var: Variable<()> = Variable {
                        value_reference: 0,
                        causality,
                        variability,
                        initial: None,
                        unit: None,
                        declaration: 0,
                        access: Access::Real {
                            start: None,
                            min,
                            max,
                            get: |_, _| 0.0,
                            set: Some(|_, _, _| {}),
                            element: 0,
                            place: None,
                        },
                    };
                    let slot = RealSlot::new(0, &var).unwrap();
                    for state in State::ALL {
                        for value in values {
                            let checks = settable(causality, variability, state).is_ok()
                                && real_in_range(value, min, max);
                            if !(min.is_some_and(|m| m.value().is_nan()) && checks) {
                                assert_eq!(
                                    slot.accepts(value, state),
                                    checks,
                                    "{causality:?} {variability:?} [{min:?}, {max:?}] \
                                     {state:?} {value}"
                                );
                            }
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert_eq!(
            checked,
            6 * 5 * bounds.len() * State::ALL.len() * values.len()
        );
    }

    #[test]
    fn only_reals_get_a_real_slot_and_rows_stay_rows() {
        let row = |vr, access| Variable::<()> {
            value_reference: vr,
            causality: crate::variable::Causality::Input,
            variability: crate::variable::Variability::Discrete,
            initial: None,
            unit: None,
            declaration: 0,
            access,
        };
        let real = || Access::Real {
            start: None,
            min: None,
            max: None,
            get: |_, _| 1.5,
            set: None,
            element: 0,
            place: None,
        };
        let integer = || Access::Integer {
            start: None,
            min: None,
            max: None,
            get: |_| 3,
            set: None,
        };
        // Integer vr 1 at row 0, Reals vr 1 and 9 at rows 1 and 2.
        let table = [row(1, integer()), row(1, real()), row(9, real())];
        let index = VariableIndex::new(&table);
        assert_eq!(index.row(BaseType::Integer, 1), Some(0));
        assert_eq!(index.row(BaseType::Real, 1), Some(1));
        assert_eq!(index.row(BaseType::Real, 9), Some(2));
        assert_eq!(index.real(9).map(|s| s.row), Some(2));
        assert_eq!(index.real(1).map(|s| s.read(&())), Some(1.5));
        assert!(index.real(0).is_none() && index.real(2).is_none());
        assert_eq!(index.row(BaseType::Boolean, 1), None);
    }

    #[test]
    fn a_repeated_reference_finds_the_first_row() {
        let lookup = Lookup::new(vec![(5, 3), (5, 1), (2, 0)]);
        assert_eq!(lookup.row(5), Some(1));
        assert_eq!(lookup.row(2), Some(0));
        assert_eq!(Lookup::new(Vec::new()).row(0), None);
    }
}
