//! The samples of spindle discovery and its linear model: the columns, the least-squares fit on
//! a fold's training samples, and the searches for a model's free frequencies and time
//! constant.
//!
//! Every probe is modelled on its own readings with the same columns (one design, one
//! factorisation, a right-hand side per probe); the searched values (a harmonic order, a line's
//! frequency, a drift's time constant) are shared by the probes, since one error motion shows
//! in all of them.

use super::super::record::SpindleRecord;
use crate::math::Real;
use mtwin_kernels::FftPlanner;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use rustfft::num_complex::Complex;
use std::collections::HashMap;
use std::f64::consts::TAU;
use std::sync::{Arc, Mutex};

/// Eigenvalues of the unit-diagonal Gram matrix below this fraction of the largest are cut
/// (singular values under 1e-6 of the largest: columns the samples cannot tell apart get the
/// minimum-norm share).
const RANK_TOLERANCE: Real = 1e-12;

/// Why a record cannot be searched.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum DiscoveryDataError {
    /// The set-up asked is not in the record.
    #[error("set-up `{0}` is not in the record (set-ups: {1})")]
    UnknownSetup(String, String),
    /// A speed segment has too few revolutions to hold some out.
    #[error(
        "the segment at {rpm:.0} min⁻¹ has {revolutions} revolution(s): discovery holds revolutions out and needs at least 3 in every speed"
    )]
    TooFewRevolutions {
        /// The segment's speed (min⁻¹).
        rpm: Real,
        /// Its revolutions.
        revolutions: usize,
    },
    /// No probe.
    #[error("the record has no probe")]
    NoProbe,
}

/// One stretch of constant speed in the set-up searched.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    /// Speed (rad/s, signed).
    pub speed: Real,
    /// Revolutions recorded.
    pub revolutions: usize,
    /// Its samples (the set-up's samples are in time order, a segment's contiguous).
    pub samples: std::ops::Range<usize>,
    /// Revolutions per second: from the turns and times recorded when the times differ (a
    /// record without a speed column, or a speed that is not the commanded one), else the
    /// commanded speed's.
    pub turns_per_second: Real,
}

/// The samples of one set-up, ready for fitting. SI (m, rad, s).
#[derive(Clone, Debug)]
pub struct Data {
    /// The set-up searched (`""` for a record of one set-up).
    pub setup: String,
    /// The record's other set-ups, left out.
    pub other_setups: Vec<String>,
    /// Probe names.
    pub probes: Vec<String>,
    /// Samples per revolution of the record.
    pub samples_per_revolution: usize,
    /// The axis angle of each sample (rad): the argument of synchronous terms.
    pub theta: Vec<Real>,
    /// Turns travelled since the segment's first revolution (the argument of asynchronous
    /// lines, in cycles per revolution).
    pub turns: Vec<Real>,
    /// Time of each sample (s).
    pub time: Vec<Real>,
    /// The segment of each sample.
    pub segment: Vec<usize>,
    /// The revolution of each sample within its segment (from 0).
    pub revolution: Vec<usize>,
    /// The segments, in time order.
    pub segments: Vec<Segment>,
    /// Readings (m), one vector per probe.
    pub readings: Vec<Vec<Real>>,
    /// The values of the columns that searches do not move (offsets, harmonics), computed
    /// once.
    cache: ColumnCache,
}

/// Column values computed once, shared between fits.
#[derive(Debug, Default)]
struct ColumnCache(Mutex<HashMap<ColumnKey, Arc<Vec<Real>>>>);

/// A cached column: its kind, order or segment, segment.
type ColumnKey = (u8, usize, usize);

impl Clone for ColumnCache {
    fn clone(&self) -> ColumnCache {
        ColumnCache::default()
    }
}

impl Data {
    /// The values of `column` at every sample (cached unless a search moves it).
    pub fn column(&self, column: Column) -> Arc<Vec<Real>> {
        let compute = || Arc::new((0..self.len()).map(|i| column.value(self, i)).collect());
        let key = match column {
            Column::Offset(s) => (0, s, 0),
            Column::Cos(k) => (1, k, 0),
            Column::Sin(k) => (2, k, 0),
            Column::SegmentCos(k, s) => (3, k, s),
            Column::SegmentSin(k, s) => (4, k, s),
            Column::LineCos(..) | Column::LineSin(..) | Column::Drift(..) => return compute(),
        };
        let mut cache = self.cache.0.lock().unwrap_or_else(|e| e.into_inner());
        cache.entry(key).or_insert_with(compute).clone()
    }

    /// The samples of set-up `setup` of `record` (the first set-up when `None`).
    pub fn new(
        record: &SpindleRecord,
        samples_per_revolution: usize,
        setup: Option<&str>,
    ) -> Result<Data, DiscoveryDataError> {
        if record.probes.is_empty() {
            return Err(DiscoveryDataError::NoProbe);
        }
        let mut setups: Vec<String> = Vec::new();
        for s in &record.setup {
            if !setups.contains(s) {
                setups.push(s.clone());
            }
        }
        let chosen = match setup {
            Some(name) => setups
                .iter()
                .find(|s| s.as_str() == name)
                .cloned()
                .ok_or_else(|| {
                    DiscoveryDataError::UnknownSetup(name.to_string(), setups.join(", "))
                })?,
            None => setups.first().cloned().unwrap_or_default(),
        };
        let index: Vec<usize> = (0..record.len())
            .filter(|&i| record.setup[i] == chosen)
            .collect();
        let mut data = Data {
            other_setups: setups.into_iter().filter(|s| *s != chosen).collect(),
            setup: chosen,
            probes: record.probes.iter().map(|p| p.name.clone()).collect(),
            samples_per_revolution,
            theta: Vec::with_capacity(index.len()),
            turns: Vec::with_capacity(index.len()),
            time: Vec::with_capacity(index.len()),
            segment: Vec::with_capacity(index.len()),
            revolution: Vec::with_capacity(index.len()),
            segments: Vec::new(),
            readings: vec![Vec::with_capacity(index.len()); record.probes.len()],
            cache: ColumnCache::default(),
        };
        let mut first_revolution = 0;
        for (position, &i) in index.iter().enumerate() {
            let new_segment = position == 0 || record.speed[i] != record.speed[index[position - 1]];
            if new_segment {
                data.segments.push(Segment {
                    speed: record.speed[i],
                    revolutions: 0,
                    samples: position..position,
                    turns_per_second: 0.0,
                });
                first_revolution = record.revolution[i];
            }
            let s = data.segments.len() - 1;
            let revolution = record.revolution[i].saturating_sub(first_revolution);
            let segment = &mut data.segments[s];
            segment.revolutions = segment.revolutions.max(revolution + 1);
            segment.samples.end = position + 1;
            // The angle travelled since the index, forward in time for either sense.
            let travelled = if segment.speed < 0.0 {
                (TAU - record.angle[i]).rem_euclid(TAU)
            } else {
                record.angle[i]
            };
            data.theta.push(record.angle[i]);
            data.turns.push(revolution as Real + travelled / TAU);
            data.time.push(record.time[i]);
            data.segment.push(s);
            data.revolution.push(revolution);
            for (p, values) in data.readings.iter_mut().enumerate() {
                values.push(record.readings[p][i]);
            }
        }
        for segment in &mut data.segments {
            let (first, last) = (segment.samples.start, segment.samples.end - 1);
            let elapsed = data.time[last] - data.time[first];
            segment.turns_per_second = if elapsed > 0.0 {
                (data.turns[last] - data.turns[first]) / elapsed
            } else {
                segment.speed.abs() / TAU
            };
        }
        if let Some(short) = data.segments.iter().find(|s| s.revolutions < 3) {
            return Err(DiscoveryDataError::TooFewRevolutions {
                rpm: short.speed * 60.0 / TAU,
                revolutions: short.revolutions,
            });
        }
        Ok(data)
    }

    /// Number of samples per probe.
    pub fn len(&self) -> usize {
        self.theta.len()
    }

    /// Whether there is no sample.
    pub fn is_empty(&self) -> bool {
        self.theta.is_empty()
    }

    /// The fewest revolutions of any segment.
    pub fn fewest_revolutions(&self) -> usize {
        self.segments
            .iter()
            .map(|s| s.revolutions)
            .min()
            .unwrap_or(0)
    }

    /// The time span of the set-up (s).
    pub fn time_span(&self) -> (Real, Real) {
        self.time
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), &t| {
                (l.min(t), h.max(t))
            })
    }
}

/// One column of the design.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Column {
    /// 1 in segment `s`, else 0: each speed's mean reading.
    Offset(usize),
    /// cos kθ.
    Cos(usize),
    /// sin kθ.
    Sin(usize),
    /// cos kθ in segment `s` only (speed dependence of harmonic `k`).
    SegmentCos(usize, usize),
    /// sin kθ in segment `s` only.
    SegmentSin(usize, usize),
    /// cos 2πf·turns in segment `s` only (an asynchronous line at `f` cycles per revolution).
    LineCos(Real, usize),
    /// sin 2πf·turns in segment `s` only.
    LineSin(Real, usize),
    /// The drift's shape over the set-up's time span `(t0, t1)`, 0 at `t0` and 1 at `t1`:
    /// linear when the time constant is `None`, else `1 − e^{−(t−t0)/τ}` scaled.
    Drift(Option<Real>, Real, Real),
}

impl Column {
    /// The samples where the column can be non-zero.
    pub fn support(self, data: &Data) -> std::ops::Range<usize> {
        match self {
            Column::Offset(s)
            | Column::SegmentCos(_, s)
            | Column::SegmentSin(_, s)
            | Column::LineCos(_, s)
            | Column::LineSin(_, s) => data.segments[s].samples.clone(),
            _ => 0..data.len(),
        }
    }

    /// The column's value at sample `i` of `data`.
    pub fn value(self, data: &Data, i: usize) -> Real {
        let in_segment = |s: usize| data.segment[i] == s;
        match self {
            Column::Offset(s) => Real::from(u8::from(in_segment(s))),
            Column::Cos(k) => (k as Real * data.theta[i]).cos(),
            Column::Sin(k) => (k as Real * data.theta[i]).sin(),
            Column::SegmentCos(k, s) if in_segment(s) => (k as Real * data.theta[i]).cos(),
            Column::SegmentSin(k, s) if in_segment(s) => (k as Real * data.theta[i]).sin(),
            Column::LineCos(f, s) if in_segment(s) => (TAU * f * data.turns[i]).cos(),
            Column::LineSin(f, s) if in_segment(s) => (TAU * f * data.turns[i]).sin(),
            Column::Drift(tau, t0, t1) => drift_shape(tau, t0, t1, data.time[i]),
            _ => 0.0,
        }
    }
}

/// The drift shape: 0 at `t0`, 1 at `t1`; linear, or a first-order approach with time
/// constant `tau`.
pub fn drift_shape(tau: Option<Real>, t0: Real, t1: Real, t: Real) -> Real {
    let span = (t1 - t0).max(Real::MIN_POSITIVE);
    match tau {
        None => (t - t0) / span,
        Some(tau) => (1.0 - (-(t - t0) / tau).exp()) / (1.0 - (-span / tau).exp()),
    }
}

/// A linear fit of every probe on one design.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearFit {
    /// The columns.
    pub columns: Vec<Column>,
    /// Coefficients, one vector per probe (column order).
    pub coefficients: Vec<Vec<Real>>,
    /// Measured − fitted at every sample (all samples, training or not), one vector per probe.
    pub residuals: Vec<Vec<Real>>,
}

impl LinearFit {
    /// Sum of squared training residuals over every probe.
    pub fn training_sse(&self, train: &[bool]) -> Real {
        self.residuals
            .iter()
            .map(|r| {
                r.iter()
                    .zip(train)
                    .filter(|(_, t)| **t)
                    .map(|(v, _)| v * v)
                    .sum::<Real>()
            })
            .sum()
    }

    /// The coefficient of `column` for probe `p` (0 when the design has no such column).
    pub fn coefficient(&self, p: usize, column: Column) -> Real {
        self.columns
            .iter()
            .position(|c| *c == column)
            .map_or(0.0, |j| self.coefficients[p][j])
    }
}

/// Least squares of every probe's readings on `columns`, over the samples where `train` is
/// true; residuals at every sample. The Gram matrix and the right-hand sides are dot products
/// over the training samples, each computed in one piece (in parallel, so the result does not
/// depend on the thread count).
pub fn fit_linear(data: &Data, columns: &[Column], train: &[bool]) -> LinearFit {
    let p = columns.len();
    let values: Vec<Arc<Vec<Real>>> = columns.par_iter().map(|c| data.column(*c)).collect();
    // The columns with the held-out samples zeroed: plain dot products from here on.
    let masked: Vec<Vec<Real>> = values
        .par_iter()
        .map(|v| {
            v.iter()
                .zip(train)
                .map(|(x, &t)| if t { *x } else { 0.0 })
                .collect()
        })
        .collect();
    let supports: Vec<std::ops::Range<usize>> = columns.iter().map(|c| c.support(data)).collect();
    let pairs: Vec<(usize, usize)> = (0..p).flat_map(|a| (a..p).map(move |b| (a, b))).collect();
    let entries: Vec<Real> = pairs
        .par_iter()
        .map(|&(a, b)| {
            let both =
                supports[a].start.max(supports[b].start)..supports[a].end.min(supports[b].end);
            if both.is_empty() {
                0.0
            } else {
                dot(&masked[a][both.clone()], &values[b][both])
            }
        })
        .collect();
    let mut gram = DMatrix::<Real>::zeros(p, p);
    for (&(a, b), &v) in pairs.iter().zip(&entries) {
        gram[(a, b)] = v;
        gram[(b, a)] = v;
    }
    let scale: Vec<Real> = (0..p)
        .map(|j| {
            let d = gram[(j, j)];
            if d > 0.0 { 1.0 / d.sqrt() } else { 0.0 }
        })
        .collect();
    let scaled = DMatrix::from_fn(p, p, |a, b| gram[(a, b)] * scale[a] * scale[b]);
    let eigen = mtwin_kernels::linalg::symmetric_eigen(scaled);
    let largest = eigen.eigenvalues.iter().copied().fold(0.0, Real::max);
    let (coefficients, residuals): (Vec<Vec<Real>>, Vec<Vec<Real>>) = data
        .readings
        .par_iter()
        .map(|y| {
            let rhs = DVector::from_fn(p, |j, _| {
                let at = supports[j].clone();
                dot(&masked[j][at.clone()], &y[at]) * scale[j]
            });
            // Pseudo-inverse within the rank cut: V · diag(1/λ) · Vᵀ · rhs.
            let projected = eigen.eigenvectors.transpose() * rhs;
            let inverted = DVector::from_fn(p, |j, _| {
                let lambda = eigen.eigenvalues[j];
                if lambda > largest * RANK_TOLERANCE {
                    projected[j] / lambda
                } else {
                    0.0
                }
            });
            let solution = &eigen.eigenvectors * inverted;
            let c: Vec<Real> = (0..p).map(|j| solution[j] * scale[j]).collect();
            let mut r = y.clone();
            for ((column, &cj), at) in values.iter().zip(&c).zip(&supports) {
                for (ri, v) in r[at.clone()].iter_mut().zip(&column[at.clone()]) {
                    *ri -= cj * v;
                }
            }
            (c, r)
        })
        .unzip();
    LinearFit {
        columns: columns.to_vec(),
        coefficients,
        residuals,
    }
}

/// Σ aᵢbᵢ in eight interleaved partial sums (vectorised; the same order every time).
fn dot(a: &[Real], b: &[Real]) -> Real {
    let mut lanes = [0.0; 8];
    let (head_a, tail_a) = a.split_at(a.len() - a.len() % 8);
    let (head_b, tail_b) = b.split_at(head_a.len());
    for (x, y) in head_a.chunks_exact(8).zip(head_b.chunks_exact(8)) {
        for k in 0..8 {
            lanes[k] += x[k] * y[k];
        }
    }
    let tail: Real = tail_a.iter().zip(tail_b).map(|(x, y)| x * y).sum();
    lanes.iter().sum::<Real>() + tail
}

/// The peak of a search: the value found and its statistic.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    /// The harmonic order or the frequency (cycles per revolution).
    pub at: Real,
    /// The summed F statistic over the probes: `Σ_p (ΔSSE_p / 2) / (SSE_p / n_p)`, the
    /// reduction of each probe's sum of squares by a sine–cosine pair at `at`, in units of its
    /// residual variance.
    pub f: Real,
    /// The number of independent values searched (for the false-alarm level).
    pub searched: usize,
}

/// The synchronous harmonic `k` in `lowest..=highest`, not in `taken`, that best explains the
/// training residuals: the harmonics of each probe's revolution-averaged residual.
pub fn search_harmonic(
    data: &Data,
    residuals: &[Vec<Real>],
    train: &[bool],
    lowest: usize,
    taken: &[usize],
) -> Option<Peak> {
    let m = data.samples_per_revolution;
    let highest = m / 2 - 1;
    if lowest > highest {
        return None;
    }
    let fft = FftPlanner::new().plan_fft_forward(m);
    let mut total = vec![0.0; highest + 1];
    let mut series = 0usize;
    for r in residuals {
        // The training residual averaged at each angle of the index grid.
        let mut sum = vec![Complex::new(0.0, 0.0); m];
        let mut count = vec![0usize; m];
        let (mut sse, mut n) = (0.0, 0usize);
        for i in (0..data.len()).filter(|&i| train[i]) {
            let bin = ((data.theta[i] / TAU * m as Real).round() as usize) % m;
            sum[bin].re += r[i];
            count[bin] += 1;
            sse += r[i] * r[i];
            n += 1;
        }
        if n == 0 || sse <= 0.0 {
            continue;
        }
        series += 1;
        for (s, &c) in sum.iter_mut().zip(&count) {
            if c > 0 {
                s.re /= c as Real;
            }
        }
        fft.process(&mut sum);
        let variance = sse / n as Real;
        for (k, t) in total.iter_mut().enumerate().skip(lowest) {
            // A pair of amplitude a over n samples lowers the SSE by n·a²/2; a = 2|X_k|/m.
            let amplitude = 2.0 * sum[k].norm() / m as Real;
            *t += n as Real * amplitude * amplitude / 4.0 / variance;
        }
    }
    if series == 0 {
        // No probe's residual has any scatter: no F can be formed.
        return None;
    }
    (lowest..=highest)
        .filter(|k| !taken.contains(k))
        .max_by(|&a, &b| total[a].total_cmp(&total[b]))
        .map(|k| Peak {
            at: k as Real,
            f: total[k],
            searched: highest + 1 - lowest - taken.len(),
        })
}

/// Most harmonics of an asynchronous component searched (an impact train has many).
pub const MOST_LINE_HARMONICS: usize = 5;

/// A periodic asynchronous component found by [`search_line`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinePeak {
    /// Its fundamental (cycles per revolution).
    pub frequency: Real,
    /// Harmonics of it that carry it (1: a sinusoid; more: a periodic train such as a race
    /// defect's impacts).
    pub harmonics: usize,
    /// The summed F statistic of the fundamental alone (see [`Peak::f`]).
    pub f: Real,
    /// The harmonic-sum score that chose it: `(Σ_h F − H·S) / √(H·S)` over `H` harmonics and
    /// `S` probe-segment series (each F is a unit exponential under noise alone).
    pub z: Real,
    /// Fundamentals searched.
    pub searched: usize,
}

/// The periodic asynchronous component that best explains the training residuals: a
/// zero-padded periodogram over each probe's and segment's turns (each normalised by its
/// residual variance, summed), searched for the fundamental `f` and number of harmonics `H`
/// (1 to [`MOST_LINE_HARMONICS`]) with the largest harmonic-sum score ([`LinePeak::z`]); `f`
/// refined by a parabola through its bin. Frequencies within one line spacing
/// (1/revolutions) of a whole multiple of the rotation are synchronous and not counted, nor
/// those within one spacing of a harmonic of `taken` (fundamental, harmonics), nor
/// fundamentals below one spacing (a drift).
pub fn search_line(
    data: &Data,
    residuals: &[Vec<Real>],
    train: &[bool],
    taken: &[(Real, usize)],
) -> Option<LinePeak> {
    let m = data.samples_per_revolution;
    let most = data.segments.iter().map(|s| s.revolutions).max()?;
    let length = (8 * most * m).next_power_of_two();
    let spacing = 1.0 / data.fewest_revolutions() as Real;
    let fft = FftPlanner::new().plan_fft_forward(length);
    let per_bin = m as Real / length as Real;
    let half = length / 2;
    let mut total = vec![0.0; half];
    let mut buffer = vec![Complex::new(0.0, 0.0); length];
    let mut series = 0usize;
    for r in residuals {
        for (s, segment) in data.segments.iter().enumerate() {
            buffer.fill(Complex::new(0.0, 0.0));
            let (mut sse, mut n) = (0.0, 0usize);
            for i in segment.samples.clone().filter(|&i| train[i]) {
                debug_assert_eq!(data.segment[i], s);
                let position = (data.turns[i] * m as Real).round() as usize;
                if position < length {
                    buffer[position].re += r[i];
                }
                sse += r[i] * r[i];
                n += 1;
            }
            if n == 0 || sse <= 0.0 {
                continue;
            }
            series += 1;
            fft.process(&mut buffer);
            let variance = sse / n as Real;
            for (j, t) in total.iter_mut().enumerate() {
                // Σ r e^{−iωu}: a pair lowers the SSE by about 2|X|²/n; F = that / 2 / σ².
                *t += buffer[j].norm_sqr() / n as Real / variance;
            }
        }
    }
    if series == 0 {
        return None;
    }
    let free = |f: Real| {
        f <= m as Real / 2.0 - spacing
            && (f - f.round()).abs() >= spacing
            && taken
                .iter()
                .all(|&(t, h)| (1..=h).all(|k| (f - k as Real * t).abs() >= spacing))
    };
    // The largest F within half a padded bin per harmonic of bin j's frequency.
    let at_harmonic = |j: usize, h: usize| -> Option<Real> {
        let centre = j * h;
        let reach = h.div_ceil(2);
        if centre + reach >= half {
            return None;
        }
        let f = centre as Real * per_bin;
        free(f).then(|| {
            total[centre - reach..=centre + reach]
                .iter()
                .copied()
                .fold(0.0, Real::max)
        })
    };
    let expected = series as Real;
    let mut best: Option<(usize, usize, Real)> = None;
    for j in (1..half - 1).filter(|&j| j as Real * per_bin >= spacing && free(j as Real * per_bin))
    {
        let (mut sum, mut count) = (0.0, 0usize);
        for h in 1..=MOST_LINE_HARMONICS {
            if let Some(value) = at_harmonic(j, h) {
                sum += if h == 1 { total[j] } else { value };
                count += 1;
                let z = (sum - count as Real * expected) / (count as Real * expected).sqrt();
                if best.is_none_or(|(_, _, b)| z > b) {
                    best = Some((j, h, z));
                }
            }
        }
    }
    let (j, harmonics, z) = best?;
    // Each harmonic's peak refined by a parabola through its bin and neighbours; the
    // fundamental is their weighted mean (harmonic h pins f h times more finely; weight F·h²).
    let refine = |centre: usize| -> Real {
        let (before, at, after) = (total[centre - 1], total[centre], total[centre + 1]);
        let curvature = before - 2.0 * at + after;
        let shift = if curvature < 0.0 {
            (0.5 * (before - after) / curvature).clamp(-0.5, 0.5)
        } else {
            0.0
        };
        (centre as Real + shift) * per_bin
    };
    let (mut weighted, mut weights) = (0.0, 0.0);
    for h in 1..=harmonics {
        let reach = h.div_ceil(2);
        let centre = j * h;
        if centre + reach + 1 >= half || at_harmonic(j, h).is_none() {
            continue;
        }
        let peak = (centre - reach..=centre + reach)
            .max_by(|&a, &b| total[a].total_cmp(&total[b]))
            .unwrap_or(centre);
        let weight = total[peak] * (h * h) as Real;
        weighted += weight * refine(peak) / h as Real;
        weights += weight;
    }
    let frequency = if weights > 0.0 {
        weighted / weights
    } else {
        refine(j)
    };
    let at = total[j];
    Some(LinePeak {
        frequency,
        harmonics,
        f: at,
        z,
        searched: (m as Real / 2.0 / spacing) as usize,
    })
}

/// The level the largest of `searched` independent statistics, each the sum of `probes`
/// unit-exponential variables (Gamma(probes, 1): `Σ_p F_p` with `F_p ~ F(2, ∞)`), exceeds
/// with probability `false_alarm` (Bonferroni).
pub fn false_alarm_level(probes: usize, searched: usize, false_alarm: Real) -> Real {
    let target = false_alarm / searched.max(1) as Real;
    // Upper tail of Gamma(P, 1): e^{−x} Σ_{j<P} x^j / j!.
    let tail = |x: Real| {
        let (mut term, mut sum) = (1.0, 1.0);
        for j in 1..probes.max(1) {
            term *= x / j as Real;
            sum += term;
        }
        (-x).exp() * sum
    };
    let (mut low, mut high) = (0.0, 1.0);
    while tail(high) > target {
        high *= 2.0;
    }
    for _ in 0..100 {
        let mid = 0.5 * (low + high);
        if tail(mid) > target {
            low = mid;
        } else {
            high = mid;
        }
    }
    high
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn false_alarm_level_of_one_probe_is_the_exponential_quantile() {
        // One probe: P(F ≥ x) = e^{−x}; the largest of 100 exceeds ln(100/0.05) 5 % of the time.
        let level = false_alarm_level(1, 100, 0.05);
        assert!((level - (100.0_f64 / 0.05).ln()).abs() < 1e-9);
        // Two probes: e^{−x}(1 + x) = 0.05 / 10 at x ≈ 7.43 (tables of the χ² with 4 degrees
        // of freedom: 14.86 / 2).
        let level = false_alarm_level(2, 10, 0.05);
        assert!(((-level).exp() * (1.0 + level) - 0.005).abs() < 1e-12);
        assert!((level - 7.43).abs() < 0.01);
    }

    #[test]
    fn drift_shape_runs_from_zero_to_one() {
        assert_eq!(drift_shape(None, 2.0, 6.0, 4.0), 0.5);
        assert!((drift_shape(Some(1.0), 0.0, 3.0, 3.0) - 1.0).abs() < 1e-15);
        assert_eq!(drift_shape(Some(1.0), 0.0, 3.0, 0.0), 0.0);
    }
}
