//! Least squares in normal-equation form over the readings of a union of blocks
//! ([`Fitter`]): a column is a dense part plus a sparse change (`columns.rs`), and the cross
//! products of any two are taken from the per-block sums of their dense parts and over the
//! sparse readings only. [`NormalFit`] is a fit of fixed columns from its
//! Gram matrix, ready to score extra columns from their cross products.

use super::blocks::Blocks;
use super::columns::{Column, Dense, Key, Sparse};
use super::linalg::{gram_pinv, small_pinv};
use super::moments::{CombinedLobes, CombinedMoments, SeriesPair};
use super::reversal::Reversal;
use super::statics::{WIDTH, Y, lagged, static_index};
use super::{CircleData, Shape, Term};
use crate::math::Real;
use nalgebra::DMatrix;
use std::cell::{OnceCell, RefCell};
use std::collections::HashMap;
use std::f64::consts::TAU;
use std::rc::Rc;

/// A fit of fixed columns from their normal equations.
#[derive(Clone, Debug)]
pub(super) struct NormalFit {
    /// (FᵀF)⁺.
    pub(super) pinv: DMatrix<Real>,
    /// The coefficients.
    pub(super) coefficients: Vec<Real>,
    /// The residual sum of squares.
    pub(super) rss: Real,
}

impl NormalFit {
    /// The fit with Gram matrix `g`, cross products with the deviation `fy` and the
    /// deviation's sum of squares `yy`. The residual sum of squares is taken as
    /// yᵀy − 2cᵀFᵀy + cᵀFᵀFc, second order in the coefficients' rounding errors.
    pub(super) fn new(g: &DMatrix<Real>, fy: &[Real], yy: Real) -> NormalFit {
        let k = fy.len();
        let pinv = gram_pinv(g);
        let coefficients: Vec<Real> = (0..k)
            .map(|i| (0..k).map(|j| pinv[(i, j)] * fy[j]).sum())
            .collect();
        let mut quadratic = 0.0;
        for i in 0..k {
            let row: Real = (0..k).map(|j| g[(i, j)] * coefficients[j]).sum();
            quadratic += coefficients[i] * (row - 2.0 * fy[i]);
        }
        NormalFit {
            pinv,
            coefficients,
            rss: (yy + quadratic).max(0.0),
        }
    }

    /// The residual sum of squares with extra columns B added, from Fᵀ·B (`fb`, fixed ×
    /// extra), Bᵀ·B and Bᵀ·y: the fit's, less what the extras' parts orthogonal to the fixed
    /// columns explain of its residual (whose cross products with B are Bᵀy − BᵀF·c).
    pub(super) fn rss_from(&self, fb: &DMatrix<Real>, bb: &DMatrix<Real>, by: &[Real]) -> Real {
        let (k, m) = (fb.nrows(), by.len());
        let f = fb.as_slice();
        let p = self.pinv.as_slice();
        let c = &self.coefficients;
        let mut reduced = vec![0.0; m * m];
        let mut br = vec![0.0; m];
        let mut q = vec![0.0; k];
        for j in 0..m {
            let column = &f[j * k..(j + 1) * k];
            br[j] = by[j] - column.iter().zip(c).map(|(u, v)| u * v).sum::<Real>();
            // q = (FᵀF)⁺·(Fᵀb_j), the pseudo-inverse symmetric and column-major.
            for (i, out) in q.iter_mut().enumerate() {
                *out = p[i * k..(i + 1) * k]
                    .iter()
                    .zip(column)
                    .map(|(u, v)| u * v)
                    .sum();
            }
            for a in 0..=j {
                let other = &f[a * k..(a + 1) * k];
                let value = bb[(a, j)] - other.iter().zip(&q).map(|(u, v)| u * v).sum::<Real>();
                reduced[a * m + j] = value;
                reduced[j * m + a] = value;
            }
        }
        let inverse = small_pinv(m, &reduced);
        let explained: Real = (0..m)
            .map(|i| {
                (0..m)
                    .map(|j| br[i] * inverse[i * m + j] * br[j])
                    .sum::<Real>()
            })
            .sum();
        (self.rss - explained).max(0.0)
    }
}

/// Fits over the readings of some blocks of a [`Blocks`].
pub(super) struct Fitter<'a> {
    pub(super) data: &'a CircleData,
    pub(super) blocks: &'a Blocks,
    /// Whether each block is fitted.
    pub(super) included: Vec<bool>,
    /// The readings fitted.
    pub(super) rows: Vec<usize>,
    /// The table's cross products over the fitted readings (`WIDTH` × `WIDTH`).
    sums: Vec<Real>,
    /// Cyclic and lobe columns evaluated at every reading.
    values: RefCell<HashMap<Key, Rc<Vec<Real>>>>,
    /// Their products with each other and with sparse parts (by where these are kept),
    /// summed over the fitted readings.
    products: RefCell<HashMap<(Key, Key), Real>>,
    sparse_products: RefCell<HashMap<(usize, Key), Real>>,
    sparse_pairs: RefCell<HashMap<(usize, usize), Real>>,
    /// Cyclic columns' products with the table's columns.
    cyclic_tables: RefCell<HashMap<Key, Rc<Vec<Real>>>>,
    /// Reversal columns by term, lag, play and decay.
    reversal_columns: RefCell<HashMap<(Term, [u64; 3]), Column>>,
    /// Cyclic moments summed over the fitted blocks, per (axis, grid index).
    pub(super) centres: RefCell<HashMap<(usize, usize), Rc<CombinedMoments>>>,
    /// Lobe sums over the fitted blocks.
    pub(super) lobes: OnceCell<CombinedLobes>,
    /// The last offset series taken (see `spectral.rs`).
    pub(super) last_series: RefCell<Option<(Real, SeriesPair)>>,
    /// The angle lag (s) every fit holds, when it is not estimated from the fitted readings
    /// ([`CircleData::fit_blocks_at_lag`]).
    pub(super) held_angle_lag: Option<Real>,
}

impl<'a> Fitter<'a> {
    /// Fits over the `included` blocks of `blocks` (made from `data`).
    pub(super) fn new(data: &'a CircleData, blocks: &'a Blocks, included: Vec<bool>) -> Self {
        let mut sums = vec![0.0; WIDTH * WIDTH];
        for (b, block) in blocks.sums.chunks(WIDTH * WIDTH).enumerate() {
            if included[b] {
                for (s, v) in sums.iter_mut().zip(block) {
                    *s += v;
                }
            }
        }
        let rows = (0..data.len())
            .filter(|&i| included[usize::from(blocks.block_of[i])])
            .collect();
        Fitter {
            data,
            blocks,
            included,
            rows,
            sums,
            values: RefCell::new(HashMap::new()),
            products: RefCell::new(HashMap::new()),
            sparse_products: RefCell::new(HashMap::new()),
            sparse_pairs: RefCell::new(HashMap::new()),
            cyclic_tables: RefCell::new(HashMap::new()),
            reversal_columns: RefCell::new(HashMap::new()),
            centres: RefCell::new(HashMap::new()),
            lobes: OnceCell::new(),
            last_series: RefCell::new(None),
            held_angle_lag: None,
        }
    }

    /// Whether reading `i` is fitted.
    pub(super) fn fitted(&self, i: usize) -> bool {
        self.blocks.fitted(&self.included, i)
    }

    /// The sum of squared deviations over the fitted readings.
    pub(super) fn yy(&self) -> Real {
        self.sums[Y * WIDTH + Y]
    }

    /// The columns of `terms` at `shape`, in order.
    pub(super) fn columns(&self, terms: &[Term], shape: &Shape) -> Vec<Column> {
        let mut columns = Vec::new();
        for &term in terms {
            if let Some(axis) = term.reversal_axis() {
                columns.push(self.reversal_column(term, axis, shape));
                continue;
            }
            for index in 0..term.columns() {
                let dense = match term {
                    Term::CyclicP | Term::CyclicQ => {
                        let axis = usize::from(term == Term::CyclicQ);
                        Dense::Cyclic {
                            axis,
                            period: shape.period[axis],
                            index,
                        }
                    }
                    Term::Lobes => Dense::Lobe {
                        k: shape.lobes,
                        index,
                    },
                    _ => match static_index(term, shape) {
                        Some(j) => Dense::Static(j),
                        None => Dense::Mix(
                            lagged(term, shape, &self.data.test)
                                .unwrap_or_default()
                                .into(),
                        ),
                    },
                };
                columns.push(Column::dense(dense));
            }
        }
        columns
    }

    /// The column of reversal term `term` of `axis` at `shape`, made once per fit.
    fn reversal_column(&self, term: Term, axis: usize, shape: &Shape) -> Column {
        let key = (
            term,
            [
                shape.lag[axis].to_bits(),
                shape.play[axis].to_bits(),
                shape.decay[axis].to_bits(),
            ],
        );
        if let Some(known) = self.reversal_columns.borrow().get(&key) {
            return known.clone();
        }
        let column = Reversal::new(axis, shape, &self.data.test).column(
            self.data,
            self.blocks,
            &self.included,
            term,
        );
        self.reversal_columns
            .borrow_mut()
            .insert(key, column.clone());
        column
    }

    /// A cyclic or lobe column's values at every reading, made once per fit (with its
    /// companion: sin and cos from one phase).
    pub(super) fn dense_values(&self, dense: &Dense) -> Rc<Vec<Real>> {
        let Some(key) = dense.key() else {
            return Rc::new(
                (0..self.data.len())
                    .map(|i| self.dense_at(dense, i))
                    .collect(),
            );
        };
        if let Some(values) = self.values.borrow().get(&key) {
            return values.clone();
        }
        let n = self.data.len();
        let (mut sin, mut cos) = (Vec::with_capacity(n), Vec::with_capacity(n));
        let keys = match *dense {
            Dense::Cyclic { axis, period, .. } => {
                match self.cyclic_near_centre(axis, period) {
                    Some(values) => {
                        for (s, c) in values {
                            sin.push(s);
                            cos.push(c);
                        }
                    }
                    None => {
                        for i in 0..n {
                            let c = self.data.cyclic_c(axis, i);
                            let (s, k) = (TAU * self.data.test.radius * c / period).sin_cos();
                            sin.push(c * s);
                            cos.push(c * k);
                        }
                    }
                }
                (
                    Key::Cyclic(axis, period.to_bits(), 0),
                    Key::Cyclic(axis, period.to_bits(), 1),
                )
            }
            Dense::Lobe { k, .. } => {
                for point in &self.data.points {
                    let (s, c) = (Real::from(k) * point.angle).sin_cos();
                    sin.push(s);
                    cos.push(c);
                }
                (Key::Lobe(k, 0), Key::Lobe(k, 1))
            }
            _ => unreachable!("only cyclic and lobe columns have keys"),
        };
        let (sin, cos) = (Rc::new(sin), Rc::new(cos));
        let mut values = self.values.borrow_mut();
        values.insert(keys.0, sin.clone());
        values.insert(keys.1, cos.clone());
        if key == keys.0 { sin } else { cos }
    }

    /// The key of a cyclic or lobe column's first column (its pair's).
    fn pair_key(&self, dense: &Dense) -> Key {
        match *dense {
            Dense::Cyclic { axis, period, .. } => Key::Cyclic(axis, period.to_bits(), 0),
            Dense::Lobe { k, .. } => Key::Lobe(k, 0),
            _ => unreachable!("only cyclic and lobe columns come in pairs"),
        }
    }

    /// A cyclic or lobe pair's two values at reading `i` (its sin and cos columns).
    fn phase(&self, dense: &Dense, i: usize) -> (Real, Real) {
        match *dense {
            Dense::Cyclic { axis, period, .. } => {
                let c = self.data.cyclic_c(axis, i);
                let (s, k) = (TAU * self.data.test.radius * c / period).sin_cos();
                (c * s, c * k)
            }
            Dense::Lobe { k, .. } => (Real::from(k) * self.data.points[i].angle).sin_cos(),
            _ => (0.0, 0.0),
        }
    }

    /// A dense part's value at reading `i`.
    pub(super) fn dense_at(&self, dense: &Dense, i: usize) -> Real {
        match dense {
            Dense::Zero => 0.0,
            Dense::Static(j) => self.blocks.row(i)[*j],
            Dense::Mix(mix) => {
                let row = self.blocks.row(i);
                mix.iter().map(|(j, w)| w * row[*j]).sum()
            }
            Dense::Cyclic {
                axis,
                period,
                index,
            } => {
                let (sin, cos) = self.data.points[i].sin_cos;
                let c = if *axis == 0 { cos } else { sin };
                let phase = TAU * self.data.test.radius * c / period;
                c * if *index == 0 {
                    phase.sin()
                } else {
                    phase.cos()
                }
            }
            Dense::Lobe { k, index } => {
                let phase = Real::from(*k) * self.data.points[i].angle;
                if *index == 0 {
                    phase.sin()
                } else {
                    phase.cos()
                }
            }
        }
    }

    /// The values at every reading of the fixed columns `columns`, for the readings `rows`:
    /// row by row, `columns.len()` values each, then the deviation.
    pub(super) fn values_at(&self, columns: &[Column], rows: &[usize]) -> Vec<Real> {
        let k = columns.len();
        let mut out = Vec::with_capacity(rows.len() * (k + 1));
        // Cyclic and lobe columns come in pairs (sin, cos): one phase for both, or the values
        // the fit has already made.
        let made: Vec<Option<Rc<Vec<Real>>>> = columns
            .iter()
            .map(|c| {
                c.dense
                    .key()
                    .and_then(|key| self.values.borrow().get(&key).cloned())
            })
            .collect();
        for &i in rows {
            let row = self.blocks.row(i);
            let mut last: Option<(Key, (Real, Real))> = None;
            for (c, made) in columns.iter().zip(&made) {
                out.push(match (&c.dense, made) {
                    (Dense::Static(j), _) => row[*j],
                    (_, Some(values)) => values[i],
                    (dense @ (Dense::Cyclic { .. } | Dense::Lobe { .. }), None) => {
                        let pair = self.pair_key(dense);
                        let (s, co) = match last {
                            Some((key, phase)) if key == pair => phase,
                            _ => {
                                let phase = self.phase(dense, i);
                                last = Some((pair, phase));
                                phase
                            }
                        };
                        let index = match dense {
                            Dense::Cyclic { index, .. } | Dense::Lobe { index, .. } => *index,
                            _ => 0,
                        };
                        if index == 0 { s } else { co }
                    }
                    (dense, None) => self.dense_at(dense, i),
                });
            }
            out.push(self.data.deviation[i]);
        }
        // The sparse changes, scattered to where their readings are.
        let mut position = vec![u32::MAX; self.data.len()];
        for (p, &i) in rows.iter().enumerate() {
            position[i] = p as u32;
        }
        for (j, c) in columns.iter().enumerate() {
            for (&i, v) in c.sparse.rows.iter().zip(&c.sparse.values) {
                let p = position[i as usize];
                if p != u32::MAX {
                    out[p as usize * (k + 1) + j] += v;
                }
            }
        }
        out
    }

    /// Σ over the fitted readings of two dense parts' product.
    fn dense_dot(&self, a: &Dense, b: &Dense) -> Real {
        if let (Dense::Static(i), Dense::Static(j)) = (a, b) {
            return self.sums[i * WIDTH + j];
        }
        let a_static = a.with_statics(|a| {
            b.with_statics(|b| {
                a.iter()
                    .map(|(i, u)| {
                        b.iter()
                            .map(|(j, w)| u * w * self.sums[i * WIDTH + j])
                            .sum::<Real>()
                    })
                    .sum::<Real>()
            })
        });
        match a_static {
            Some(Some(both)) => both,
            Some(None) => a.with_statics(|mix| self.static_dot(mix, b)).unwrap_or(0.0),
            None => match b.with_statics(|mix| self.static_dot(mix, a)) {
                Some(product) => product,
                None => self.dynamic_dot(a, b),
            },
        }
    }

    /// Σ over the fitted readings of a combination of table columns times a cyclic or lobe
    /// column (the table's last column is the deviation).
    fn static_dot(&self, mix: &[(usize, Real)], dense: &Dense) -> Real {
        if let Dense::Cyclic { .. } = dense
            && let Some(products) = self.cyclic_table(dense)
        {
            return mix.iter().map(|&(j, w)| w * products[j]).sum();
        }
        mix.iter()
            .map(|&(j, w)| {
                let product = match dense {
                    Dense::Lobe { k, index } => self.lobe_with(*k, *index, j),
                    _ => None,
                };
                w * product.unwrap_or_else(|| {
                    let values = self.dense_values(dense);
                    self.rows
                        .iter()
                        .map(|&i| values[i] * self.blocks.row(i)[j])
                        .sum()
                })
            })
            .sum()
    }

    /// A cyclic column's products with every table column over the fitted readings, by its
    /// moments about the nearest grid frequency (made once per fit).
    fn cyclic_table(&self, dense: &Dense) -> Option<Rc<Vec<Real>>> {
        let key = dense.key()?;
        if let Some(known) = self.cyclic_tables.borrow().get(&key) {
            return Some(known.clone());
        }
        let products: Rc<Vec<Real>> = Rc::new(
            (0..WIDTH)
                .map(|j| self.cyclic_with(dense, j))
                .collect::<Option<Vec<Real>>>()?,
        );
        self.cyclic_tables
            .borrow_mut()
            .insert(key, products.clone());
        Some(products)
    }

    /// Σ over the fitted readings of two cyclic or lobe columns' product.
    fn dynamic_dot(&self, a: &Dense, b: &Dense) -> Real {
        let known = match (a, b) {
            (Dense::Cyclic { .. }, Dense::Cyclic { .. }) => self.cyclic_self(a, b),
            (Dense::Cyclic { .. }, Dense::Lobe { .. }) => self.cyclic_lobe(a, b),
            (Dense::Lobe { .. }, Dense::Cyclic { .. }) => self.cyclic_lobe(b, a),
            (Dense::Lobe { k, index }, Dense::Lobe { k: l, index: m }) if k == l => {
                self.lobe_self(*k, *index, *m)
            }
            _ => None,
        };
        if let Some(known) = known {
            return known;
        }
        let (Some(ka), Some(kb)) = (a.key(), b.key()) else {
            return 0.0;
        };
        let key = (ka.min(kb), ka.max(kb));
        if let Some(&known) = self.products.borrow().get(&key) {
            return known;
        }
        let (va, vb) = (self.dense_values(a), self.dense_values(b));
        let product = self.rows.iter().map(|&i| va[i] * vb[i]).sum();
        self.products.borrow_mut().insert(key, product);
        product
    }

    /// Σ over the fitted readings of a sparse part times a dense part.
    fn sparse_dense(&self, sparse: &Rc<Sparse>, dense: &Dense) -> Real {
        if sparse.is_empty() {
            return 0.0;
        }
        if let Some(product) =
            dense.with_statics(|mix| mix.iter().map(|(j, w)| w * sparse.table[*j]).sum())
        {
            return product;
        }
        let Some(key) = dense.key() else {
            return 0.0;
        };
        let id = (Rc::as_ptr(sparse) as usize, key);
        if let Some(&known) = self.sparse_products.borrow().get(&id) {
            return known;
        }
        let product = sparse
            .rows
            .iter()
            .zip(&sparse.values)
            .filter(|(i, _)| self.fitted(**i as usize))
            .map(|(&i, v)| v * self.dense_at(dense, i as usize))
            .sum();
        self.sparse_products.borrow_mut().insert(id, product);
        product
    }

    /// Σ over the fitted readings of two sparse parts' product.
    fn sparse_sparse(&self, a: &Rc<Sparse>, b: &Rc<Sparse>) -> Real {
        if a.is_empty() || b.is_empty() {
            return 0.0;
        }
        let (pa, pb) = (Rc::as_ptr(a) as usize, Rc::as_ptr(b) as usize);
        let id = (pa.min(pb), pa.max(pb));
        if let Some(&known) = self.sparse_pairs.borrow().get(&id) {
            return known;
        }
        let (mut i, mut j, mut sum) = (0, 0, 0.0);
        while i < a.rows.len() && j < b.rows.len() {
            match a.rows[i].cmp(&b.rows[j]) {
                std::cmp::Ordering::Less => i += 1,
                std::cmp::Ordering::Greater => j += 1,
                std::cmp::Ordering::Equal => {
                    if self.fitted(a.rows[i] as usize) {
                        sum += a.values[i] * b.values[j];
                    }
                    i += 1;
                    j += 1;
                }
            }
        }
        self.sparse_pairs.borrow_mut().insert(id, sum);
        sum
    }

    /// Σ over the fitted readings of two columns' product.
    pub(super) fn cross(&self, a: &Column, b: &Column) -> Real {
        self.dense_dot(&a.dense, &b.dense)
            + self.sparse_dense(&a.sparse, &b.dense)
            + self.sparse_dense(&b.sparse, &a.dense)
            + self.sparse_sparse(&a.sparse, &b.sparse)
    }

    /// Σ over the fitted readings of a column times the deviation.
    pub(super) fn cross_y(&self, a: &Column) -> Real {
        let dense = a
            .dense
            .with_statics(|mix| mix.iter().map(|(j, w)| w * self.sums[j * WIDTH + Y]).sum())
            .unwrap_or_else(|| self.static_dot(&[(Y, 1.0)], &a.dense));
        dense + a.sparse.table.get(Y).copied().unwrap_or(0.0)
    }

    /// The Gram matrix of `columns` and their cross products with the deviation.
    pub(super) fn normal(&self, columns: &[Column]) -> (DMatrix<Real>, Vec<Real>) {
        let k = columns.len();
        let mut g = DMatrix::zeros(k, k);
        for i in 0..k {
            for j in i..k {
                let v = self.cross(&columns[i], &columns[j]);
                g[(i, j)] = v;
                g[(j, i)] = v;
            }
        }
        (g, columns.iter().map(|c| self.cross_y(c)).collect())
    }

    /// The fit of `columns`.
    pub(super) fn project(&self, columns: &[Column]) -> NormalFit {
        let (g, fy) = self.normal(columns);
        NormalFit::new(&g, &fy, self.yy())
    }

    /// The residual of the fit of `columns` with `coefficients` at every reading: the table's
    /// columns combined first, reading by reading.
    pub(super) fn residuals(&self, columns: &[Column], coefficients: &[Real]) -> Vec<Real> {
        let mut weights = [0.0; WIDTH];
        weights[Y] = -1.0;
        let mut dynamic = Vec::new();
        for (column, &c) in columns.iter().zip(coefficients) {
            match column.dense.statics() {
                Some(mix) => {
                    for (j, w) in mix {
                        weights[j] += c * w;
                    }
                }
                None => dynamic.push((self.dense_values(&column.dense), c)),
            }
        }
        let mut residual: Vec<Real> = (0..self.data.len())
            .map(|i| {
                -self
                    .blocks
                    .row(i)
                    .iter()
                    .zip(&weights)
                    .map(|(v, w)| v * w)
                    .sum::<Real>()
            })
            .collect();
        for (values, c) in dynamic {
            for (r, v) in residual.iter_mut().zip(values.iter()) {
                *r -= c * v;
            }
        }
        for (column, c) in columns.iter().zip(coefficients) {
            for (&i, v) in column.sparse.rows.iter().zip(&column.sparse.values) {
                residual[i as usize] -= c * v;
            }
        }
        residual
    }
}
