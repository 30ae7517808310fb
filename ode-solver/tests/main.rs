//! The solver's tests, one binary (each test binary is linked on its own): accuracy against
//! closed forms and the edge cases of stepping and event location.
mod accuracy;
mod common;
mod edge_cases;
