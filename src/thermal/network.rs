//! A lumped-capacitance thermal network: nodes with heat capacities, conductances between
//! them and to the ambient air, heat sources per node.
//!
//! ```text
//! Cᵢ dTᵢ/dt = Σⱼ Gᵢⱼ (Tⱼ − Tᵢ) + Gᵢₐ (Tₐ − Tᵢ) + Pᵢ
//! ```
//!
//! i.e. `dT/dt = A·T + B·u` with `u = (P, Tₐ)`. Between two samples the inputs (heat powers,
//! ambient temperature) are held constant, and the network is integrated **exactly** over the
//! step with the matrix exponential of the augmented system
//! `exp([[A, B], [0, 0]]·Δt) = [[Φ, Γ], [0, I]]`, `T(t + Δt) = Φ·T(t) + Γ·u`:
//! unconditionally stable, no step-size error whatever the time constants (seconds for a
//! nut, hours for a column), and the same answer for one 10-minute step as for six hundred
//! 1-second steps. An implicit Euler step would be stable too, but smears fast transients by
//! O(Δt); the exponential costs one n+m matrix exponential per distinct step length, cached.
//!
//! Simplified: each node is isothermal (no gradient inside a part), conductances and
//! capacities are constant, radiation is linearised into the conductances.

use crate::math::Real;
use nalgebra::{DMatrix, DVector};
use std::collections::HashMap;

/// A node of the network.
#[derive(Clone, Debug, PartialEq)]
pub struct ThermalNode {
    /// Name (e.g. `x_nut`, `column_front`).
    pub name: String,
    /// Heat capacity (J/K), > 0.
    pub capacity: Real,
    /// Conductance to the ambient air (W/K), ≥ 0.
    pub to_ambient: Real,
}

/// Why a network was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ThermalNetworkError {
    /// A capacity that is not a positive finite number.
    #[error("node \"{0}\": the heat capacity must be a positive number of J/K")]
    Capacity(String),
    /// A conductance that is negative or not finite.
    #[error("{0}: a conductance must be a finite number of W/K, not negative")]
    Conductance(String),
    /// A link names a node that does not exist, or links a node to itself.
    #[error("link {0}: expected two different nodes of the network")]
    Link(String),
    /// Two nodes share a name.
    #[error("node \"{0}\" is defined twice")]
    Duplicate(String),
}

/// An immutable thermal network (the model); integrate it with a [`ThermalStepper`].
#[derive(Clone, Debug, PartialEq)]
pub struct ThermalNetwork {
    nodes: Vec<ThermalNode>,
    /// (i, j, G) with i < j.
    links: Vec<(usize, usize, Real)>,
}

impl ThermalNetwork {
    /// A network of `nodes` joined by `links` (node names and conductance in W/K).
    pub fn new(
        nodes: Vec<ThermalNode>,
        links: &[(&str, &str, Real)],
    ) -> Result<ThermalNetwork, ThermalNetworkError> {
        for (i, node) in nodes.iter().enumerate() {
            if !(node.capacity.is_finite() && node.capacity > 0.0) {
                return Err(ThermalNetworkError::Capacity(node.name.clone()));
            }
            if !(node.to_ambient.is_finite() && node.to_ambient >= 0.0) {
                return Err(ThermalNetworkError::Conductance(format!(
                    "node \"{}\" to ambient",
                    node.name
                )));
            }
            if nodes[..i].iter().any(|n| n.name == node.name) {
                return Err(ThermalNetworkError::Duplicate(node.name.clone()));
            }
        }
        let index = |name: &str| nodes.iter().position(|n| n.name == name);
        let mut resolved = Vec::with_capacity(links.len());
        for &(a, b, conductance) in links {
            let label = format!("\"{a}\" – \"{b}\"");
            let (Some(i), Some(j)) = (index(a), index(b)) else {
                return Err(ThermalNetworkError::Link(label));
            };
            if i == j {
                return Err(ThermalNetworkError::Link(label));
            }
            if !(conductance.is_finite() && conductance >= 0.0) {
                return Err(ThermalNetworkError::Conductance(label));
            }
            resolved.push((i.min(j), i.max(j), conductance));
        }
        Ok(ThermalNetwork {
            nodes,
            links: resolved,
        })
    }

    /// The nodes.
    pub fn nodes(&self) -> &[ThermalNode] {
        &self.nodes
    }

    /// The links between nodes: `(i, j, conductance W/K)` with `i < j`.
    pub fn links(&self) -> &[(usize, usize, Real)] {
        &self.links
    }

    /// The index of a node.
    pub fn node(&self, name: &str) -> Option<usize> {
        self.nodes.iter().position(|n| n.name == name)
    }

    /// `A` (n×n) and `B` (n×(n+1), inputs: the n heat powers then the ambient temperature).
    fn system(&self) -> (DMatrix<Real>, DMatrix<Real>) {
        let n = self.nodes.len();
        let mut a = DMatrix::zeros(n, n);
        let mut b = DMatrix::zeros(n, n + 1);
        for &(i, j, g) in &self.links {
            a[(i, i)] -= g;
            a[(j, j)] -= g;
            a[(i, j)] += g;
            a[(j, i)] += g;
        }
        for (i, node) in self.nodes.iter().enumerate() {
            a[(i, i)] -= node.to_ambient;
            b[(i, i)] = 1.0;
            b[(i, n)] = node.to_ambient;
        }
        for (i, node) in self.nodes.iter().enumerate() {
            a.row_mut(i).scale_mut(1.0 / node.capacity);
            b.row_mut(i).scale_mut(1.0 / node.capacity);
        }
        (a, b)
    }

    /// The steady-state temperatures for constant heat powers (W) and ambient (°C), when every
    /// node is connected to the ambient; `None` otherwise (the network would heat without end).
    pub fn steady_state(&self, power: &[Real], ambient: Real) -> Option<Vec<Real>> {
        let (a, b) = self.system();
        let u = input(power, ambient);
        let lu = mtwin_kernels::linalg::lu(a);
        mtwin_kernels::linalg::lu_solve(&lu, &(-(b * u))).map(|t| t.iter().copied().collect())
    }
}

fn input(power: &[Real], ambient: Real) -> DVector<Real> {
    DVector::from_iterator(power.len() + 1, power.iter().copied().chain([ambient]))
}

/// How many step lengths a [`ThermalStepper`] keeps the exact step matrices of.
const MAX_CACHED_STEPS: usize = 64;

/// Integrates a [`ThermalNetwork`]: the temperatures, and a cache of the exact step matrices
/// per step length.
#[derive(Clone, Debug)]
pub struct ThermalStepper {
    a: DMatrix<Real>,
    b: DMatrix<Real>,
    temperatures: DVector<Real>,
    /// Step length (s, as bits) → (Φ, Γ).
    cache: HashMap<u64, (DMatrix<Real>, DMatrix<Real>)>,
    input: DVector<Real>,
    next: DVector<Real>,
}

impl ThermalStepper {
    /// Starts with every node at `initial` °C.
    pub fn new(network: &ThermalNetwork, initial: Real) -> ThermalStepper {
        let (a, b) = network.system();
        let n = network.nodes.len();
        ThermalStepper {
            a,
            b,
            temperatures: DVector::from_element(n, initial),
            cache: HashMap::new(),
            input: DVector::zeros(n + 1),
            next: DVector::zeros(n),
        }
    }

    /// The node temperatures (°C), in node order.
    pub fn temperatures(&self) -> &[Real] {
        self.temperatures.as_slice()
    }

    /// Advances by `dt` seconds with the heat powers `power` (W, one per node) and the ambient
    /// temperature `ambient` (°C) held over the step.
    pub fn step(&mut self, dt: Real, power: &[Real], ambient: Real) {
        let n = self.temperatures.len();
        assert_eq!(power.len(), n, "one heat power per node");
        assert!(
            dt >= 0.0 && dt.is_finite(),
            "a step must be a finite, non-negative time"
        );
        if dt == 0.0 {
            return;
        }
        let (a, b) = (&self.a, &self.b);
        // A programme has few distinct step lengths; should one have many, start the cache afresh
        // rather than let it grow (each entry is an (n+m)² matrix exponential).
        if self.cache.len() >= MAX_CACHED_STEPS && !self.cache.contains_key(&dt.to_bits()) {
            self.cache.clear();
        }
        let (phi, gamma) = self.cache.entry(dt.to_bits()).or_insert_with(|| {
            let m = n + b.ncols();
            let mut augmented = DMatrix::zeros(m, m);
            augmented.view_mut((0, 0), (n, n)).copy_from(a);
            augmented.view_mut((0, n), (n, b.ncols())).copy_from(b);
            let exponential = (augmented * dt).exp();
            (
                exponential.view((0, 0), (n, n)).into_owned(),
                exponential.view((0, n), (n, b.ncols())).into_owned(),
            )
        });
        for (slot, value) in self
            .input
            .iter_mut()
            .zip(power.iter().copied().chain([ambient]))
        {
            *slot = value;
        }
        phi.mul_to(&self.temperatures, &mut self.next);
        self.next.gemv(1.0, gamma, &self.input, 1.0);
        std::mem::swap(&mut self.temperatures, &mut self.next);
    }
}
