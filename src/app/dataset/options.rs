//! What `mtwin dataset` is asked to make: the layout and the folder, as the command line
//! gives them.

use std::path::PathBuf;

/// What to make.
#[derive(Clone, Debug)]
pub struct Options {
    /// Number of cases.
    pub count: u64,
    /// Shard layout.
    pub shards: u64,
    /// Only this shard (else every shard).
    pub only: Option<u64>,
    /// Worker threads (else all cores).
    pub threads: Option<usize>,
    /// The dataset folder.
    pub out: PathBuf,
}
