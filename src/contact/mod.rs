//! Contact geometry: where a stylus ball touches an artefact, and collision checks.
