//! The touch probe on artefacts.
