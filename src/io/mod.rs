//! Files, and nothing above them: the primitives every measurement table shares (the CSV
//! dialect, the header row, errors that name the file, line and column) and writing outputs
//! whole (through temporary names, so a reader never sees half a file).
//!
//! Each test kind's table schema (reader and writer) lives in its folder
//! (`crate::kinds::<kind>::table`), on these primitives.

mod columns;
mod conditions;
mod path;
pub mod plausible;
mod table;
mod write;

pub use columns::not_read_line;
pub(crate) use columns::{Quantity, channel_slip, clock, looks_like, read_past, thermometer_slip};
pub use conditions::{Conditions, not_used_line};
pub use path::{PathError, relative_path};
pub use table::{CLOCK_MIN, CLOCK_S, Range, THERMOMETER, TableError, first_non_finite};
pub(crate) use table::{csv_reader, finite_number, number_within, read_file, read_header, row};
pub use write::{WriteError, check_folder_of, write_atomically, write_files};
