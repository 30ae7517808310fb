//! The solver's tests, one binary (each test binary is linked on its own): accuracy against
//! closed forms, the two methods on non-stiff and stiff problems, and the edge cases of
//! stepping and event location.
mod accuracy;
mod common;
mod edge_cases;
mod jacobian;
mod methods;
