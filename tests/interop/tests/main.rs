//! The closed loop in other masters, one binary (each test binary is linked on its own): fmpy in
//! FMI 2.0 and 3.0, fmpy's SSP runner, libcosim, Ecos, pythonfmu and pythonfmu3 FMUs, the
//! documented examples, the FMU checkers, the FMUs' shipped references in fmpy and the SSP 2.0
//! schemas (pyssp-standard).
mod checkers;
mod container_fmu;
mod docs_example;
mod ecos;
mod fmpy3_master;
mod fmpy3_touchdown;
mod fmpy_master;
mod fmpy_references;
mod fmpy_ssp;
mod libcosim;
mod python_plant;
mod pythonfmu3;
mod pythonfmu3_types;
mod scripts;
mod ssp2_package;
mod ssp_package;
mod terminals;
