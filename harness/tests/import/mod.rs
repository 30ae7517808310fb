//! The harness's side of importing FMUs and systems: the command line's verdicts, exit codes and messages with FMI 3.0 FMUs, with an
//! FMU that is not a lander, with archives the importer refuses and with outputs that stop
//! being numbers; and the scenarios it loads from SSP packages, SSDs and its shipped files.
//! The importer's and the master's own behaviour is tested in fmi-import/tests and
//! cosim/tests.
mod fmi3_import;
mod fmi3_types;
mod fmu_archive;
mod model_exchange;
mod non_finite;
mod oscillator;
mod ssp;
mod terminals;
