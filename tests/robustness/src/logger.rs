//! A recording logger: the workspace's test kit logger, formatting every message in C
//! exactly as a C master would (so a format string that does not match its arguments would
//! show up, under valgrind, as a read of garbage).
pub use fmi_testkit::{Record, TestLogger as LogSink};
