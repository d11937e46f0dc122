//! Integration tests across camsim's parts live in `tests/tests/`.

pub mod weak_spring;
