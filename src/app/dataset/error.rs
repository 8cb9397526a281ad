//! Why a dataset could not be made, and the small adapters that turn a failed read or write
//! into that reason with the path it concerns.

use crate::app::RunError;
use std::path::Path;

/// Why a dataset could not be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DatasetError {
    /// A case's scenario is not valid (a drawn value outside what the scenario accepts).
    #[error("case {id}: {message} (bound the prior that drew it)")]
    Case {
        /// The case.
        id: u64,
        /// The scenario's message.
        message: String,
    },
    /// A case could not be simulated.
    #[error("case {id}: {source}")]
    Run {
        /// The case.
        id: u64,
        /// Why.
        source: RunError,
    },
    /// A case's table does not fit the dataset's schema.
    #[error("case {id}: {table}: {message}")]
    Table {
        /// The case.
        id: u64,
        /// The table.
        table: String,
        /// What is wrong.
        message: String,
    },
    /// The options do not make a layout.
    #[error("{0}")]
    Options(String),
    /// The output folder holds another dataset.
    #[error("{dir}: {message}")]
    Layout {
        /// The folder.
        dir: String,
        /// What is there.
        message: String,
    },
    /// A file could not be read or written.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// The system's message.
        message: String,
    },
}

pub(super) fn io_error(path: &Path) -> impl Fn(std::io::Error) -> DatasetError + '_ {
    move |e| DatasetError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

pub(super) fn parquet_error(
    path: &Path,
) -> impl Fn(parquet::errors::ParquetError) -> DatasetError + '_ {
    move |e| DatasetError::Io {
        path: path.display().to_string(),
        message: format!("cannot write Parquet: {e}"),
    }
}
