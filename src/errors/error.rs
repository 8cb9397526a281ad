//! Why an error model does not fit a machine ([`ErrorModelError`]).

use super::name::ParameterName;
use crate::machine::Axis;

/// Why an error model does not fit a machine.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ErrorModelError {
    /// The parameter names an axis the machine does not have.
    #[error("{name}: the machine has no axis {axis}")]
    MissingAxis {
        /// The parameter.
        name: ParameterName,
        /// The axis.
        axis: Axis,
    },
    /// The name is not a parameter.
    #[error("{0}: {1}")]
    InvalidName(ParameterName, String),
    /// Location, squareness and tool errors are constants.
    #[error("{0}: location, squareness and tool errors are constants")]
    NotConstant(ParameterName),
    /// A function that does not repeat every turn on an axis that turns without end.
    #[error("{name}: {message}")]
    NotPeriodic {
        /// The parameter.
        name: ParameterName,
        /// What is wrong.
        message: String,
    },
    /// A name appears twice.
    #[error("{0} is given twice")]
    Duplicate(ParameterName),
}

impl ErrorModelError {
    /// The parameter the error is about.
    pub fn parameter(&self) -> ParameterName {
        match self {
            ErrorModelError::MissingAxis { name, .. }
            | ErrorModelError::InvalidName(name, _)
            | ErrorModelError::NotConstant(name)
            | ErrorModelError::NotPeriodic { name, .. }
            | ErrorModelError::Duplicate(name) => *name,
        }
    }
}
