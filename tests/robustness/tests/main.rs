//! The FMUs under hostile use, one binary (each test binary is linked on its own): API fuzzing,
//! the bad-input table, threads, fmpy cycles, library size and long runs. The leak test is a
//! binary of its own (leaks.rs): it measures this process's resident memory.
mod bad_input;
mod common;
mod fmpy_cycles;
mod fuzz_api;
mod library_size;
mod long_run;
mod threads;
