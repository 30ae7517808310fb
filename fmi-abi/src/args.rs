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
}
