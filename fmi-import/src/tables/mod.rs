//! The entry points of an FMU binary as tables of typed function pointers, each table listed
//! once: the importer, the test kit and the speed tests all resolve through these.
//!
//! A table is one group of the standard's functions (the common ones, those of Co-Simulation,
//! those of Model Exchange), so that an FMU which exports one interface only is still loaded:
//! a master resolves the common table and the table of the interface it uses.
#![allow(unsafe_code)]

pub mod fmi2;
pub mod fmi3;

/// A function the binary does not export.
#[derive(Debug)]
pub struct MissingSymbol {
    pub symbol: &'static str,
    pub source: libloading::Error,
}

impl std::fmt::Display for MissingSymbol {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the binary does not export {}: {}",
            self.symbol, self.source
        )
    }
}

impl std::error::Error for MissingSymbol {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.source)
    }
}

/// Resolves one symbol as `T`.
///
/// # Safety
/// `T` must be the type the standard gives `symbol`; the copied pointer is only valid while
/// `library` stays loaded.
#[doc(hidden)]
pub unsafe fn symbol<T: Copy>(
    library: &libloading::Library,
    symbol: &'static str,
) -> Result<T, MissingSymbol> {
    // SAFETY: the caller promises the standard's type for this symbol.
    let loaded = unsafe { library.get::<T>(symbol.as_bytes()) };
    loaded
        .map(|function| *function)
        .map_err(|source| MissingSymbol { symbol, source })
}

/// Declares one table from one listing: the struct, its symbols in order, its resolution
/// from a loaded library, and a macro (`$linked!(crate_path)`) that fills it from the
/// `#[no_mangle]` functions of an FMU crate linked into a test.
///
/// `$d` is a `$` passed in, so that the nested macro can have metavariables of its own.
macro_rules! function_table {
    (
        $d:tt
        $(#[$meta:meta])*
        $table:ident, linked as $linked:ident {
            $($field:ident: $ty:ty = $symbol:ident,)+
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy)]
        pub struct $table {
            $(pub $field: $ty,)+
        }

        impl $table {
            /// The C names, in table order.
            pub const SYMBOLS: &'static [&'static str] = &[$(stringify!($symbol)),+];

            /// Resolves every function, failing on the first the binary lacks.
            ///
            /// # Safety
            /// The library's symbols must have the standard's signatures, and the table may only
            /// be used while the library stays loaded.
            pub unsafe fn load(
                library: &libloading::Library,
            ) -> Result<Self, $crate::tables::MissingSymbol> {
                Ok(Self {
                    // SAFETY: forwarded from the caller.
                    $($field: unsafe {
                        $crate::tables::symbol::<$ty>(library, stringify!($symbol))
                    }?,)+
                })
            }
        }

        #[doc = concat!("The [`", stringify!($table), "`] of an FMU crate linked into the \
            caller, e.g. `", stringify!($linked), "!(fmu_plant)`.")]
        #[macro_export]
        macro_rules! $linked {
            ($d fmu:path) => {{
                use $d fmu as fmu;
                $d crate::$table { $($field: fmu::$symbol,)+ }
            }};
        }
    };
}
pub(crate) use function_table;

/// Each symbol of a listing once, all with the version's prefix.
#[cfg(test)]
fn assert_listed_once(symbols: &[&str], prefix: &str, count: usize) {
    let unique: std::collections::BTreeSet<_> = symbols.iter().collect();
    assert_eq!(symbols.len(), count, "{symbols:?}");
    assert_eq!(unique.len(), count, "a symbol listed twice");
    assert!(symbols.iter().all(|s| s.starts_with(prefix)));
}
