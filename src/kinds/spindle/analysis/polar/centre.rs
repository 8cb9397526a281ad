//! The polar-plot centres of ISO 230-7 §3.7 ([`Centre`]), a profile evaluated about one
//! ([`CentreFit`]), and why a profile cannot be ([`PolarError`]).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::math::{RAD_PER_DEG, Real};

/// The largest gap (rad) between neighbouring angles for which MIC and MCC are computed: 179°.
///
/// With a gap of `π − δ` the directions surround the centre only by `sin(δ/2)`, and profile
/// noise reaches the offset amplified by about `1/sin(δ/2)`: 115 at this limit, unbounded at
/// 180°.
pub const MAX_ANGLE_GAP: Real = 179.0 * RAD_PER_DEG;

/// A polar-plot centre of ISO 230-7 §3.7.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Centre {
    /// Polar chart centre: the sensor zero, offset `(0, 0)` (§3.7.2).
    #[serde(rename = "PC")]
    Pc,
    /// Least-squares circle centre (§3.7.4).
    #[serde(rename = "LSC")]
    Lsc,
    /// Minimum radial separation centre (§3.7.5).
    #[serde(rename = "MRS")]
    Mrs,
    /// Maximum inscribed circle centre (§3.7.6).
    #[serde(rename = "MIC")]
    Mic,
    /// Minimum circumscribed circle centre (§3.7.7).
    #[serde(rename = "MCC")]
    Mcc,
}

impl Centre {
    /// The five centres, in the order of ISO 230-7 §3.7.
    pub const ALL: [Centre; 5] = [
        Centre::Pc,
        Centre::Lsc,
        Centre::Mrs,
        Centre::Mic,
        Centre::Mcc,
    ];

    /// The abbreviation of ISO 230-7: "PC", "LSC", "MRS", "MIC" or "MCC".
    pub fn name(self) -> &'static str {
        match self {
            Centre::Pc => "PC",
            Centre::Lsc => "LSC",
            Centre::Mrs => "MRS",
            Centre::Mic => "MIC",
            Centre::Mcc => "MCC",
        }
    }
}

impl fmt::Display for Centre {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is none of PC, LSC, MRS, MIC, MCC.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown polar-plot centre \"{0}\" (expected PC, LSC, MRS, MIC or MCC)")]
pub struct UnknownCentre(pub String);

impl FromStr for Centre {
    type Err = UnknownCentre;

    /// The abbreviation, in any case ("lsc", "MRS", "Mcc").
    fn from_str(s: &str) -> Result<Centre, UnknownCentre> {
        Centre::ALL
            .into_iter()
            .find(|c| c.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| UnknownCentre(s.to_string()))
    }
}

/// A profile evaluated about one centre.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CentreFit {
    /// Which centre.
    pub centre: Centre,
    /// The centre's offset `(cx, cy)` from the polar chart centre (m), in the limaçon model.
    pub offset: [Real; 2],
    /// `min ρ_c` (m): the inner circle's radius minus `r0`.
    pub low: Real,
    /// `max ρ_c` (m): the outer circle's radius minus `r0`.
    pub high: Real,
    /// The points (indices, ascending) that fix the circles. PC, LSC: where the lowest and the
    /// highest residual are. MRS: the optimal basis, alternately on the outer and the inner
    /// circle. MCC (MIC): the outer (inner) contacts that certify the smallest maximum (largest
    /// minimum) and the points that fix the centre among equals. Each contact lies on the
    /// inner or the outer circle to within 2e-13 × max|p|.
    pub contacts: Vec<usize>,
}

impl CentreFit {
    /// The value about this centre, `high − low` (m): the difference in radii of the two
    /// concentric circles that just enclose the plot.
    pub fn value(&self) -> Real {
        self.high - self.low
    }
}

/// Why a profile cannot be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PolarError {
    /// Fewer than 3 points.
    #[error("a polar profile needs at least 3 points, got {0}")]
    TooFew(usize),
    /// The number of values is not the number of angles.
    #[error("{values} values do not match {angles} angles")]
    LengthMismatch {
        /// Number of values.
        values: usize,
        /// Number of angles.
        angles: usize,
    },
    /// A value, angle or offset is NaN or infinite.
    #[error("{what} {index} is not finite")]
    NonFinite {
        /// "value", "angle" or "offset".
        what: &'static str,
        /// Its index.
        index: usize,
    },
    /// Too few distinct directions for the centre (3 for LSC, 4 for MRS).
    #[error("the {centre} centre needs at least {needed} distinct angles")]
    TooFewDirections {
        /// The centre asked for.
        centre: Centre,
        /// Distinct directions it needs.
        needed: usize,
    },
    /// The angles do not surround the centre (a partial arc): the MIC or MCC is unbounded or
    /// ill-conditioned.
    #[error(
        "the angles leave a gap of {gap_deg:.1}° (more than {:.0}°): they do not surround the centre, so the {centre} centre is unbounded or ill-conditioned; use PC, LSC or MRS",
        MAX_ANGLE_GAP / RAD_PER_DEG
    )]
    NotSurrounded {
        /// The centre asked for.
        centre: Centre,
        /// The largest gap between neighbouring angles (degrees).
        gap_deg: Real,
    },
    /// The simplex could not certify its optimum (a numerical failure; should not happen).
    #[error("the {centre} solver could not certify its optimum: {reason}")]
    NotCertified {
        /// The centre asked for.
        centre: Centre,
        /// What failed.
        reason: &'static str,
    },
}
