//! The Real exchange of an instance: every Real element found by its value reference in
//! one array access, whatever order, grouping or repetition the master lists them in.
//!
//! A co-simulation master sets and gets Reals at every step, and each master lists them its
//! own way: in its connection table's order, sorted, one per call, rebuilt every step. So
//! nothing here depends on the list: each instance keeps one table indexed by value
//! reference (built once, at the first Real get or set it cannot serve, from the model's
//! static declarations), whose entry for a reference gives its elements (one per FMI 2.0
//! scalar, one per element of an FMI 3.0 array) with everything a value needs on its way:
//! where the element is stored in the model (an offset in its bytes, so a value is one load
//! or store; an element that is no field of the model goes through its accessor), the closed
//! range of values its bounds admit, and the states in which it is settable.
//!
//! A call whose references are all stored in the model's bytes is served by loops with no
//! call in them, so that their values stay in registers; a call with any other goes to loops
//! that call the accessors, out of line.
//!
//! Anything unusual (an unknown reference, a value out of range or not finite, a variable
//! not settable in this state, a wrong value count) leaves the decision, and its message, to
//! the layer's generic path, which looks at each reference again: the table only says yes.
//!
//! The table depends only on the model's declarations and the layout of its type, so
//! nothing makes it stale. References far apart (a model numbering its variables by hash,
//! say) get no table: every call then takes the generic path.
#![allow(unsafe_code)]

use std::mem::{align_of, size_of};

/// Where an element is stored, as a declaration gives it (`Kind::Real::place`): a reference,
/// so that safe code can only point at an `f64` that exists.
pub type Place<M> = Option<fn(&M, usize) -> &f64>;

/// One Real variable as the layer declares it: an FMI 2.0 scalar (`len` 1, `element` its
/// element of the declaration), or an FMI 3.0 array (`len` elements from `element` 0). Its
/// accessors, where it is, the bounds every element admits, the states (as the layer's
/// bits) in which it is settable (none for a variable without a setter).
pub struct Element<M> {
    pub get: fn(&M, usize) -> f64,
    pub set: Option<fn(&mut M, usize, f64)>,
    pub element: usize,
    pub len: usize,
    pub place: Place<M>,
    /// The closed range of finite values the bounds admit (`Limit::lowest_admitted`).
    pub lowest: f64,
    pub highest: f64,
    pub settable_in: u16,
}

/// Marks, in [`Entry::offset`], a variable whose elements are not stored one after the
/// other in the model's own bytes; the other bits then index its accessors.
const NOT_IN_PLACE: u32 = 1 << 31;

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

/// Where the `len` elements of a variable lie in the model: from one offset, one after the
/// other, or `NOT_IN_PLACE`.
fn run_in<M>(model: &M, e: &Element<M>) -> u32 {
    let Some(first) = offset_in(model, e.place, e.element) else {
        return NOT_IN_PLACE;
    };
    let contiguous = (1..e.len)
        .all(|i| offset_in(model, e.place, e.element + i) == Some(first + i * size_of::<f64>()));
    match u32::try_from(first) {
        Ok(offset) if contiguous && offset < NOT_IN_PLACE => offset,
        _ => NOT_IN_PLACE,
    }
}

/// What a value of one reference needs on its way, in 12 bytes (the table has a slot per
/// reference up to the largest, and an instance's heap is kept small): a set checks it
/// against its bounds and writes at `offset`, a get reads there.
#[derive(Clone, Copy)]
struct Entry {
    /// Where the first element is in the model's bytes, or [`NOT_IN_PLACE`] with the
    /// index of its accessors (an empty entry: `NOT_IN_PLACE` alone).
    offset: u32,
    /// Its bounds in [`RealTable::bounds`] (few distinct: most variables have none).
    bounds: u16,
    /// Elements; 0: no Real at this reference.
    len: u16,
    settable_in: u16,
    /// `settable_in` for elements stored in place, else none: what the in-place loops check,
    /// so that they need no test of their own for an entry they cannot serve.
    settable_in_place: u16,
}

// The slot per reference is most of an instance's heap (fmi-testkit's heap check).
const _: () = assert!(size_of::<Entry>() == 12);

const NO_ENTRY: Entry = Entry {
    offset: NOT_IN_PLACE,
    bounds: 0,
    len: 0,
    settable_in: 0,
    settable_in_place: 0,
};

/// The accessors of a reference whose elements are not in place (few: a table of its own,
/// so that the instance's heap stays small).
struct Accessors<M> {
    get: fn(&M, usize) -> f64,
    set: Option<fn(&mut M, usize, f64)>,
    element: usize,
}

/// The table is built while it has at most this many slots per Real reference (plus a fixed
/// allowance for small models), as the layers' own value-reference indexes are.
const SLOTS_PER_REFERENCE: usize = 8;
const SLOTS_ALLOWANCE: usize = 256;

/// Whether the table was built, and which loops serve it.
#[derive(Default, Clone, Copy, PartialEq, Eq)]
enum Built {
    #[default]
    Not,
    /// Every reference has at most one element (FMI 2.0): a call whose references are all
    /// stored in place is served by loops with one load of the entry and one load or store
    /// per value, without a call in them; any other by the loops of `Elements`.
    Scalars,
    /// References with any number of elements (FMI 3.0 arrays).
    Elements,
    /// References too sparse for a table: the generic path serves every call.
    Never,
}

/// Every Real variable of an instance by value reference; see the module documentation.
pub struct RealTable<M> {
    entries: Box<[Entry]>,
    /// The closed ranges the entries admit, `(lowest, highest)`; the first admits nothing
    /// (NaN), for the empty entries.
    bounds: Box<[(f64, f64)]>,
    accessors: Box<[Accessors<M>]>,
    built: Built,
}

impl<M> Default for RealTable<M> {
    fn default() -> Self {
        RealTable {
            entries: Box::default(),
            bounds: Box::default(),
            accessors: Box::default(),
            built: Built::Not,
        }
    }
}

impl<M> RealTable<M> {
    /// Builds the table once, from `declared` (each Real value reference with its
    /// variable; called twice), unless it is built already. `model` is any instance of
    /// `M`: only the layout of its type is read.
    #[inline]
    pub fn ensure<I>(&mut self, model: &M, declared: impl Fn() -> I)
    where
        I: IntoIterator<Item = (u32, Element<M>)>,
    {
        if self.built == Built::Not {
            self.build(model, declared);
        }
    }

    #[cold]
    #[inline(never)]
    fn build<I>(&mut self, model: &M, declared: impl Fn() -> I)
    where
        I: IntoIterator<Item = (u32, Element<M>)>,
    {
        // Counted first, so that each table is allocated once at its size: the instance's
        // heap at its peak is what it holds.
        let (mut slots, mut count, mut outside) = (0, 0, 0);
        for (vr, e) in declared() {
            slots = slots.max(vr as usize + 1);
            count += 1;
            outside += usize::from(run_in(model, &e) == NOT_IN_PLACE);
            if u16::try_from(e.len).is_err() {
                count = 0;
                break;
            }
        }
        if count == 0 || slots > SLOTS_PER_REFERENCE * count + SLOTS_ALLOWANCE {
            self.built = Built::Never;
            return;
        }
        let mut entries = vec![NO_ENTRY; slots];
        let mut bounds = vec![(f64::NAN, f64::NAN)];
        let mut accessors = Vec::with_capacity(outside);
        for (vr, e) in declared() {
            let slot = vr as usize;
            // A reference declared twice is refused by the layers' table checks; should
            // one get here, the first declared wins, as in their lookups.
            if entries[slot].len != 0 || e.len == 0 {
                continue;
            }
            let mut offset = run_in(model, &e);
            if offset == NOT_IN_PLACE {
                let Ok(index) = u32::try_from(accessors.len()) else {
                    self.built = Built::Never;
                    return;
                };
                offset |= index & !NOT_IN_PLACE;
                accessors.push(Accessors {
                    get: e.get,
                    set: e.set,
                    element: e.element,
                });
            }
            let settable_in = if e.set.is_some() { e.settable_in } else { 0 };
            let in_place = offset & NOT_IN_PLACE == 0;
            let range = (e.lowest, e.highest);
            let same = |b: &(f64, f64)| {
                b.0.to_bits() == range.0.to_bits() && b.1.to_bits() == range.1.to_bits()
            };
            let at = match bounds.iter().position(same) {
                Some(at) => at,
                None => {
                    bounds.push(range);
                    bounds.len() - 1
                }
            };
            let Ok(at) = u16::try_from(at) else {
                self.built = Built::Never;
                return;
            };
            entries[slot] = Entry {
                offset,
                bounds: at,
                len: e.len as u16,
                settable_in,
                settable_in_place: if in_place { settable_in } else { 0 },
            };
        }
        self.built = if entries.iter().all(|e| e.len <= 1) {
            Built::Scalars
        } else {
            Built::Elements
        };
        self.entries = entries.into_boxed_slice();
        self.bounds = bounds.into_boxed_slice();
        self.accessors = accessors.into_boxed_slice();
    }

    /// The accessors of an entry not in place.
    #[inline(always)]
    fn accessors(&self, e: &Entry) -> Option<&Accessors<M>> {
        self.accessors.get((e.offset & !NOT_IN_PLACE) as usize)
    }

    /// The closed range an entry admits.
    #[inline(always)]
    fn range(&self, e: &Entry) -> (f64, f64) {
        // SAFETY: every entry's `bounds` indexes `bounds` (set when the table was built).
        unsafe { *self.bounds.get_unchecked(e.bounds as usize) }
    }

    #[inline(always)]
    fn entry(&self, vr: u32) -> Entry {
        match self.entries.get(vr as usize) {
            Some(e) => *e,
            None => NO_ENTRY,
        }
    }

    /// Writes `values` to the references `vrs` if each is a Real of this table, the count
    /// matches, every element is settable in the state `state_bit` and admits its value;
    /// says whether it wrote. False leaves `model` as it was, for the generic path to
    /// refuse with a reason.
    #[inline(always)]
    pub fn write(&self, vrs: &[u32], values: &[f64], model: &mut M, state_bit: u16) -> bool {
        // Tested one after the other, the common case first (a `match` compiles to a jump
        // table here).
        if self.built == Built::Scalars && vrs.len() == values.len() {
            self.write_in_place_scalars(vrs, values, model, state_bit)
                || self.write_elements(vrs, values, model, state_bit)
        } else if matches!(self.built, Built::Scalars | Built::Elements) {
            self.write_in_place(vrs, values, model, state_bit)
                || self.write_elements(vrs, values, model, state_bit)
        } else {
            false
        }
    }

    /// [`write`](Self::write) for a call's fast path: only references stored in the model's
    /// bytes, with no call in the loops (neither of an accessor, so no code of the model's
    /// that could panic, nor of memcpy, so that the caller's values stay in caller-saved
    /// registers); false leaves `model` as it was, for the full path. `scalars_only`: a
    /// layer whose references are all scalars (FMI 2.0) leaves out the loops of arrays.
    #[inline(always)]
    pub fn write_fast(
        &self,
        vrs: &[u32],
        values: &[f64],
        model: &mut M,
        state_bit: u16,
        scalars_only: bool,
    ) -> bool {
        if self.built == Built::Scalars && vrs.len() == values.len() {
            self.write_in_place_scalars(vrs, values, model, state_bit)
        } else if !scalars_only && matches!(self.built, Built::Scalars | Built::Elements) {
            self.write_in_place_elements(vrs, values, model, state_bit)
        } else {
            false
        }
    }

    /// [`read`](Self::read) for a call's fast path, as [`write_fast`](Self::write_fast) is
    /// for writes; true only if every value read is finite (false: the values are no
    /// result, for the full path to read again and refuse with a reason).
    #[inline(always)]
    pub fn read_fast(
        &self,
        vrs: &[u32],
        values: &mut [f64],
        model: &M,
        scalars_only: bool,
    ) -> bool {
        if self.built == Built::Scalars && vrs.len() == values.len() {
            self.read_in_place_scalars_finite(vrs, values, model)
        } else if !scalars_only && matches!(self.built, Built::Scalars | Built::Elements) {
            // One variable: each value tested as it is copied. Several: the copy in a few
            // moves per variable, then every value tested at once (vectorised), fewer
            // instructions for a long list.
            if vrs.len() == 1 {
                return self.read_in_place_elements_finite(vrs, values, model);
            }
            #[allow(clippy::eq_op)]
            let finite = |values: &[f64]| values.iter().fold(true, |all, &v| all & (v - v == 0.0));
            self.read_in_place(vrs, values, model) && finite(values)
        } else {
            false
        }
    }

    /// [`read_in_place_scalars`](Self::read_in_place_scalars) that also says whether every
    /// value is finite, in the same pass.
    #[inline(always)]
    fn read_in_place_scalars_finite(&self, vrs: &[u32], values: &mut [f64], model: &M) -> bool {
        let base = (model as *const M).cast::<u8>();
        let entries = &*self.entries;
        // `v - v` is 0 exactly when `v` is finite and NaN otherwise, so the sum is 0 exactly
        // when every value is finite: two operations a value, no branch.
        let mut nan_unless_finite = 0.0;
        for (&vr, value) in vrs.iter().zip(values) {
            let Some(e) = entries.get(vr as usize) else {
                return false;
            };
            if e.offset & NOT_IN_PLACE != 0 {
                return false;
            }
            // SAFETY: as in `write_in_place_scalars`, for a shared borrow.
            let v = unsafe { base.add(e.offset as usize).cast::<f64>().read() };
            #[allow(clippy::eq_op)]
            {
                nan_unless_finite += v - v;
            }
            *value = v;
        }
        nan_unless_finite == 0.0
    }

    /// [`read_in_place`](Self::read_in_place) that also says whether every value is
    /// finite, in the same pass (which also keeps the copy from becoming a call of memcpy).
    #[inline(always)]
    fn read_in_place_elements_finite(&self, vrs: &[u32], values: &mut [f64], model: &M) -> bool {
        let base = (model as *const M).cast::<u8>();
        let entries = &*self.entries;
        let mut nan_unless_finite = 0.0;
        let mut k = 0;
        for &vr in vrs {
            let Some(e) = entries.get(vr as usize) else {
                return false;
            };
            if e.offset & NOT_IN_PLACE != 0 {
                return false;
            }
            let Some(out) = values.get_mut(k..k + usize::from(e.len)) else {
                return false;
            };
            // SAFETY: as in `write_in_place`, for a shared borrow; `out` has `len` values.
            let from = unsafe { base.add(e.offset as usize).cast::<f64>() };
            for (i, value) in out.iter_mut().enumerate() {
                // SAFETY: element `i` of `len`.
                let v = unsafe { from.add(i).read() };
                #[allow(clippy::eq_op)]
                {
                    nan_unless_finite += v - v;
                }
                *value = v;
            }
            k += out.len();
        }
        k == values.len() && nan_unless_finite == 0.0
    }

    /// [`write_in_place`](Self::write_in_place) with the copy as a loop of its own (not
    /// a call of memcpy).
    #[inline(always)]
    fn write_in_place_elements(
        &self,
        vrs: &[u32],
        values: &[f64],
        model: &mut M,
        state_bit: u16,
    ) -> bool {
        let entries = &*self.entries;
        let mut k = 0;
        for &vr in vrs {
            let Some(e) = entries.get(vr as usize) else {
                return false;
            };
            let Some(given) = values.get(k..k + usize::from(e.len)) else {
                return false;
            };
            if e.settable_in_place & state_bit == 0 {
                return false;
            }
            let (lowest, highest) = self.range(e);
            for &v in given {
                if !(lowest..=highest).contains(&v) {
                    return false;
                }
            }
            k += given.len();
        }
        if k != values.len() {
            return false;
        }
        let base = (model as *mut M).cast::<u8>();
        let mut from = values.as_ptr();
        for &vr in vrs {
            // SAFETY: as in `write_in_place`; `from` walks `values`, `len` of them per
            // reference, as the first pass counted.
            unsafe {
                let e = entries.get_unchecked(vr as usize);
                let to = base.add(e.offset as usize).cast::<f64>();
                for i in 0..usize::from(e.len) {
                    // Volatile: the same one store, but never merged into a memcpy call.
                    to.add(i).write_volatile(from.read());
                    from = from.add(1);
                }
            }
        }
        true
    }

    /// [`write`](Self::write) of references with any number of elements (FMI 3.0 arrays),
    /// or stored anywhere.
    #[inline(never)]
    fn write_elements(&self, vrs: &[u32], values: &[f64], model: &mut M, state_bit: u16) -> bool {
        // Checked before anything is written, so a refused call changes nothing. The
        // comparisons are combined without branching: a refusal is the rare case.
        let mut admitted = true;
        let mut k = 0;
        for &vr in vrs {
            let e = self.entry(vr);
            let len = usize::from(e.len);
            // No elements: an unknown reference or one of another type. Too few values:
            // a wrong count.
            let Some(given) = values.get(k..k + len).filter(|_| len != 0) else {
                return false;
            };
            admitted &= e.settable_in & state_bit != 0;
            let (lowest, highest) = self.range(&e);
            for v in given {
                admitted &= (*v >= lowest) & (*v <= highest);
            }
            k += len;
        }
        if !admitted || k != values.len() {
            return false;
        }
        let base = (model as *mut M).cast::<u8>();
        let mut k = 0;
        for &vr in vrs {
            let e = self.entry(vr);
            let len = usize::from(e.len);
            let given = &values[k..k + len];
            if e.offset & NOT_IN_PLACE == 0 {
                // SAFETY: `len` f64s lie one after the other from this offset in every `M`
                // (fields found inside the model's bytes and aligned when the table was
                // built), and `model` is borrowed mutably for this write.
                // (A loop, not `copy_nonoverlapping`: a handful of values, where a call of
                // memcpy would cost more than the copy.)
                unsafe {
                    let to = base.add(e.offset as usize).cast::<f64>();
                    for (i, &v) in given.iter().enumerate() {
                        to.add(i).write(v);
                    }
                }
            } else if let Some(a) = self.accessors(&e) {
                if let Some(set) = a.set {
                    for (i, &v) in given.iter().enumerate() {
                        // SAFETY: `base` is `model`, not otherwise used during this call.
                        set(unsafe { &mut *base.cast::<M>() }, a.element + i, v);
                    }
                }
            }
            k += len;
        }
        true
    }

    /// Reads the references `vrs` into `values` if each is a Real of this table and the
    /// count matches, and says whether it did; false means the values are no result, for
    /// the generic path to read again or refuse with a reason.
    #[inline(always)]
    pub fn read(&self, vrs: &[u32], values: &mut [f64], model: &M) -> bool {
        if self.built == Built::Scalars && vrs.len() == values.len() {
            self.read_in_place_scalars(vrs, values, model) || self.read_scalars(vrs, values, model)
        } else if matches!(self.built, Built::Scalars | Built::Elements) {
            self.read_in_place(vrs, values, model) || self.read_elements(vrs, values, model)
        } else {
            false
        }
    }

    /// [`read`](Self::read) of one value per reference, some stored elsewhere (a master
    /// that reads every output, computed ones too): per value, one entry loaded, then one
    /// load or one accessor call. Out of line, so that the in-place loop keeps its values in
    /// registers across no call.
    #[inline(never)]
    fn read_scalars(&self, vrs: &[u32], values: &mut [f64], model: &M) -> bool {
        let base = (model as *const M).cast::<u8>();
        let entries = &*self.entries;
        for (&vr, value) in vrs.iter().zip(values) {
            let Some(e) = entries.get(vr as usize) else {
                return false;
            };
            if e.offset & NOT_IN_PLACE == 0 {
                // SAFETY: as in `write_in_place_scalars`, for a shared borrow.
                *value = unsafe { base.add(e.offset as usize).cast::<f64>().read() };
            } else {
                match self.accessors(e) {
                    // An empty entry is no Real (its length is 0).
                    Some(a) if e.len != 0 => *value = (a.get)(model, a.element),
                    _ => return false,
                }
            }
        }
        true
    }

    /// [`read`](Self::read) of references with any number of elements (FMI 3.0 arrays),
    /// or stored anywhere.
    #[inline(never)]
    fn read_elements(&self, vrs: &[u32], values: &mut [f64], model: &M) -> bool {
        let base = (model as *const M).cast::<u8>();
        let mut k = 0;
        for &vr in vrs {
            let e = self.entry(vr);
            let len = usize::from(e.len);
            let Some(out) = values.get_mut(k..k + len).filter(|_| len != 0) else {
                return false;
            };
            if e.offset & NOT_IN_PLACE == 0 {
                // SAFETY: as in `write`, for a shared borrow.
                unsafe {
                    let from = base.add(e.offset as usize).cast::<f64>();
                    for (i, v) in out.iter_mut().enumerate() {
                        *v = from.add(i).read();
                    }
                }
            } else if let Some(a) = self.accessors(&e) {
                for (i, v) in out.iter_mut().enumerate() {
                    *v = (a.get)(model, a.element + i);
                }
            }
            k += len;
        }
        k == values.len()
    }

    /// [`write`](Self::write) of references with any number of elements, each stored in
    /// place; false (nothing written) also for a reference stored elsewhere.
    #[inline(always)]
    fn write_in_place(&self, vrs: &[u32], values: &[f64], model: &mut M, state_bit: u16) -> bool {
        let entries = &*self.entries;
        let mut admitted = true;
        let mut k = 0;
        for &vr in vrs {
            let Some(e) = entries.get(vr as usize) else {
                return false;
            };
            // Too few values: a wrong count. An empty entry (no values taken) or one not in
            // place is settable in no state here.
            let Some(given) = values.get(k..k + usize::from(e.len)) else {
                return false;
            };
            admitted &= e.settable_in_place & state_bit != 0;
            let (lowest, highest) = self.range(e);
            for &v in given {
                admitted &= (v >= lowest) & (v <= highest);
            }
            k += given.len();
        }
        if !admitted || k != values.len() {
            return false;
        }
        let base = (model as *mut M).cast::<u8>();
        let mut k = 0;
        for &vr in vrs {
            // SAFETY: found by the first pass, settable in place: its `len` elements lie
            // one after the other from its offset in every `M` (found inside the model's
            // bytes and aligned when the table was built), and `model` is borrowed mutably
            // for this write; the first pass found `len` values from `k`.
            unsafe {
                let e = entries.get_unchecked(vr as usize);
                let len = usize::from(e.len);
                let to = base.add(e.offset as usize).cast::<f64>();
                copy_few(values.as_ptr().add(k), to, len);
                k += len;
            }
        }
        true
    }

    /// [`read`](Self::read) of references with any number of elements, each stored in
    /// place; false (the values no result) also for a reference stored elsewhere.
    #[inline(always)]
    fn read_in_place(&self, vrs: &[u32], values: &mut [f64], model: &M) -> bool {
        let base = (model as *const M).cast::<u8>();
        let entries = &*self.entries;
        let mut k = 0;
        for &vr in vrs {
            let Some(e) = entries.get(vr as usize) else {
                return false;
            };
            // Neither an empty entry nor one stored elsewhere is read here (both have
            // `NOT_IN_PLACE`).
            if e.offset & NOT_IN_PLACE != 0 {
                return false;
            }
            let Some(out) = values.get_mut(k..k + usize::from(e.len)) else {
                return false;
            };
            // SAFETY: as in `write_in_place`, for a shared borrow; `out` has `len` values.
            unsafe {
                let from = base.add(e.offset as usize).cast::<f64>();
                copy_few(from, out.as_mut_ptr(), out.len());
            }
            k += out.len();
        }
        k == values.len()
    }

    /// [`write`](Self::write) of one value per reference, each a scalar stored in place:
    /// per value, one entry loaded and checked, then one store; no call in either loop.
    /// False (nothing written) also for a reference stored elsewhere.
    #[inline(always)]
    fn write_in_place_scalars(
        &self,
        vrs: &[u32],
        values: &[f64],
        model: &mut M,
        state_bit: u16,
    ) -> bool {
        let entries = &*self.entries;
        // A branch per test, taken only by a refusal: fewer instructions (and registers)
        // than combining them.
        for (&vr, &v) in vrs.iter().zip(values) {
            let Some(e) = entries.get(vr as usize) else {
                return false;
            };
            // An empty entry, or one not in place, is settable in no state here (and an
            // empty one's bounds are NaN).
            // (A table of scalars: each entry has one element or none.)
            let (lowest, highest) = self.range(e);
            if e.settable_in_place & state_bit == 0 || !(lowest..=highest).contains(&v) {
                return false;
            }
        }
        let base = (model as *mut M).cast::<u8>();
        for (&vr, &v) in vrs.iter().zip(values) {
            // SAFETY: found by the first pass, and settable in place, so a scalar in place:
            // its offset is an f64 of every `M` (found inside the model's bytes and aligned when the
            // table was built), and `model` is borrowed mutably for this write.
            unsafe {
                let e = entries.get_unchecked(vr as usize);
                base.add(e.offset as usize).cast::<f64>().write(v);
            }
        }
        true
    }

    /// [`read`](Self::read) of one value per reference, each a scalar stored in place;
    /// false (the values no result) also for a reference stored elsewhere.
    #[inline(always)]
    fn read_in_place_scalars(&self, vrs: &[u32], values: &mut [f64], model: &M) -> bool {
        let base = (model as *const M).cast::<u8>();
        let entries = &*self.entries;
        for (&vr, value) in vrs.iter().zip(values) {
            let Some(e) = entries.get(vr as usize) else {
                return false;
            };
            // Neither an empty entry nor one stored elsewhere is read here (both have
            // `NOT_IN_PLACE`); a scalar's offset is its only element's.
            if e.offset & NOT_IN_PLACE != 0 {
                return false;
            }
            // SAFETY: as in `write_in_place_scalars`, for a shared borrow.
            *value = unsafe { base.add(e.offset as usize).cast::<f64>().read() };
        }
        true
    }
}

/// Copies `len` values, in a few moves for the lengths a variable has (a vector or a
/// quaternion: a call of memcpy, which the compiler makes of a plain copy loop, costs more
/// than the copy).
///
/// # Safety
/// As `std::ptr::copy_nonoverlapping`.
#[inline(always)]
unsafe fn copy_few(from: *const f64, to: *mut f64, len: usize) {
    // SAFETY: `len` elements are readable at `from` and writable at `to`, apart.
    unsafe {
        if len > 4 {
            std::ptr::copy_nonoverlapping(from, to, len);
            return;
        }
        if len >= 1 {
            to.write(from.read());
        }
        if len >= 2 {
            to.add(1).write(from.add(1).read());
        }
        if len >= 3 {
            to.add(2).write(from.add(2).read());
        }
        if len == 4 {
            to.add(3).write(from.add(3).read());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type M = [f64; 4];
    const INIT: u16 = 1;
    const RUNNING: u16 = 2;

    fn variable(
        element: usize,
        len: usize,
        lowest: f64,
        highest: f64,
        settable_in: u16,
    ) -> Element<M> {
        Element {
            get: |m: &M, i| m[i] * 10.0,
            set: Some(|m: &mut M, i, v| m[i] = -v),
            element,
            len,
            place: Some(|m: &M, i| &m[i]),
            lowest,
            highest,
            settable_in,
        }
    }

    /// vr 0: element 0, settable only initializing; vr 5: a two-element array (elements 1,
    /// 2) bounded to [0, 8]; vr 3: an output (element 3, no setter). Anything else is
    /// unknown.
    fn declared() -> Vec<(u32, Element<M>)> {
        let mut output = variable(3, 1, -f64::MAX, f64::MAX, INIT | RUNNING);
        output.set = None;
        vec![
            (0, variable(0, 1, -f64::MAX, f64::MAX, INIT)),
            (5, variable(1, 2, 0.0, 8.0, INIT | RUNNING)),
            (3, output),
        ]
    }

    /// FMI 2.0's kind: scalars only (vr 0 element 0, vr 1 element 1 bounded to [0, 1],
    /// vr 2 an output at element 2).
    fn scalars() -> Vec<(u32, Element<M>)> {
        let mut output = variable(2, 1, -f64::MAX, f64::MAX, INIT | RUNNING);
        output.set = None;
        vec![
            (0, variable(0, 1, -f64::MAX, f64::MAX, INIT)),
            (1, variable(1, 1, 0.0, 1.0, INIT | RUNNING)),
            (2, output),
        ]
    }

    fn table(model: &M, declared: fn() -> Vec<(u32, Element<M>)>) -> RealTable<M> {
        let mut table = RealTable::default();
        table.ensure(model, declared);
        table
    }

    #[test]
    fn a_set_writes_what_the_checks_admit_in_any_order_and_nothing_else() {
        let mut model: M = [0.0; 4];
        let table = table(&model, declared);
        assert!(table.write(&[5, 0], &[7.0, 0.5, 3.0], &mut model, INIT));
        assert_eq!(
            model,
            [3.0, 7.0, 0.5, 0.0],
            "stored in place, not through `set`"
        );
        assert!(table.write(&[0, 5], &[4.0, 8.0, 1.0], &mut model, INIT));
        assert_eq!(model, [4.0, 8.0, 1.0, 0.0]);
        // Out of bounds, non-finite, a wrong count, a state where vr 0 is not settable, an
        // output, an unknown reference: nothing written.
        for (vrs, values, state) in [
            (&[5, 0][..], &[1.0, 8.5, 1.0][..], INIT),
            (&[5, 0], &[1.0, -0.1, 1.0], INIT),
            (&[5, 0], &[f64::NAN, 0.5, 1.0], INIT),
            (&[5, 0], &[1.0, 0.5, f64::NEG_INFINITY], INIT),
            (&[5, 0], &[1.0, 0.5], INIT),
            (&[5, 0], &[1.0, 0.5, 1.0, 2.0], INIT),
            (&[5, 0], &[1.0, 0.5, 1.0], RUNNING),
            (&[3], &[1.0], RUNNING),
            (&[5, 4], &[1.0, 0.5, 1.0], INIT),
            (&[1], &[1.0], INIT),
            (&[u32::MAX], &[1.0], INIT),
        ] {
            assert!(
                !table.write(vrs, values, &mut model, state),
                "{vrs:?} {values:?} in state {state}"
            );
            assert_eq!(model, [4.0, 8.0, 1.0, 0.0], "{vrs:?} {values:?}");
        }
        // A reference repeated: each takes its own values, the last written last.
        assert!(table.write(&[5, 5], &[1.0, 0.0, 6.0, 1.0], &mut model, RUNNING));
        assert_eq!(model, [4.0, 6.0, 1.0, 0.0]);
    }

    #[test]
    fn scalars_are_set_in_any_order_one_or_many_per_call() {
        let mut model: M = [0.0; 4];
        let table = table(&model, scalars);
        assert!(table.write(&[1, 0], &[0.5, 3.0], &mut model, INIT));
        assert_eq!(model, [3.0, 0.5, 0.0, 0.0]);
        assert!(table.write(&[0], &[2.0], &mut model, INIT));
        assert!(table.write(&[1], &[0.25], &mut model, RUNNING));
        assert_eq!(model, [2.0, 0.25, 0.0, 0.0]);
        for (vrs, values, state) in [
            (&[1, 0][..], &[1.5, 1.0][..], INIT),
            (&[0, 1], &[f64::INFINITY, 1.0], INIT),
            (&[0], &[1.0], RUNNING),
            (&[2], &[1.0], RUNNING),
            (&[0, 3], &[1.0, 1.0], INIT),
            (&[0, 9999], &[1.0, 1.0], INIT),
            (&[0, 1], &[1.0], INIT),
        ] {
            assert!(
                !table.write(vrs, values, &mut model, state),
                "{vrs:?} {values:?} in state {state}"
            );
            assert_eq!(model, [2.0, 0.25, 0.0, 0.0], "{vrs:?} {values:?}");
        }
        let mut values = [0.0; 3];
        assert!(table.read(&[2, 0, 1], &mut values, &model));
        assert_eq!(values, [0.0, 2.0, 0.25]);
        assert!(!table.read(&[2, 3, 1], &mut values, &model));
        assert!(!table.read(&[2, 1], &mut values, &model), "count");
    }

    #[test]
    fn a_set_admits_every_finite_value_where_no_bound_is_declared() {
        let mut model: M = [0.0; 4];
        let table = table(&model, declared);
        for v in [f64::MAX, -f64::MAX, f64::MIN_POSITIVE, -0.0, 1e-310] {
            assert!(table.write(&[0], &[v], &mut model, INIT), "{v}");
            assert_eq!(model[0].to_bits(), v.to_bits());
        }
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(!table.write(&[0], &[v], &mut model, INIT), "{v}");
            assert_eq!(model[0], 1e-310);
        }
    }

    #[test]
    fn a_read_gives_each_reference_its_values_in_the_order_asked() {
        let model: M = [1.0, 2.0, 3.0, 4.0];
        let table = table(&model, declared);
        let mut values = [0.0; 4];
        assert!(table.read(&[3, 5, 0], &mut values, &model));
        assert_eq!(values, [4.0, 2.0, 3.0, 1.0]);
        assert!(table.read(&[0, 0, 5], &mut values, &model));
        assert_eq!(values, [1.0, 1.0, 2.0, 3.0]);
        let mut one = [0.0];
        assert!(table.read(&[3], &mut one, &model));
        assert_eq!(one, [4.0]);
        // Unknown, or a wrong count: no result.
        assert!(!table.read(&[0, 9, 5], &mut values, &model));
        assert!(!table.read(&[0, 5], &mut values, &model), "count");
        assert!(!table.read(&[0, 5, 5], &mut values[..3], &model), "count");
    }

    /// A variable stored outside the model's bytes goes through its accessors.
    #[test]
    fn elements_elsewhere_go_through_their_accessors() {
        static ELSEWHERE: f64 = 0.0;
        let outside = || {
            let mut e = variable(1, 2, -f64::MAX, f64::MAX, INIT);
            e.place = Some(|m: &M, i| if i == 1 { &m[1] } else { &ELSEWHERE });
            vec![(7, e)]
        };
        let mut model: M = [1.0, 2.0, 3.0, 4.0];
        let mut table = RealTable::default();
        table.ensure(&model, outside);
        let mut values = [0.0; 2];
        assert!(table.read(&[7], &mut values, &model));
        assert_eq!(values, [20.0, 30.0], "the accessor multiplies by 10");
        assert!(table.write(&[7], &[5.0, 6.0], &mut model, INIT));
        assert_eq!(model, [1.0, -5.0, -6.0, 4.0], "the setter negates");
        assert_eq!(ELSEWHERE, 0.0);
    }

    /// References too far apart for a table: every call is left to the generic path.
    #[test]
    fn sparse_references_get_no_table() {
        let mut model: M = [0.0; 4];
        let mut table = RealTable::default();
        table.ensure(&model, || {
            vec![(4_000_000, variable(0, 1, -f64::MAX, f64::MAX, INIT))]
        });
        assert!(!table.write(&[4_000_000], &[1.0], &mut model, INIT));
        let mut one = [0.0];
        assert!(!table.read(&[4_000_000], &mut one, &model));
        // Built once: a second `ensure` does not look at the declarations again.
        table.ensure(&model, || -> Vec<(u32, Element<M>)> { unreachable!() });
    }
}
