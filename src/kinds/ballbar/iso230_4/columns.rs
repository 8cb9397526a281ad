//! The columns of a fit ([`Column`]): a dense part (a combination of the table's static
//! columns, or a cyclic or lobe column, [`Dense`]) plus a sparse change (a reversal term at a
//! lag or with play, a spike, [`Sparse`]).

use super::blocks::Blocks;
use super::statics::WIDTH;
use crate::math::Real;
use std::rc::Rc;

/// Values at a few readings (in increasing reading), zero elsewhere, with their sums against
/// the table's columns over the fitted readings.
#[derive(Clone, Debug, Default)]
pub(super) struct Sparse {
    pub(super) rows: Vec<u32>,
    pub(super) values: Vec<Real>,
    /// Σ over the fitted readings of the values times each table column (`WIDTH`).
    pub(super) table: Vec<Real>,
}

impl Sparse {
    /// The sparse part with `values` at `rows` (any order) for the readings of the `included`
    /// blocks of `blocks`.
    pub(super) fn new(blocks: &Blocks, included: &[bool], mut entries: Vec<(u32, Real)>) -> Sparse {
        entries.sort_by_key(|e| e.0);
        let mut table = vec![0.0; WIDTH];
        for &(i, v) in &entries {
            if blocks.fitted(included, i as usize) {
                for (t, w) in table.iter_mut().zip(blocks.row(i as usize)) {
                    *t += v * w;
                }
            }
        }
        Sparse {
            rows: entries.iter().map(|e| e.0).collect(),
            values: entries.iter().map(|e| e.1).collect(),
            table,
        }
    }

    pub(super) fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }
}

/// The dense part of a column.
#[derive(Clone, Debug)]
pub(super) enum Dense {
    /// None (a spike).
    Zero,
    /// A static column of the table.
    Static(usize),
    /// A combination of static columns (index, weight).
    Mix(Rc<[(usize, Real)]>),
    /// Column `index` of the cyclic term of `axis` (0: c·sin, 1: c·cos of 2π·R·c/period).
    Cyclic {
        axis: usize,
        period: Real,
        index: usize,
    },
    /// Column `index` of `k` lobes (0: sin kθ, 1: cos kθ).
    Lobe { k: u32, index: usize },
}

/// What identifies a dense part that is not static, for the fit's memory of its values and
/// products.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(super) enum Key {
    Cyclic(usize, u64, usize),
    Lobe(u32, usize),
}

impl Dense {
    /// The static columns it combines (index, weight), if it is static.
    pub(super) fn statics(&self) -> Option<Vec<(usize, Real)>> {
        self.with_statics(<[(usize, Real)]>::to_vec)
    }

    /// `f` of the static columns it combines (index, weight), if it is static.
    pub(super) fn with_statics<R>(&self, f: impl FnOnce(&[(usize, Real)]) -> R) -> Option<R> {
        match self {
            Dense::Zero => Some(f(&[])),
            Dense::Static(j) => Some(f(&[(*j, 1.0)])),
            Dense::Mix(mix) => Some(f(mix)),
            _ => None,
        }
    }

    pub(super) fn key(&self) -> Option<Key> {
        match self {
            Dense::Cyclic {
                axis,
                period,
                index,
            } => Some(Key::Cyclic(*axis, period.to_bits(), *index)),
            Dense::Lobe { k, index } => Some(Key::Lobe(*k, *index)),
            _ => None,
        }
    }
}

/// A column of a fit: a dense part plus a sparse change.
#[derive(Clone, Debug)]
pub(super) struct Column {
    pub(super) dense: Dense,
    pub(super) sparse: Rc<Sparse>,
}

impl Column {
    pub(super) fn dense(dense: Dense) -> Column {
        Column {
            dense,
            sparse: Rc::new(Sparse::default()),
        }
    }
}
