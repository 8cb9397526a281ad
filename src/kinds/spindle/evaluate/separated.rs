//! The form separations of a record (Donaldson reversal, multi-probe) and everything they
//! separate: the artefact form and the error motion, each as harmonic coefficients and as
//! values about every centre.
//!
//! # What is separated
//!
//! - **Reversal** (ISO 230-7 Annex B) of one fixed radial probe at stator azimuth φ between
//!   the set-ups `normal` and `reversed` at one speed: the form `h(ψ)` and the motion along
//!   the probe's axis `E_φ = E_X cos φ + E_Y sin φ`. What turns with the artefact comes out as
//!   form, what stays with the rotor as motion ([`separation::donaldson_reversal`]).
//! - **Face reversal** (after Estler) of one face probe at radius `R` between the same
//!   set-ups: the part of the face motion that reverses, `R·E_B` along the probe's azimuth,
//!   and the face's form, with the axial motion taken out by a probe on the axis when there is
//!   one ([`separation::face_reversal`]).
//! - **Multi-probe** separation of three or more fixed radial probes at one height
//!   ([`separation::separate`], two-direction model): the form and the motion along X and Y;
//!   from these, the motion in the rotating sensitive direction, formula (1).
//!
//! # First harmonics
//!
//! A multi-probe layout cannot tell the form's 1 UPR from a motion (a centring offset turning
//! with the rotor moves the artefact's centre): harmonic 1 is given to the motion, and the
//! form is harmonics 2 up. The reversal separates both: the form's 1 UPR is the artefact's
//! centring on the rotor, the motion's the axis's own 1-UPR motion. Either way the form's
//! first harmonic is not form: roundness about LSC, MRS, MIC and MCC does not depend on it;
//! about PC it counts.
//!
//! # Asynchronous motion
//!
//! The form is synchronous, so what a probe reads beyond its synchronous profile is motion:
//! revolution by revolution, the motion is its separated synchronous profile plus the
//! asynchronous part of the readings — for a reversal, of the normal set-up's probe
//! (`−(r₁ − S₁)`, the probe facing the axis); for a multi-probe layout, the least-squares
//! displacement `(E_X, E_Y)` of the probes' asynchronous parts at each sample (all probes read
//! at one time). The values of that signal about each centre are the motion's total,
//! synchronous, asynchronous, inner, outer, fundamental and residual values.
//!
//! # Uncertainty
//!
//! A separated value takes the budget of its probes' tests (the largest, for a layout): a
//! reversal's form and motion are half the sum and the difference of two readings with that
//! budget, which keeps a probe's gain error whole and halves its noise, so the probe's U is
//! kept (an upper bound for the noise). A layout adds its misfit: `2 × rms` of what the
//! probes read that the model of form and motion cannot hold (azimuth and gain errors of the
//! probes show there). Left out: the artefact's repositioning between the set-ups of a
//! reversal (a centring change shows as 1 UPR only, which the profile centres remove).
//!
//! # Blind harmonics
//!
//! Harmonics the layout cannot see are zero in the form and the motion. Where some probe reads
//! more than its noise at one of them ([`separation::blind_with_content`]) the separated
//! synchronous values are not determined; the asynchronous value still is.

use super::uncertainty::{Contribution, TestUncertainty, student_t95};
use super::{EvaluateError, Options, ProbeKind, Segment, compact_list, kind};
use crate::kinds::spindle::analysis::motion::{
    self, Direction, ErrorMotionValues, Grid, Revolutions,
};
use crate::kinds::spindle::analysis::polar::{Centre, CentreFit};
use crate::kinds::spindle::analysis::separation::{self, Model};
use crate::kinds::spindle::analysis::spectrum;
use crate::kinds::spindle::record::{Sensing, SpindleRecord};
use crate::math::Real;
use std::f64::consts::TAU;

/// Artefact form separated from the error motion by one probe (reversal) or a layout
/// (multi-probe), at one speed.
#[derive(Clone, Debug)]
pub struct Separated {
    /// The method: `reversal`, `multi-probe`, `face reversal` or `face reversal with axial
    /// motion` (no probe on the axis: the form still holds the axial motion).
    pub method: &'static str,
    /// The probes used.
    pub probes: Vec<String>,
    /// Speed (rad/s).
    pub speed: Real,
    /// Highest harmonic separated: `⌈M/2⌉ − 1`, the highest below Nyquist.
    pub k_max: usize,
    /// Artefact form h(ψ) (m, outward positive) on the grid ψ_m = 2πm/M.
    pub form: Vec<Real>,
    /// `[a_k, b_k]` of the form, `h(ψ) = Σ a_k cos kψ + b_k sin kψ`, entry `k − 1` for
    /// k = 1..=k_max (m); zero at blind harmonics, and at 1 for a multi-probe layout.
    pub form_harmonics: Vec<[Real; 2]>,
    /// The form about each centre asked, in the order asked (roundness).
    pub form_values: Vec<CentreFit>,
    /// Synchronous error motion along X and Y (m) on the θ grid (reversal: along the probe
    /// only, in `motion_x`).
    pub motion_x: Vec<Real>,
    /// See `motion_x` (empty for a reversal).
    pub motion_y: Vec<Real>,
    /// The motion, direction by direction, with its values.
    pub motions: Vec<SeparatedMotion>,
    /// Harmonics the layout cannot see (multi-probe).
    pub blind: Vec<usize>,
    /// Those of `blind` at which a probe reads more than its noise: form or motion is there
    /// and unknown, so neither's value is determined ([`separation::blind_with_content`]).
    pub unknown: Vec<usize>,
    /// The values' uncertainty (module docs).
    pub uncertainty: TestUncertainty,
}

/// The separated error motion in one direction.
#[derive(Clone, Debug)]
pub struct SeparatedMotion {
    /// `X`, `Y`, `−X`, `−Y`, `φ°` (a fixed direction at that azimuth) or `rotating`.
    pub axis: String,
    /// The fixed direction's azimuth from X (rad); `None` for the rotating direction.
    pub azimuth: Option<Real>,
    /// `[a_k, b_k]` of the synchronous motion, `E(θ) = Σ a_k cos kθ + b_k sin kθ`, entry
    /// `k − 1` for k = 1..=k_max (m).
    pub harmonics: Vec<[Real; 2]>,
    /// Separated synchronous motion plus the readings' asynchronous part, revolution by
    /// revolution (m).
    pub signal: Revolutions,
    /// Its values about each centre asked (module docs).
    pub values: Vec<ErrorMotionValues>,
}

/// The name of a fixed direction at azimuth `phi` (rad): an axis when it is one (within
/// 1 µrad), else its azimuth in degrees.
fn axis_name(phi: Real) -> String {
    let deg = phi.to_degrees().rem_euclid(360.0);
    let named = [
        (0.0, "X"),
        (90.0, "Y"),
        (180.0, "−X"),
        (270.0, "−Y"),
        (360.0, "X"),
    ];
    named
        .iter()
        .find(|(at, _)| (deg - at).abs() < 1e-6_f64.to_degrees())
        .map_or_else(|| format!("{deg:.3}°"), |(_, name)| (*name).to_string())
}

/// The centres asked, the radial preferred one (LSC) first.
fn centres(options: &Options) -> Vec<Centre> {
    let preferred = Direction::Radial.preferred_centre();
    std::iter::once(preferred)
        .chain(options.centres.iter().copied().filter(|c| *c != preferred))
        .collect()
}

/// The values of a separated quantity, with the error's name.
fn motion_values(
    what: &str,
    signal: &Revolutions,
    centres: &[Centre],
    grid: &Grid,
) -> Result<Vec<ErrorMotionValues>, EvaluateError> {
    motion::values_about_on(signal, Direction::Radial, centres, grid).map_err(|source| {
        EvaluateError::Motion {
            test: what.to_string(),
            source,
        }
    })
}

/// The form's values about each centre.
fn form_values(
    what: &str,
    form: &[Real],
    centres: &[Centre],
    grid: &Grid,
) -> Result<Vec<CentreFit>, EvaluateError> {
    centres
        .iter()
        .map(|&c| {
            grid.angles()
                .fit(form, c)
                .map_err(|source| EvaluateError::Motion {
                    test: what.to_string(),
                    source: motion::MotionError::Centre(source),
                })
        })
        .collect()
}

/// `synchronous[m] + asynchronous[k·M + m]` as revolutions.
fn with_asynchronous(synchronous: &[Real], asynchronous: &[Real]) -> Revolutions {
    let m = synchronous.len();
    let values = asynchronous
        .chunks_exact(m)
        .flat_map(|revolution| revolution.iter().zip(synchronous).map(|(a, s)| a + s))
        .collect();
    Revolutions::new(m, values).expect("laid out like the probes")
}

/// The grid, the highest harmonic and the motion of a reversal: the separated synchronous
/// motion plus the normal set-up's asynchronous part, which is minus the reading's (the probe
/// faces the axis), scored about `centres`.
fn reversal_motion(
    what: &str,
    axis: String,
    azimuth: Real,
    normal: &Revolutions,
    r1: &[Real],
    synchronous: &[Real],
    centres: &[Centre],
) -> Result<(Grid, usize, SeparatedMotion), EvaluateError> {
    let m = r1.len();
    let grid = Grid::new(m).map_err(|source| EvaluateError::Motion {
        test: what.to_string(),
        source,
    })?;
    let k_max = (m - 1) / 2;
    let asynchronous: Vec<Real> = normal
        .values()
        .chunks_exact(m)
        .flat_map(|rev| rev.iter().zip(r1).map(|(v, s)| s - v))
        .collect();
    let signal = with_asynchronous(synchronous, &asynchronous);
    let motion = SeparatedMotion {
        axis,
        azimuth: Some(azimuth),
        harmonics: spectrum::harmonics(synchronous, k_max),
        values: motion_values(what, &signal, centres, &grid)?,
        signal,
    };
    Ok((grid, k_max, motion))
}

/// Donaldson reversal of each radial probe between the set-ups `normal` and `reversed` at
/// equal speeds.
pub(super) fn reversals(
    record: &SpindleRecord,
    segments: &[Segment],
    options: &Options,
) -> Result<Vec<Separated>, EvaluateError> {
    let mut out = Vec::new();
    let centres = centres(options);
    // Forward records only: the separations' conventions take the axis angle increasing.
    for normal in segments
        .iter()
        .filter(|s| s.setup == "normal" && s.speed >= 0.0)
    {
        let Some(reversed) = segments
            .iter()
            .find(|s| s.setup == "reversed" && s.speed == normal.speed)
        else {
            continue;
        };
        for (test, other) in normal.tests.iter().zip(&reversed.tests) {
            let single = test.probes.len() == 1 && test.sensing == Sensing::Fixed;
            if !single || other.name != test.name {
                continue;
            }
            if test.direction == Direction::Face {
                out.push(face_reversal(record, normal, test, other, &centres)?);
                continue;
            }
            if test.direction != Direction::Radial {
                continue;
            }
            let what = format!("reversal of {}", test.probes[0]);
            let azimuth = match record
                .probe(&test.probes[0])
                .map(|i| kind(&record.probes[i]))
            {
                Some(Some(ProbeKind::Radial { azimuth })) => azimuth,
                _ => continue,
            };
            let r1 = motion::synchronous(&test.signal);
            let r2 = motion::synchronous(&other.signal);
            let result = separation::donaldson_reversal(&r1, &r2).map_err(|source| {
                EvaluateError::Separation {
                    what: what.clone(),
                    source,
                }
            })?;
            let (grid, k_max, motion) = reversal_motion(
                &what,
                axis_name(azimuth),
                azimuth,
                &test.signal,
                &r1,
                &result.motion,
                &centres,
            )?;
            out.push(Separated {
                method: "reversal",
                probes: test.probes.clone(),
                speed: normal.speed,
                k_max,
                form_harmonics: spectrum::harmonics(&result.form, k_max),
                form_values: form_values(&what, &result.form, &centres, &grid)?,
                form: result.form,
                motion_x: result.motion,
                motion_y: Vec::new(),
                motions: vec![motion],
                blind: Vec::new(),
                unknown: Vec::new(),
                uncertainty: test.uncertainty.clone(),
            });
        }
    }
    Ok(out)
}

/// Estler's face reversal of one face probe between the set-ups `normal` and `reversed`
/// ([`separation::face_reversal`]): the part of the face motion that reverses with the set-up,
/// `W = R·E_B` along the probe's azimuth (a tilt times the radius, m), as the motion; what does
/// not, as the face's form — with the axial motion taken out when the record has a probe on
/// the axis, else with it left in (the report says which).
fn face_reversal(
    record: &SpindleRecord,
    normal: &Segment,
    test: &super::Test,
    other: &super::Test,
    centres: &[Centre],
) -> Result<Separated, EvaluateError> {
    let what = format!("face reversal of {}", test.probes[0]);
    let r1 = motion::synchronous(&test.signal);
    let r2 = motion::synchronous(&other.signal);
    let axial = normal
        .tests
        .iter()
        .find(|t| t.direction == Direction::Axial && t.probes.len() == 1)
        .map(|t| motion::synchronous(&t.signal));
    let result = separation::face_reversal(&r1, &r2, axial.as_deref()).map_err(|source| {
        EvaluateError::Separation {
            what: what.clone(),
            source,
        }
    })?;
    let azimuth = record
        .probe(&test.probes[0])
        .map(|i| record.probes[i].position)
        .map_or(0.0, |p| p[1].atan2(p[0]));
    // The probe reads −(E_N + W) − g, so the same construction as a radial reversal's.
    let (grid, k_max, motion) = reversal_motion(
        &what,
        format!("face tilt × radius at {}", axis_name(azimuth)),
        azimuth,
        &test.signal,
        &r1,
        &result.tilt,
        centres,
    )?;
    Ok(Separated {
        method: if result.axial_removed {
            "face reversal"
        } else {
            "face reversal with axial motion"
        },
        probes: test.probes.clone(),
        speed: normal.speed,
        k_max,
        form_harmonics: spectrum::harmonics(&result.form, k_max),
        form_values: form_values(&what, &result.form, centres, &grid)?,
        form: result.form,
        motion_x: result.tilt,
        motion_y: Vec::new(),
        motions: vec![motion],
        blind: Vec::new(),
        unknown: Vec::new(),
        uncertainty: test.uncertainty.clone(),
    })
}

/// Multi-probe separation (two-direction model) of three or more fixed radial probes at one
/// height, per segment.
pub(super) fn multiprobe(
    record: &SpindleRecord,
    segments: &[Segment],
    options: &Options,
    notes: &mut Vec<String>,
) -> Result<Vec<Separated>, EvaluateError> {
    let mut out = Vec::new();
    let centres = centres(options);
    let mut groups: Vec<(Real, Vec<(usize, Real)>)> = Vec::new();
    for (i, probe) in record.probes.iter().enumerate() {
        if let (Some(ProbeKind::Radial { azimuth }), Sensing::Fixed) = (kind(probe), probe.sensing)
        {
            let z = probe.position[2];
            match groups.iter_mut().find(|(h, _)| (h - z).abs() < 1e-6) {
                Some((_, members)) => members.push((i, azimuth)),
                None => groups.push((z, vec![(i, azimuth)])),
            }
        }
    }
    for (_, members) in groups.iter().filter(|(_, m)| m.len() >= 3) {
        let names: Vec<String> = members
            .iter()
            .map(|(i, _)| record.probes[*i].name.clone())
            .collect();
        let what = format!("multi-probe {}", names.join("+"));
        let azimuths: Vec<Real> = members.iter().map(|(_, a)| *a).collect();
        // The probe azimuths of the table describe the normal set-up: a reversed or turned
        // set-up moves the probes (or the artefact), so only normal, forward records are
        // separated.
        let separable =
            |s: &&Segment| (s.setup.is_empty() || s.setup == "normal") && s.speed >= 0.0;
        for segment in segments.iter().filter(separable) {
            let tests: Vec<&super::Test> = members
                .iter()
                .map(|(i, _)| {
                    segment
                        .tests
                        .iter()
                        .find(|t| t.probes == [record.probes[*i].name.clone()])
                        .expect("every radial probe has its own test")
                })
                .collect();
            let signals: Vec<&Revolutions> = tests.iter().map(|t| &t.signal).collect();
            let profiles: Vec<Vec<Real>> = signals.iter().map(|s| motion::synchronous(s)).collect();
            let result = separation::separate(
                &profiles,
                &azimuths,
                Model::TwoDirection,
                separation::Options {
                    k_max: None,
                    condition_limit: options.condition_limit,
                },
            )
            .map_err(|source| EvaluateError::Separation {
                what: what.clone(),
                source,
            })?;
            if !result.blind.is_empty() {
                let note = format!(
                    "{what}: the layout cannot see harmonics {}",
                    compact_list(&result.blind)
                );
                if !notes.contains(&note) {
                    notes.push(note);
                }
            }
            let m = profiles[0].len();
            let grid = Grid::new(m).map_err(|source| EvaluateError::Motion {
                test: what.clone(),
                source,
            })?;
            let [async_x, async_y] = asynchronous_xy(&signals, &profiles, &azimuths);
            let x = with_asynchronous(&result.motion_x, &async_x);
            let y = with_asynchronous(&result.motion_y, &async_y);
            let rotating = rotating(&x, &y);
            let k_max = result.k_max;
            let mut motions = Vec::new();
            for (axis, azimuth, signal) in [
                ("X", Some(0.0), x),
                ("Y", Some(TAU / 4.0), y),
                ("rotating", None, rotating),
            ] {
                motions.push(SeparatedMotion {
                    axis: axis.to_string(),
                    azimuth,
                    harmonics: spectrum::harmonics(&motion::synchronous(&signal), k_max),
                    values: motion_values(&format!("{what} {axis}"), &signal, &centres, &grid)?,
                    signal,
                });
            }
            let widest = tests
                .iter()
                .max_by(|a, b| a.uncertainty.single.total_cmp(&b.uncertainty.single))
                .expect("three probes or more");
            let mut contributions = widest.uncertainty.contributions.clone();
            // The widest of the form's and the motion's, with its Student factor.
            let (rms, dof) = (0..3)
                .map(|i| (result.misfit_error_rms[i], result.misfit_dof[i]))
                .fold((0.0, Real::INFINITY), |best, (r, n)| {
                    if r * student_t95(n) > best.0 * student_t95(best.1) {
                        (r, n)
                    } else {
                        best
                    }
                });
            let t = student_t95(dof);
            contributions.push(Contribution {
                source: format!(
                    "separation: the probes' misfit to the layout's model, propagated: {:.4} µm rms per sample × t95({dof:.1} dof) = {t:.2}",
                    rms * 1e6
                ),
                u: t * rms,
                averages: false,
            });
            let mut missing = widest.uncertainty.missing.clone();
            if !result.unchecked.is_empty() {
                missing.push(format!(
                    "the layout has no more probes than unknowns at harmonics {}: errors of probe azimuth or gain there are not seen",
                    compact_list(&result.unchecked)
                ));
            }
            let uncertainty =
                TestUncertainty::combine(contributions, missing, widest.signal.count());
            out.push(Separated {
                method: "multi-probe",
                probes: names.clone(),
                speed: segment.speed,
                k_max,
                form_harmonics: spectrum::harmonics(&result.form, k_max),
                form_values: form_values(&what, &result.form, &centres, &grid)?,
                form: result.form,
                motion_x: result.motion_x,
                motion_y: result.motion_y,
                motions,
                unknown: separation::blind_with_content(&profiles, &result.blind),
                blind: result.blind,
                uncertainty,
            });
        }
    }
    Ok(out)
}

/// The asynchronous motion `(E_X, E_Y)` at every sample: the least-squares displacement from
/// the probes' asynchronous parts `r_j − S_j = −(E_X cos φ_j + E_Y sin φ_j)` (a probe at
/// azimuth φ faces the axis), revolution-major like the signals.
fn asynchronous_xy(
    signals: &[&Revolutions],
    synchronous: &[Vec<Real>],
    azimuths: &[Real],
) -> [Vec<Real>; 2] {
    // Normal equations of the columns −cos φ_j, −sin φ_j, inverted once.
    let d: Vec<[Real; 2]> = azimuths.iter().map(|a| [-a.cos(), -a.sin()]).collect();
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for [c, s] in &d {
        sxx += c * c;
        sxy += c * s;
        syy += s * s;
    }
    let det = sxx * syy - sxy * sxy;
    let m = synchronous[0].len();
    let n = signals[0].values().len();
    let (mut x, mut y) = (vec![0.0; n], vec![0.0; n]);
    for i in 0..n {
        let (mut bx, mut by) = (0.0, 0.0);
        for ((signal, sync), [c, s]) in signals.iter().zip(synchronous).zip(&d) {
            let a = signal.values()[i] - sync[i % m];
            bx += c * a;
            by += s * a;
        }
        x[i] = (syy * bx - sxy * by) / det;
        y[i] = (sxx * by - sxy * bx) / det;
    }
    [x, y]
}

/// Formula (1): `E_X cos θ + E_Y sin θ`, sample by sample.
fn rotating(x: &Revolutions, y: &Revolutions) -> Revolutions {
    let m = x.samples_per_revolution();
    let angles = x.angles();
    let mut values = vec![0.0; x.values().len()];
    for ((out, xs), ys) in values
        .chunks_exact_mut(m)
        .zip(x.values().chunks_exact(m))
        .zip(y.values().chunks_exact(m))
    {
        motion::rotating_radial(xs, ys, &angles, out);
    }
    Revolutions::new(m, values).expect("laid out like the probes")
}
