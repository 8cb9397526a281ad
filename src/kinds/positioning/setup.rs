//! How the laser is set up, as the scenario's `[laser]` section, a table's preamble and the
//! model of the readings all name it: which side carries the interferometer ([`Mounting`])
//! and when its reading is set to zero ([`Zeroing`]).

/// Which side carries the interferometer (and the beam with it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mounting {
    /// Interferometer on the workpiece side, reflector on the tool at `beam_offset` from the tip.
    InterferometerOnWorkpiece,
    /// Interferometer on the tool side, its beam fixed in the tool frame; the reflector is fixed
    /// on the workpiece where the point `beam_offset` from the tip was at the zero. The
    /// instrument is set to count positive when the tool moves positively.
    InterferometerOnTool,
}

/// When the laser's reading is set to zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Zeroing {
    /// At the first reading of each run.
    EachRun,
    /// Once, at the first reading of the test.
    Once,
}
