//! See src/main.rs.
