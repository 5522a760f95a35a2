//! The design points of a sweep: the full product of the variables' grids,
//! or points drawn from their distributions (random, Latin hypercube or
//! Sobol), laid out as Saltelli's design where sensitivity indices are asked.

use super::grid::DesignGrid;
use super::sample::{Distribution, Method};

/// A sweep's design points, each a value per variable.
#[derive(Debug, Clone, PartialEq)]
pub enum Points {
    /// Every combination of the variables' grids, row-major (the first
    /// variable slowest).
    Grid(DesignGrid),
    /// Points drawn from the variables' distributions.
    Drawn(Drawn),
}

/// Points drawn from distributions.
#[derive(Debug, Clone, PartialEq)]
pub struct Drawn {
    /// How they were drawn.
    pub method: Method,
    /// The base count `n` the file asks for.
    pub base: usize,
    /// The seed of the draw.
    pub seed: u64,
    /// Each variable's distribution.
    pub distributions: Vec<Distribution>,
    /// The points: `n` of them, or `n (k + 2)` in Saltelli's order (A, B,
    /// then A with column `i` from B for each variable) where `indices`.
    pub values: Vec<Vec<f64>>,
    /// Whether the points are Saltelli's design for Sobol indices.
    pub indices: bool,
}

/// Corners of a box with at most this many variables are all tried when
/// choosing a shared step; past it, the lowest and the highest corner.
pub const MAX_CORNER_VARIABLES: usize = 8;

impl Points {
    /// The number of points.
    pub fn len(&self) -> usize {
        match self {
            Self::Grid(g) => g.points().unwrap_or(0),
            Self::Drawn(d) => d.values.len(),
        }
    }

    /// Whether there is no point.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Point `i`'s values, one per variable.
    pub fn point(&self, i: usize) -> Vec<f64> {
        match self {
            Self::Grid(g) => g.point(i),
            Self::Drawn(d) => d.values[i].clone(),
        }
    }

    /// Each variable's range: its grid's least and largest value, or its
    /// distribution's 0.1 % and 99.9 % quantiles.
    pub fn ranges(&self) -> Vec<[f64; 2]> {
        match self {
            Self::Grid(g) => g
                .axes
                .iter()
                .map(|a| {
                    let lo = a.iter().copied().fold(f64::INFINITY, f64::min);
                    let hi = a.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                    [lo, hi]
                })
                .collect(),
            Self::Drawn(d) => d.distributions.iter().map(|x| x.support_hint()).collect(),
        }
    }

    /// The corners of the box of [`Self::ranges`]: every combination of each
    /// variable's ends for up to [`MAX_CORNER_VARIABLES`] variables, else
    /// the lowest and the highest.
    pub fn corners(&self) -> Vec<Vec<f64>> {
        let r = self.ranges();
        let k = r.len();
        if k > MAX_CORNER_VARIABLES {
            return vec![
                r.iter().map(|x| x[0]).collect(),
                r.iter().map(|x| x[1]).collect(),
            ];
        }
        let mut out: Vec<Vec<f64>> = (0..1usize << k)
            .map(|bits| (0..k).map(|i| r[i][(bits >> i) & 1]).collect())
            .collect();
        out.dedup();
        out
    }
}
