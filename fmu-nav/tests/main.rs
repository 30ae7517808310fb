//! LanderNav's tests, one binary (each test binary is linked on its own). The latency history's
//! heap test is a binary of its own (heap_size.rs): it installs a counting global allocator.
mod conformance;
mod statistics;
mod through_abi;
