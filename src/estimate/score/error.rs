//! Why an estimate could not be scored ([`ScoreError`]): another machine, a term in the
//! wrong unit, or a file of the wrong shape, each said of its key path and then of its file.

/// Why an estimate could not be scored.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ScoreError {
    /// The estimate or the truth is for another machine than the one loaded.
    #[error(
        "{file} is for machine \"{named}\", but the machine loaded is \"{loaded}\"; score it with that machine's URDF"
    )]
    Machine {
        /// `estimate` or `truth`.
        file: String,
        /// The machine the file names.
        named: String,
        /// The machine loaded.
        loaded: String,
    },
    /// A term in a unit that does not fit its parameter or axis.
    #[error("{}{parameter} {reason}; expected {expected}", located(.file, .path))]
    Units {
        /// `estimate` or `truth` (empty from [`error_model_of`](super::error_model_of)).
        file: String,
        /// Key path of the term, e.g. `errors.EA0C.terms.constant_um`.
        path: String,
        /// The parameter.
        parameter: String,
        /// What the parameter is, e.g. `is a rotation`.
        reason: String,
        /// The key or unit expected, e.g. `constant_urad`.
        expected: String,
    },
    /// The JSON does not have the expected shape or values.
    #[error("{}{message}", located(.file, .path))]
    Shape {
        /// `estimate` or `truth` (empty from [`error_model_of`](super::error_model_of)).
        file: String,
        /// Key path, e.g. `errors.EXX.standard_uncertainty.polynomial_um[1]`.
        path: String,
        /// What is wrong.
        message: String,
    },
}

/// `file: path: `, leaving out the empty parts.
fn located(file: &str, path: &str) -> String {
    [file, path]
        .iter()
        .filter(|part| !part.is_empty())
        .map(|part| format!("{part}: "))
        .collect()
}

impl ScoreError {
    pub(super) fn shape(path: impl Into<String>, message: impl Into<String>) -> ScoreError {
        ScoreError::Shape {
            file: String::new(),
            path: path.into(),
            message: message.into(),
        }
    }

    /// The same error, said of the file `name`: [`score`](super::score) says `estimate` and `truth`; a
    /// command line may put the paths instead.
    pub fn in_file(mut self, name: &str) -> ScoreError {
        match &mut self {
            ScoreError::Machine { file, .. }
            | ScoreError::Units { file, .. }
            | ScoreError::Shape { file, .. } => *file = name.to_string(),
        }
        self
    }
}
