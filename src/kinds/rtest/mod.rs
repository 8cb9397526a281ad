//! The R-test (ISO 10791-6).
