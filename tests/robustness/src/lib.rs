//! Robustness tests live in tests/robustness/tests/.
