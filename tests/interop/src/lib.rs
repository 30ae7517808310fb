//! Interoperability tests live in tests/interop/tests/.
