//! A master's arguments as Rust values: a pointer and a length as a slice, an
//! out-parameter as a reference, checked the same way by both export layers before any
//! memory is touched (NULL is an error unless the length is 0; a length no array can have
//! is refused).
use std::fmt::{self, Debug};

/// Why an argument cannot be read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ArgError {
    /// The argument, named as in the standard, is NULL.
    Null(&'static str),
    /// `n` elements of the argument cannot exist in memory.
    TooLong { name: &'static str, n: usize },
}

impl fmt::Display for ArgError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ArgError::Null(name) => write!(f, "argument {name} is NULL"),
            ArgError::TooLong { name, n } => write!(f, "{n} elements for {name} cannot exist"),
        }
    }
}

/// `n` elements at `ptr`.
///
/// # Safety
/// A non-NULL `ptr` must point to `n` readable elements, as the standard requires of the
/// master.
pub unsafe fn slice<'a, T>(
    ptr: *const T,
    n: usize,
    name: &'static str,
) -> Result<&'a [T], ArgError> {
    if n == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(ArgError::Null(name));
    }
    if n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return Err(ArgError::TooLong { name, n });
    }
    // SAFETY: non-NULL, the size fits; the caller guarantees n readable elements.
    Ok(unsafe { std::slice::from_raw_parts(ptr, n) })
}

/// `n` writable elements at `ptr`.
///
/// # Safety
/// A non-NULL `ptr` must point to `n` writable elements.
pub unsafe fn slice_mut<'a, T>(
    ptr: *mut T,
    n: usize,
    name: &'static str,
) -> Result<&'a mut [T], ArgError> {
    unsafe { slice(ptr as *const T, n, name) }?;
    if n == 0 {
        return Ok(&mut []);
    }
    // SAFETY: as in `slice`, writable by the caller's guarantee.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
}

/// A list of `na` elements at `a` (value references) and one of `nb` at `b` (their
/// values), each checked as [`slice`] checks it, in that order; the common case (neither
/// NULL, lengths far below the limit) in one test of each.
///
/// # Safety
/// As [`slice`], for each.
#[inline(always)]
pub unsafe fn lists<'a, A, B>(
    a: *const A,
    na: usize,
    a_name: &'static str,
    b: *const B,
    nb: usize,
    b_name: &'static str,
) -> Result<(&'a [A], &'a [B]), ArgError> {
    if !a.is_null() && !b.is_null() && (na | nb) <= const { limit::<A, B>() } {
        // SAFETY: non-NULL, the sizes fit; the caller guarantees the elements.
        return Ok(unsafe {
            (
                std::slice::from_raw_parts(a, na),
                std::slice::from_raw_parts(b, nb),
            )
        });
    }
    unsafe { Ok((slice(a, na, a_name)?, slice(b, nb, b_name)?)) }
}

/// [`lists`] for a call's fast path: the lists when neither is NULL and both lengths are
/// far below the limit, else `None` (for [`lists`] to decide).
///
/// # Safety
/// As [`slice`], for each.
#[inline(always)]
pub unsafe fn few<'a, A, B>(
    a: *const A,
    na: usize,
    b: *const B,
    nb: usize,
) -> Option<(&'a [A], &'a [B])> {
    if !a.is_null() && !b.is_null() && (na | nb) <= const { limit::<A, B>() } {
        // SAFETY: as in `lists`.
        return Some(unsafe {
            (
                std::slice::from_raw_parts(a, na),
                std::slice::from_raw_parts(b, nb),
            )
        });
    }
    None
}

/// [`few`] with the values written to.
///
/// # Safety
/// As [`slice`] for `a`, [`slice_mut`] for `b`.
#[inline(always)]
pub unsafe fn few_mut<'a, A, B>(
    a: *const A,
    na: usize,
    b: *mut B,
    nb: usize,
) -> Option<(&'a [A], &'a mut [B])> {
    if !a.is_null() && !b.is_null() && (na | nb) <= const { limit::<A, B>() } {
        // SAFETY: as in `lists_mut`.
        return Some(unsafe {
            (
                std::slice::from_raw_parts(a, na),
                std::slice::from_raw_parts_mut(b, nb),
            )
        });
    }
    None
}

/// [`lists`] with the values written to.
///
/// # Safety
/// As [`slice`] for `a`, [`slice_mut`] for `b`.
#[inline(always)]
pub unsafe fn lists_mut<'a, A, B>(
    a: *const A,
    na: usize,
    a_name: &'static str,
    b: *mut B,
    nb: usize,
    b_name: &'static str,
) -> Result<(&'a [A], &'a mut [B]), ArgError> {
    if !a.is_null() && !b.is_null() && (na | nb) <= const { limit::<A, B>() } {
        // SAFETY: as in `lists`, writable by the caller's guarantee.
        return Ok(unsafe {
            (
                std::slice::from_raw_parts(a, na),
                std::slice::from_raw_parts_mut(b, nb),
            )
        });
    }
    unsafe { Ok((slice(a, na, a_name)?, slice_mut(b, nb, b_name)?)) }
}

/// The longest arrays of `A` and of `B` [`slice`] admits, the shorter of the two (a
/// constant): both lengths at most this pass its checks. `(na | nb) <= limit` implies
/// both are, and nearly never refuses a pair `slice` would admit (it then decides).
const fn limit<A, B>() -> usize {
    let (a, b) = (std::mem::size_of::<A>(), std::mem::size_of::<B>());
    let larger = if a > b { a } else { b };
    // The largest power of two at most the limit, so that `na | nb` stays below it.
    let limit = isize::MAX as usize / if larger == 0 { 1 } else { larger };
    (1usize << (usize::BITS - 1 - limit.leading_zeros())) - 1
}

/// `*ptr` as an out-parameter.
///
/// # Safety
/// A non-NULL `ptr` must point to a writable `T`.
pub unsafe fn out<'a, T>(ptr: *mut T, name: &'static str) -> Result<&'a mut T, ArgError> {
    // SAFETY: writable when non-NULL, by the caller's guarantee.
    unsafe { ptr.as_mut() }.ok_or(ArgError::Null(name))
}

/// For a call trace: up to 16 elements of an input array.
///
/// # Safety
/// As [`slice`].
pub unsafe fn show<T: Debug>(ptr: *const T, n: usize) -> String {
    if n == 0 {
        return "[]".into();
    }
    if ptr.is_null() {
        return "NULL".into();
    }
    let shown = n.min(16);
    // SAFETY: as in `slice`, for the first `shown` elements.
    let items = unsafe { std::slice::from_raw_parts(ptr, shown) };
    let more = if n > shown { ", ..." } else { "" };
    format!("{items:?}{more}")
}

/// The message of a caught panic.
pub fn panic_text(payload: &(dyn std::any::Any + Send)) -> &str {
    payload
        .downcast_ref::<&str>()
        .copied()
        .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
        .unwrap_or("unknown panic")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn null_is_refused_unless_empty_and_impossible_lengths_are_refused() {
        let p: *const f64 = std::ptr::null();
        assert_eq!(unsafe { slice(p, 0, "values") }, Ok(&[][..]));
        assert_eq!(
            unsafe { slice(p, 2, "values") },
            Err(ArgError::Null("values"))
        );
        let x = [1.0f64];
        assert!(matches!(
            unsafe { slice(x.as_ptr(), usize::MAX, "values") },
            Err(ArgError::TooLong { .. })
        ));
        assert_eq!(unsafe { slice(x.as_ptr(), 1, "values") }, Ok(&x[..]));
        assert_eq!(
            unsafe { out(std::ptr::null_mut::<f64>(), "size") }
                .unwrap_err()
                .to_string(),
            "argument size is NULL"
        );
        assert_eq!(unsafe { show([1, 2].as_ptr(), 2) }, "[1, 2]");
    }

    /// A pair of lists is refused exactly as its two `slice`s are, the first one first.
    #[test]
    fn lists_are_checked_as_their_slices_are() {
        let (vrs, values) = ([1u32, 2], [1.0f64, 2.0]);
        let (np_u, np_f) = (std::ptr::null::<u32>(), std::ptr::null_mut::<f64>());
        let cases = [
            (vrs.as_ptr(), 2, values.as_ptr(), 2),
            (vrs.as_ptr(), 1, values.as_ptr(), 2),
            (np_u, 0, np_f.cast_const(), 0),
            (np_u, 2, np_f.cast_const(), 2),
            (vrs.as_ptr(), 2, np_f.cast_const(), 2),
            (np_u, 0, values.as_ptr(), 2),
            (vrs.as_ptr(), usize::MAX, values.as_ptr(), 2),
            (vrs.as_ptr(), 2, values.as_ptr(), usize::MAX / 4),
        ];
        for (a, na, b, nb) in cases {
            let each = unsafe { slice(a, na, "vr").and_then(|a| Ok((a, slice(b, nb, "value")?))) };
            assert_eq!(unsafe { lists(a, na, "vr", b, nb, "value") }, each);
            let each_mut = each.clone().map(|(a, b)| (a, b.to_vec()));
            let mut copy = values;
            let b_mut = if b.is_null() { np_f } else { copy.as_mut_ptr() };
            let got = unsafe { lists_mut(a, na, "vr", b_mut, nb.min(2), "value") }
                .map(|(a, b)| (a, b.to_vec()));
            if nb <= 2 {
                assert_eq!(got, each_mut);
            }
        }
    }
}
