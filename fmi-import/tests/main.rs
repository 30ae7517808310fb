//! The importer's tests, one binary (each test binary is linked on its own): the loader
//! against an independent C stub FMU and against the export layer's Oscillator, `.fmu`
//! archives, and FMI 3.0 FMUs beside their FMI 2.0 twins, their FMU states included.
mod archives;
mod common;
mod derivatives;
mod files;
mod fmi3_import;
mod fmi3_states;
mod fmi3_types;
mod fmu_archive;
mod oscillator;
mod stub_fmu;
