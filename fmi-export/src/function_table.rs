//! The form of a version's function table: an enum of the functions that take an instance,
//! their C names from one prefix, and the version's rule for each (FMI 2.0 a state mask,
//! FMI 3.0 a scope of interfaces and states).

/// Defines `pub enum Function` with `ALL`, `name` (the C name: `$prefix` and the variant),
/// `named` (the variant of a C name, for symbol tables: evaluated at compile time there, so
/// an unknown name fails the build) and `$rule` (the version's rule of each function).
#[macro_export]
macro_rules! function_table {
    (
        $(#[$meta:meta])*
        prefix = $prefix:literal, $rule:ident -> $rule_type:ty;
        $($variant:ident => $value:expr,)*
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[allow(clippy::enum_variant_names)]
        pub enum Function { $($variant,)* }

        impl Function {
            pub const ALL: &'static [Function] = &[$(Function::$variant,)*];

            /// The C name.
            pub const fn name(self) -> &'static str {
                match self { $(Function::$variant => concat!($prefix, stringify!($variant)),)* }
            }

            /// The function whose C name is `name`.
            ///
            /// # Panics
            /// When no function of the table has that name.
            pub const fn named(name: &str) -> Function {
                let mut i = 0;
                while i < Self::ALL.len() {
                    if $crate::function_table::same_str(Self::ALL[i].name(), name) {
                        return Self::ALL[i];
                    }
                    i += 1;
                }
                panic!("not a function of this table")
            }

            /// Inlined, a constant at each call site.
            #[inline]
            pub const fn $rule(self) -> $rule_type {
                match self { $(Function::$variant => $value,)* }
            }
        }
    };
}

/// `a == b` in a constant.
pub const fn same_str(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

#[cfg(test)]
mod tests {
    use crate::StateMask;

    crate::function_table! {
        /// A table of two.
        prefix = "fmiX", legal_states -> StateMask;
        DoStep => StateMask::of(&[crate::State::StepComplete]),
        Reset => StateMask::of(&[]),
    }

    #[test]
    fn names_and_their_functions_map_both_ways() {
        const RESET: Function = Function::named("fmiXReset");
        assert_eq!(RESET, Function::Reset);
        for f in Function::ALL {
            assert_eq!(Function::named(f.name()), *f);
        }
        assert!(Function::DoStep
            .legal_states()
            .contains(crate::State::StepComplete));
        assert!(!super::same_str("fmiXReset", "fmiXResets"));
    }

    #[test]
    #[should_panic(expected = "not a function of this table")]
    fn an_unknown_name_is_no_function() {
        Function::named("fmiXDoStepp");
    }
}
