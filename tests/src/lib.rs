//! Integration tests across camsim's parts live in `tests/tests/`.
