use std::fmt;

/// Why an integration stopped. The integrator must be `reset` before it is used again.
#[derive(Clone, Debug, PartialEq)]
pub enum SolverError {
    /// The system's own `derivatives` or `indicators` returned this Err.
    System { t: f64, message: String },
    /// `derivatives` returned NaN or infinity.
    NonFiniteDerivative { t: f64, index: usize },
    /// `indicators` returned NaN or infinity.
    NonFiniteIndicator { t: f64, index: usize },
    /// The step size needed for the tolerances fell below what `t` can resolve.
    StepSizeUnderflow { t: f64 },
    /// More than the step cap of accepted steps without reaching a t_stop.
    TooManySteps { t: f64, steps: u64 },
    /// Repeated error-test or Newton failures within one step.
    ConvergenceFailure { t: f64, detail: String },
    /// Bad arguments: sizes, tolerances, a t_stop behind the current time.
    InvalidInput(String),
    /// A previous error left the integrator unusable until `reset`.
    NeedsReset,
    /// Anything else the numerical backend reported.
    Backend(String),
}

impl fmt::Display for SolverError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::System { t, message } => write!(f, "system error at t = {t}: {message}"),
            Self::NonFiniteDerivative { t, index } => {
                write!(f, "derivative {index} is not finite at t = {t}")
            }
            Self::NonFiniteIndicator { t, index } => {
                write!(f, "event indicator {index} is not finite at t = {t}")
            }
            Self::StepSizeUnderflow { t } => write!(f, "step size underflow at t = {t}"),
            Self::TooManySteps { t, steps } => {
                write!(f, "step cap of {steps} steps hit at t = {t}")
            }
            Self::ConvergenceFailure { t, detail } => {
                write!(f, "no convergence at t = {t}: {detail}")
            }
            Self::InvalidInput(m) => write!(f, "invalid input: {m}"),
            Self::NeedsReset => write!(f, "integrator failed earlier; call reset first"),
            Self::Backend(m) => write!(f, "ODE backend error: {m}"),
        }
    }
}

impl std::error::Error for SolverError {}
