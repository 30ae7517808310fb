//! `impl Model` for the small models of the layer tests and benches: models that only
//! exchange values through their declaration table, with nothing to validate at
//! initialization and nothing to integrate.

/// Implements `fmi_model::Model` for `$model` (a type that is `Default + Clone + Serialize +
/// Deserialize`) with the declarations `$table`: `exit_initialization` accepts every
/// parameter, `do_step` completes at once (or runs `step = |model| ...` for its effect, e.g.
/// a panic), `calculate_values` is the optional `calculate = |model| ...`. The default
/// experiment is 0 to `$stop` s (1 s when not given) in steps of 0.1 s.
///
/// ```ignore
/// fmi_testkit::test_model!(Product, PRODUCT, "an output that overflows for large inputs");
/// ```
#[macro_export]
macro_rules! test_model {
    (
        $model:ident, $table:ident, $description:literal
        $(, identifier = $identifier:literal)?
        $(, stop = $stop:literal)?
        $(, calculate = $calculate:expr)?
        $(, step = $step:expr)?
    ) => {
        impl $crate::fmi_model::Model for $model {
            const MODEL_IDENTIFIER: &'static str =
                $crate::test_model!(@first $($identifier,)? stringify!($model));
            const MODEL_NAME: &'static str = stringify!($model);
            const VERSION: &'static str = "0.0.0";
            const DESCRIPTION: &'static str = $description;
            const DEFAULT_EXPERIMENT: $crate::fmi_model::Experiment =
                $crate::fmi_model::Experiment {
                    start_time: 0.0,
                    stop_time: $crate::test_model!(@first $($stop,)? 1.0),
                    step_size: 0.1,
                    tolerance: None,
                };
            fn declarations() -> &'static [$crate::fmi_model::Declaration<Self>] {
                &$table
            }
            $(
                fn calculate_values(&mut self, _: &mut $crate::fmi_model::Log) {
                    let calculate: fn(&mut Self) = $calculate;
                    calculate(self)
                }
            )?
            fn exit_initialization(
                &mut self,
                _: f64,
                _: &mut $crate::fmi_model::Log,
            ) -> Result<(), $crate::fmi_model::ModelError> {
                Ok(())
            }
            fn do_step(
                &mut self,
                _: f64,
                _: f64,
                _: &mut $crate::fmi_model::Log,
            ) -> Result<$crate::fmi_model::StepEnd, $crate::fmi_model::ModelError> {
                $(
                    let step: fn(&mut Self) = $step;
                    step(self);
                )?
                Ok($crate::fmi_model::StepEnd::Complete)
            }
        }
    };
    (@first $value:expr $(, $rest:expr)*) => {
        $value
    };
}
