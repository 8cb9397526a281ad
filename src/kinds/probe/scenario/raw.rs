//! The `[probe]` section as written ([`RawProbe`]), before any check.

use crate::math::Real;
use serde::Deserialize;
use toml::Spanned;

/// The raw `[probe]` section.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawProbe {
    pub(super) stylus_diameter_mm: Spanned<Real>,
    pub(super) stylus_radius_error_um: Option<Spanned<Real>>,
    pub(super) pretravel_um: Option<Spanned<Real>>,
    pub(super) lobing_um: Option<Spanned<Real>>,
    pub(super) lobing_phase_deg: Option<Spanned<Real>>,
    pub(super) pretravel_axial_um: Option<Spanned<Real>>,
    pub(super) repeatability_um: Option<Spanned<Real>>,
    pub(super) feed_mm_per_min: Option<Spanned<Real>>,
    pub(super) latency_ms: Option<Spanned<Real>>,
    pub(super) clearance_mm: Option<Spanned<Real>>,
    pub(super) overtravel_mm: Option<Spanned<Real>>,
    #[serde(default)]
    pub(super) sphere: Vec<Spanned<RawSphere>>,
    #[serde(default)]
    pub(super) ring: Vec<Spanned<RawRing>>,
    #[serde(default)]
    pub(super) ballplate: Vec<Spanned<RawPlate>>,
    #[serde(default)]
    pub(super) mesh: Vec<Spanned<RawMesh>>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRotary {
    pub(super) a_deg: Option<Real>,
    pub(super) b_deg: Option<Real>,
    pub(super) c_deg: Option<Real>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSphere {
    pub(super) diameter_mm: Spanned<Real>,
    pub(super) centre_mm: Spanned<[Real; 3]>,
    pub(super) points: Option<Spanned<i64>>,
    pub(super) incidence_deg: Option<Spanned<Real>>,
    pub(super) rotary: Option<Spanned<Vec<RawRotary>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRing {
    pub(super) diameter_mm: Spanned<Real>,
    pub(super) centre_mm: Spanned<[Real; 3]>,
    pub(super) points: Option<Spanned<i64>>,
    pub(super) axis: Option<Spanned<[Real; 3]>>,
    pub(super) rotary: Option<Spanned<RawRotary>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawPlate {
    pub(super) rows: Spanned<i64>,
    pub(super) columns: Spanned<i64>,
    pub(super) pitch_mm: Spanned<Real>,
    pub(super) ball_diameter_mm: Spanned<Real>,
    pub(super) points: Option<Spanned<i64>>,
    pub(super) incidence_deg: Option<Spanned<Real>>,
    pub(super) placements: Spanned<Vec<RawPlacement>>,
    pub(super) ball_offsets_um: Option<Spanned<Vec<[Real; 3]>>>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
pub(super) struct RawPlacement {
    pub(super) origin_mm: [Real; 3],
    pub(super) along_row: Option<[Real; 3]>,
    pub(super) across_rows: Option<[Real; 3]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMesh {
    pub(super) file: Spanned<String>,
    pub(super) units: Option<Spanned<String>>,
    pub(super) origin_mm: Option<Spanned<[Real; 3]>>,
    pub(super) rotation_deg: Option<Spanned<Real>>,
    pub(super) max_travel_mm: Option<Spanned<Real>>,
    pub(super) rotary: Option<Spanned<RawRotary>>,
    pub(super) points: Spanned<Vec<RawMeshPoint>>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMeshPoint {
    pub(super) start_mm: [Real; 3],
    pub(super) direction: [Real; 3],
}
