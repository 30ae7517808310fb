//! The workspace's FMI importer: loads FMI 2.0 and FMI 3.0 FMUs through their C ABI, as any
//! FMI master does, behind one [`Instance`] type (an FMI 2.0 or an FMI 3.0 backend); and the
//! tables of the standard's entry points ([`tables`]) that every caller of a binary resolves,
//! this importer, the test kit and the speed tests alike.
//!
//! This crate and `tables` are the only places of the importer with `unsafe`.
//!
//! ```no_run
//! use fmi_import::{Fmu, StepStatus};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let fmu = Fmu::load("target/fmu/Oscillator.fmu")?;
//! let mut oscillator = fmu.instantiate("oscillator", false)?;
//! oscillator.set_real_by_name("k", 4.0)?;
//! oscillator.setup_experiment(None, 0.0, None)?;
//! oscillator.enter_initialization_mode()?;
//! oscillator.exit_initialization_mode()?;
//! for step in 0..100 {
//!     let time = f64::from(step) * 0.01;
//!     if !matches!(oscillator.do_step(time, 0.01)?, StepStatus::Complete(_)) {
//!         break;
//!     }
//! }
//! println!("x = {}", oscillator.get_real_by_name("x")?);
//! # Ok(())
//! # }
//! ```
mod archive;
mod binary;
pub mod blackbox;
pub mod derivatives;
mod describe;
mod error;
mod ffi;
mod fmi2;
mod fmi3;
mod fmu;
mod instance;
mod loaded;
mod logger;
mod model_exchange;
mod state;
mod status;
pub mod tables;
mod variables;
mod version;
pub mod word;

pub use describe::{peek_description, read_description, read_description_typed, Declared};
pub use error::{CallError, FmiError, LoadError, VariableError};
pub use fmi3::element_name;
pub use fmu::Fmu;
pub use instance::{Instance, InstanceOptions};
pub use logger::{FmuLog, LogMessage, LOG_CAPACITY};
pub use model_description::fmi3::Fmi3Type;
pub use model_description::VariableKind;
pub use model_exchange::{EventUpdate, Interface, MeVector, StepEnd};
pub use state::{refusal as fmu_state_refusal, FmuState};
pub use status::{Failure, Status, StepStatus, Success};
pub use tables::fmi2::{Fmi2CoSimulation, Fmi2Common, Fmi2ModelExchange};
pub use tables::fmi3::{Fmi3CoSimulation, Fmi3Common, Fmi3ModelExchange};
pub use variables::VariableInfo;
pub use version::FmiVersion;
