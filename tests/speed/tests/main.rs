//! The speed bench's tests, one binary (each test binary is linked on its own): the replay
//! checks behind rows 1 and 2, and the bench binary's quick mode.
mod replay;
mod smoke;
