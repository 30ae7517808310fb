//! The model-description tests, one binary (each test binary is linked on its own): reading,
//! writing and validating FMI 2.0 and 3.0 model descriptions, ours and foreign.
mod broken_files;
mod declarations;
mod properties;
mod query;
mod round_trip;
mod samples;
mod tolerant_reading;
mod validate;
