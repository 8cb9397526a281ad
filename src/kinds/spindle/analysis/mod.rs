//! ISO 230-7 evaluation of spindle records, on plain arrays (SI: m, rad).
//!
//! | file | owns |
//! |---|---|
//! | [`polar`] | the polar-plot centres PC, LSC, MRS, MIC, MCC and the value about each |
//! | [`motion`] | revolutions × angles: synchronous, asynchronous, inner, outer, fundamental, residual; the error motion values |
//! | [`spectrum`] | the amplitude spectrum of a record, lines marked synchronous or asynchronous |
//! | [`separation`] | artefact form from error motion: Donaldson reversal, multi-probe (two-direction model) with the harmonics a layout cannot see; tilt from two stations |

pub mod motion;
pub mod polar;
pub mod separation;
pub mod spectrum;
