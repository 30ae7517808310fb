//! The Real value references a master exchanges, looked up once.
//!
//! A co-simulation master sets and gets the same lists of value references at every step.
//! Each instance keeps the last few lists of its Real sets and of its Real gets (a master
//! may read the feedthrough outputs and then all outputs, say) with what the lookup found
//! for them, so a repeated call compares the list with the kept ones (a memcmp each)
//! and goes straight to the values: no per-reference lookup, and the settable check done
//! once for the whole list. Anything unusual (an unknown reference, a value out of range, a
//! variable not settable in this state, a wrong value count) leaves the decision, and its
//! message, to the layer's generic path, which looks at each reference again.
//!
//! When every element of a list is a field of the model (`Kind::Real::place`), the list
//! also keeps each element's offset in the model's bytes, and a call reads or writes the
//! values there: a load and a store per value instead of a call of its accessor. An element
//! found anywhere else (a computed output, a field behind a pointer) leaves the whole list
//! to the accessors.
//!
//! The lists depend only on the model's static declarations, so nothing makes them stale.
//! The layer supplies the lookup (one entry per FMI 2.0 scalar, one per element of an FMI
//! 3.0 array) and its states as bits (`settable_in`, `state_bit`).
#![allow(unsafe_code)]

use std::mem::{align_of, size_of};

/// Where an element is stored, as a declaration gives it (`Kind::Real::place`): a reference,
/// so that safe code can only point at an `f64` that exists.
pub type Place<M> = Option<fn(&M, usize) -> &f64>;

/// One element a set writes: its setter, the bounds it admits, the states (as the layer's
/// bits) in which it is settable.
pub struct Setter<M> {
    pub set: fn(&mut M, usize, f64),
    pub element: usize,
    pub place: Place<M>,
    /// Where the element is in the model, filled in when the list is kept (the lookup
    /// leaves it 0).
    pub offset: usize,
    /// The closed range of finite values the bounds admit (`Limit::lowest_admitted`).
    pub lowest: f64,
    pub highest: f64,
    pub settable_in: u16,
}

/// One element a get reads.
pub struct Getter<M> {
    pub get: fn(&M, usize) -> f64,
    pub element: usize,
    pub place: Place<M>,
    /// As [`Setter::offset`].
    pub offset: usize,
}

/// The most elements a kept list may have (a co-simulation exchanges tens per call).
pub const MAX_ELEMENTS: usize = 1024;

/// The byte offset of `element` in `model` if it is stored inside the model's own bytes,
/// aligned as an `f64` there.
fn offset_in<M>(model: &M, place: Place<M>, element: usize) -> Option<usize> {
    let base = model as *const M as usize;
    let at = place?(model, element) as *const f64 as usize;
    let offset = at.checked_sub(base)?;
    let inside = offset
        .checked_add(size_of::<f64>())
        .is_some_and(|end| end <= size_of::<M>());
    (inside && at.is_multiple_of(align_of::<f64>())).then_some(offset)
}

/// Where the elements of a kept list are in the model. Kept in the entries themselves
/// (`offset`), so that keeping a list allocates nothing beyond the list.
#[derive(Default, Clone, Copy)]
enum Layout {
    /// One after the other from this offset (a list of whole vectors and neighbouring
    /// fields, the usual case): copied as one block.
    Contiguous(usize),
    /// At the entries' offsets.
    Scattered,
    /// Not all inside the model: through the accessors.
    #[default]
    Accessors,
}

impl Layout {
    /// Fills in each entry's offset and says how the list is laid out.
    fn of<M, E>(
        model: &M,
        entries: &mut [E],
        place: impl Fn(&E) -> (Place<M>, usize),
        offset: impl Fn(&mut E) -> &mut usize,
    ) -> Layout {
        for e in entries.iter_mut() {
            let (at, element) = place(e);
            match offset_in(model, at, element) {
                Some(o) => *offset(e) = o,
                None => return Layout::Accessors,
            }
        }
        let mut offsets = entries.iter_mut().map(|e| *offset(e));
        let Some(first) = offsets.next() else {
            return Layout::Scattered;
        };
        let contiguous = offsets
            .enumerate()
            .all(|(k, o)| o == first + (k + 1) * size_of::<f64>());
        if contiguous {
            Layout::Contiguous(first)
        } else {
            Layout::Scattered
        }
    }
}

/// One kept list of references, with the entries the lookup gave and what the direction
/// derives from them (`X`).
struct List<E, X> {
    vrs: Vec<u32>,
    entries: Vec<E>,
    derived: X,
}

/// How many lists each direction keeps.
const KEPT: usize = 4;

/// The kept lists of one direction, replaced in turn.
struct Lists<E, X> {
    lists: [List<E, X>; KEPT],
    next: usize,
}

impl<E, X: Default> Default for Lists<E, X> {
    fn default() -> Self {
        Lists {
            lists: std::array::from_fn(|_| List {
                vrs: Vec::new(),
                entries: Vec::new(),
                derived: X::default(),
            }),
            next: 0,
        }
    }
}

impl<E, X> Lists<E, X> {
    /// The kept list `vrs`, looked up (and `derive`d) now if it was not kept; `None` (and
    /// nothing kept) when a reference is not found.
    #[inline]
    fn ready(
        &mut self,
        vrs: &[u32],
        lookup: impl FnMut(u32, &mut Vec<E>) -> bool,
        derive: impl FnOnce(&mut [E]) -> X,
    ) -> Option<&List<E, X>> {
        match self.lists.iter().position(|list| list.vrs == vrs) {
            Some(i) => Some(&self.lists[i]),
            None => self.prepare(vrs, lookup, derive),
        }
    }

    #[cold]
    fn prepare(
        &mut self,
        vrs: &[u32],
        mut lookup: impl FnMut(u32, &mut Vec<E>) -> bool,
        derive: impl FnOnce(&mut [E]) -> X,
    ) -> Option<&List<E, X>> {
        let list = &mut self.lists[self.next];
        list.vrs.clear();
        list.entries.clear();
        // A longer list is served by the generic path: an instance keeps no more than this
        // for a master that once passed a million references.
        let found = vrs.len() <= MAX_ELEMENTS
            && vrs
                .iter()
                .all(|&vr| lookup(vr, &mut list.entries) && list.entries.len() <= MAX_ELEMENTS);
        if !found {
            list.entries.clear();
            list.entries.shrink_to(MAX_ELEMENTS);
            return None;
        }
        list.vrs.extend_from_slice(vrs);
        list.derived = derive(&mut list.entries);
        self.next = (self.next + 1) % KEPT;
        Some(list)
    }
}

/// What a kept set list derives: the states in which every element of it is settable,
/// and where the elements are.
#[derive(Default)]
struct SetPlan {
    settable_in: u16,
    /// Whether an element has a bound narrower than the doubles' own range (else the
    /// check is one of finiteness).
    bounded: bool,
    layout: Layout,
}

/// The last lists of a Real set.
pub struct PreparedSet<M> {
    lists: Lists<Setter<M>, SetPlan>,
}

impl<M> Default for PreparedSet<M> {
    fn default() -> Self {
        PreparedSet {
            lists: Lists::default(),
        }
    }
}

impl<M> PreparedSet<M> {
    /// Writes `values` to the references `vrs` if each is found by `lookup` (which appends
    /// its elements, or says false), the count matches, every element is settable in the
    /// state `state_bit` and admits its value; says whether it wrote. False leaves `model`
    /// as it was, for the generic path to refuse with a reason.
    #[inline]
    pub fn write(
        &mut self,
        vrs: &[u32],
        values: &[f64],
        model: &mut M,
        state_bit: u16,
        lookup: impl FnMut(u32, &mut Vec<Setter<M>>) -> bool,
    ) -> bool {
        let shown: &M = model;
        let plan = |entries: &mut [Setter<M>]| SetPlan {
            settable_in: entries.iter().fold(u16::MAX, |all, e| all & e.settable_in),
            bounded: entries
                .iter()
                .any(|e| e.lowest > -f64::MAX || e.highest < f64::MAX),
            layout: Layout::of(shown, entries, |e| (e.place, e.element), |e| &mut e.offset),
        };
        let Some(list) = self.lists.ready(vrs, lookup, plan) else {
            return false;
        };
        let (plan, entries) = (&list.derived, &list.entries);
        if plan.settable_in & state_bit == 0 || entries.len() != values.len() {
            return false;
        }
        // Checked before anything is written, so a refused call changes nothing. The
        // comparisons are combined without branching: a refusal is the rare case.
        let admitted = if plan.bounded {
            entries
                .iter()
                .zip(values)
                .fold(true, |ok, (e, &v)| ok & (v >= e.lowest) & (v <= e.highest))
        } else {
            // Within [-MAX, MAX] is finite: `v - v` is 0 exactly then (NaN otherwise).
            #[allow(clippy::eq_op)]
            values.iter().fold(true, |ok, &v| ok & (v - v == 0.0))
        };
        if !admitted {
            return false;
        }
        let base = (model as *mut M).cast::<u8>();
        match plan.layout {
            // SAFETY (both arms): each offset is where an element's f64 lies in every `M`
            // (a field of the model, found inside its bytes and aligned when the list was
            // kept; a contiguous run was found element by element), and `model` is
            // borrowed mutably for this write.
            Layout::Contiguous(first) => unsafe {
                let to = base.add(first).cast::<f64>();
                std::ptr::copy_nonoverlapping(values.as_ptr(), to, values.len());
            },
            Layout::Scattered => {
                for (e, &value) in entries.iter().zip(values) {
                    unsafe { base.add(e.offset).cast::<f64>().write(value) };
                }
            }
            Layout::Accessors => {
                for (e, &value) in entries.iter().zip(values) {
                    (e.set)(model, e.element, value);
                }
            }
        }
        true
    }
}

/// The last lists of a Real get; each derives where its elements are.
pub struct PreparedGet<M> {
    lists: Lists<Getter<M>, Layout>,
}

impl<M> Default for PreparedGet<M> {
    fn default() -> Self {
        PreparedGet {
            lists: Lists::default(),
        }
    }
}

impl<M> PreparedGet<M> {
    /// Reads the references `vrs` into `values` if each is found by `lookup` and the count
    /// matches, and says whether it did; false writes nothing, for the generic path to
    /// refuse with a reason.
    #[inline]
    pub fn read(
        &mut self,
        vrs: &[u32],
        values: &mut [f64],
        model: &M,
        lookup: impl FnMut(u32, &mut Vec<Getter<M>>) -> bool,
    ) -> bool {
        let plan = |entries: &mut [Getter<M>]| {
            Layout::of(model, entries, |e| (e.place, e.element), |e| &mut e.offset)
        };
        let Some(list) = self.lists.ready(vrs, lookup, plan) else {
            return false;
        };
        if list.entries.len() != values.len() {
            return false;
        }
        let base = (model as *const M).cast::<u8>();
        match list.derived {
            // SAFETY (both arms): as in `PreparedSet::write`, for a shared borrow.
            Layout::Contiguous(first) => unsafe {
                let from = base.add(first).cast::<f64>();
                std::ptr::copy_nonoverlapping(from, values.as_mut_ptr(), values.len());
            },
            Layout::Scattered => {
                for (e, value) in list.entries.iter().zip(values) {
                    *value = unsafe { base.add(e.offset).cast::<f64>().read() };
                }
            }
            Layout::Accessors => {
                for (e, value) in list.entries.iter().zip(values) {
                    *value = (e.get)(model, e.element);
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type M = [f64; 4];
    const INIT: u16 = 1;
    const RUNNING: u16 = 2;

    /// vr 0: settable only initializing; vr 1: a two-element array (elements 1, 2), element
    /// 2 bounded to [0, 1]; vr 3: not settable. Anything else is unknown.
    fn setters(vr: u32, out: &mut Vec<Setter<M>>) -> bool {
        let setter = |element, lowest, highest, settable_in| Setter {
            set: |m: &mut M, i, v| m[i] = v,
            element,
            place: Some(|m: &M, i| &m[i]),
            offset: 0,
            lowest,
            highest,
            settable_in,
        };
        match vr {
            0 => out.push(setter(0, -f64::MAX, f64::MAX, INIT)),
            1 => out.extend([
                setter(1, -f64::MAX, f64::MAX, INIT | RUNNING),
                setter(2, 0.0, 1.0, INIT | RUNNING),
            ]),
            _ => return false,
        }
        true
    }

    #[test]
    fn a_repeated_list_writes_what_the_checks_admit_and_nothing_else() {
        let mut set = PreparedSet::default();
        let mut model: M = [0.0; 4];
        assert!(set.write(&[1, 0], &[7.0, 0.5, 3.0], &mut model, INIT, setters));
        assert_eq!(model, [3.0, 7.0, 0.5, 0.0]);
        // Same list: out of bounds, non-finite, a wrong count, or a state where vr 0 is
        // not settable.
        for (values, state) in [
            (&[1.0, 1.5, 1.0][..], INIT),
            (&[1.0, -0.1, 1.0], INIT),
            (&[f64::NAN, 0.5, 1.0], INIT),
            (&[1.0, 0.5, f64::NEG_INFINITY], INIT),
            (&[1.0, 0.5], INIT),
            (&[1.0, 0.5, 1.0], RUNNING),
        ] {
            assert!(
                !set.write(&[1, 0], values, &mut model, state, setters),
                "{values:?} in state {state}"
            );
            assert_eq!(model, [3.0, 7.0, 0.5, 0.0], "{values:?} in state {state}");
        }
        // Another list is looked up afresh; an unknown reference is not prepared.
        assert!(set.write(&[1], &[4.0, 1.0], &mut model, RUNNING, setters));
        assert_eq!(model, [3.0, 4.0, 1.0, 0.0]);
        assert!(!set.write(&[1, 3], &[5.0, 0.0, 5.0], &mut model, INIT, setters));
        assert_eq!(model, [3.0, 4.0, 1.0, 0.0]);
    }

    #[test]
    fn a_list_without_bounds_admits_every_finite_value_and_nothing_else() {
        let mut set = PreparedSet::default();
        let mut model: M = [0.0; 4];
        for v in [f64::MAX, -f64::MAX, f64::MIN_POSITIVE, -0.0, 1e-310] {
            assert!(set.write(&[0], &[v], &mut model, INIT, setters), "{v}");
            assert_eq!(model[0].to_bits(), v.to_bits());
        }
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(!set.write(&[0], &[v], &mut model, INIT, setters), "{v}");
            assert_eq!(model[0], 1e-310);
        }
    }

    /// Lists taking turns (the feedthrough outputs, then all of them) are each looked up
    /// once while no more than `KEPT` alternate; more still give the right values.
    #[test]
    fn alternating_lists_are_looked_up_once_each() {
        let model: M = [1.0, 2.0, 3.0, 4.0];
        for lists in [2, KEPT, KEPT + 1] {
            let mut get = PreparedGet::default();
            let mut lookups = 0;
            for round in 0..10 {
                for first in 0..lists {
                    let vrs = [first as u32, 3];
                    let mut values = [0.0; 2];
                    let counting = |vr: u32, out: &mut Vec<Getter<M>>| {
                        lookups += 1;
                        out.push(Getter {
                            get: |m: &M, i| m[i],
                            element: vr as usize % 4,
                            place: None,
                            offset: 0,
                        });
                        true
                    };
                    assert!(get.read(&vrs, &mut values, &model, counting));
                    assert_eq!(values, [model[first % 4], 4.0], "round {round}");
                }
            }
            let expected = if lists <= KEPT {
                2 * lists
            } else {
                2 * lists * 10
            };
            assert_eq!(lookups, expected, "{lists} lists");
        }
    }

    #[test]
    fn a_list_too_long_to_keep_is_left_to_the_generic_path() {
        let mut set = PreparedSet::default();
        let mut model: M = [0.0; 4];
        // vr 1 has two elements.
        let vrs = vec![1; MAX_ELEMENTS / 2];
        let values = vec![0.5; MAX_ELEMENTS];
        assert!(set.write(&vrs, &values, &mut model, RUNNING, setters));
        let vrs = vec![1; MAX_ELEMENTS / 2 + 1];
        let values = vec![0.25; MAX_ELEMENTS + 2];
        assert!(!set.write(&vrs, &values, &mut model, RUNNING, setters));
        assert_eq!(model, [0.0, 0.5, 0.5, 0.0]);
        assert!(set
            .lists
            .lists
            .iter()
            .all(|l| l.entries.capacity() <= MAX_ELEMENTS));
        // More references than elements kept: refused before any lookup.
        let vrs = vec![9; MAX_ELEMENTS + 1];
        let mut looked_up = 0;
        let count = |_: u32, _: &mut Vec<Setter<M>>| {
            looked_up += 1;
            false
        };
        assert!(!set.write(&vrs, &values, &mut model, RUNNING, count));
        assert_eq!(looked_up, 0);
    }

    #[test]
    fn a_prepared_read_gives_what_each_accessor_gives() {
        let getters = |vr: u32, out: &mut Vec<Getter<M>>| {
            let ok = vr < 4;
            if ok {
                out.push(Getter {
                    get: |m: &M, i| m[i] * 10.0,
                    element: vr as usize,
                    place: None,
                    offset: 0,
                });
            }
            ok
        };
        let mut get = PreparedGet::default();
        let model: M = [1.0, 2.0, 3.0, 4.0];
        let mut values = [0.0; 3];
        for vrs in [[3, 0, 3], [2, 1, 0], [2, 1, 0]] {
            assert!(get.read(&vrs, &mut values, &model, getters));
            assert_eq!(values, vrs.map(|vr| 10.0 * model[vr as usize]));
        }
        assert!(!get.read(&[0, 4, 1], &mut values, &model, getters));
        assert!(!get.read(&[0, 1], &mut values, &model, getters), "count");
    }

    /// Elements stored in the model are read and written in place; a list with one element
    /// stored elsewhere goes through the accessors, whole.
    #[test]
    fn stored_elements_are_exchanged_in_place_and_others_through_their_accessors() {
        static ELSEWHERE: f64 = 0.0;
        let getter = |element, place: Place<M>| Getter {
            get: |m: &M, i| m[i] * 10.0,
            element,
            place,
            offset: 0,
        };
        let inside: Place<M> = Some(|m, i| &m[i]);
        let outside: Place<M> = Some(|_, _| &ELSEWHERE);
        let model: M = [1.0, 2.0, 3.0, 4.0];
        let mut get = PreparedGet::default();
        let mut values = [0.0; 2];
        // The accessor multiplies by 10: a value read in place is not.
        assert!(get.read(&[3, 0], &mut values, &model, |vr, out| {
            out.push(getter(vr as usize, inside));
            true
        }));
        assert_eq!(values, [4.0, 1.0]);
        assert!(get.read(&[2, 1], &mut values, &model, |vr, out| {
            out.push(getter(vr as usize, if vr == 1 { outside } else { inside }));
            true
        }));
        assert_eq!(values, [30.0, 20.0]);

        let mut set = PreparedSet::default();
        let mut model: M = [0.0; 4];
        assert!(set.write(&[1], &[7.0, 0.5], &mut model, INIT, setters));
        assert_eq!(model, [0.0, 7.0, 0.5, 0.0]);
        let elsewhere = |vr: u32, out: &mut Vec<Setter<M>>| {
            out.push(Setter {
                set: |m: &mut M, i, v| m[i] = -v,
                element: vr as usize,
                place: outside,
                offset: 0,
                lowest: -f64::MAX,
                highest: f64::MAX,
                settable_in: INIT,
            });
            true
        };
        assert!(set.write(&[3], &[2.0], &mut model, INIT, elsewhere));
        assert_eq!(model, [0.0, 7.0, 0.5, -2.0]);
        assert_eq!(ELSEWHERE, 0.0);
    }
}
