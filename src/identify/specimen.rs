//! Fit of the specimen law `S(e)` of the tensile model to quasi-static
//! force–elongation data (`rigfit fit-specimen`).
//!
//! The law is `S(e) = k_lin·e` for `e ≤ e_yield` and `Σ_{i=0..n} a_i·e^i` above,
//! `n` = degree (3 for aluminium, 5 for carbon/epoxy, at most
//! [`MAX_POLY_DEGREE`]). At 0.1/s the rig's dynamics play no part, so the
//! measured force is `S(e)`.
//!
//! # Method
//! - Points are sorted by elongation. For a candidate `e_yield` (a data point),
//!   `k_lin` is the least-squares line through the origin on `e ≤ e_yield`,
//!   `k_lin = Σe·F / Σe²`, and `a_0..a_n` the least-squares polynomial on
//!   `e > e_yield`, solved by SVD in the scaled variable `u = e/max|e|` (raw powers
//!   `e^5 ~ 1e-15` would make the system singular), then unscaled,
//!   `a_i = b_i / max|e|^i`.
//! - **`e_yield` is chosen by the best total fit**: the candidate breakpoint with
//!   the smallest total sum of squared errors of both branches (a coarse scan over
//!   at most 200 candidates, then every data point around the best one). Each
//!   candidate must leave ≥ 2 points in the elastic branch and ≥ degree + 2 in the
//!   plastic one. The scan fixes which points belong to which branch; any
//!   `e_yield` in the gap between the last elastic and the first plastic point
//!   gives the same SSE, and within that gap `e_yield` is put where the branches
//!   meet (the crossing of `k_lin·e` and the polynomial, clamped to the gap), so
//!   the law is as continuous as the data allow. The report gives the remaining
//!   force jump `S_poly(e_yield) − k_lin·e_yield` and the crossing itself
//!   (`e_meet`), which a user can pass as a fixed `e_yield` when continuity
//!   matters more than the last bit of fit.
//! - The data must show a plastic range: the two-branch fit is compared with the
//!   elastic line through all points by the F statistic
//!   `F = ((SSE_line − SSE_fit)/(p − 1)) / (SSE_fit/(N − p))`, `p = degree + 3`
//!   (line, polynomial, breakpoint); below [`MIN_F_STATISTIC`] the fit is refused.
//! - R² = 1 − SSE/SST is reported per branch (SST about the branch mean) and
//!   overall.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use serde_json::{Value, json};

use super::{IdentifyError, check_inputs, r_squared, require_points};

/// Highest degree of the specimen's plastic polynomial (`a0` … `a5` of the tensile
/// rig file).
pub const MAX_POLY_DEGREE: usize = 5;

/// Smallest F statistic (two-branch fit against the elastic line alone) for which
/// the data are taken to show a plastic range.
pub const MIN_F_STATISTIC: f64 = 20.0;

/// Largest condition number of the plastic branch's least squares (powers of
/// the scaled elongation, columns of unit norm) a fit is reported with; past
/// it the elongations past yield have too little spread for the degree, and
/// the coefficients amplify noise by as much.
pub const MAX_CONDITION: f64 = 1e8;

/// Least spread of the middle 80 % of the elongations past yield, as a
/// fraction of the largest elongation, a fit is reported with.
pub const MIN_PLASTIC_SPREAD: f64 = 1e-3;

/// Most candidate breakpoints in the coarse scan.
const COARSE_CANDIDATES: usize = 200;

/// Options of [`fit`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpecimenFitOptions {
    /// Degree of the plastic polynomial, `1..=5` (3 for aluminium, 5 for
    /// carbon/epoxy).
    pub degree: usize,
    /// A fixed `e_yield` (m) instead of the best-total-fit scan.
    pub e_yield: Option<f64>,
}

impl Default for SpecimenFitOptions {
    fn default() -> Self {
        Self {
            degree: 3,
            e_yield: None,
        }
    }
}

/// How `e_yield` was chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum YieldChoice {
    /// The data point giving the smallest total SSE.
    BestTotalFit,
    /// Given by the caller.
    Fixed,
}

/// Result of [`fit`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpecimenFit {
    /// Polynomial degree.
    pub degree: usize,
    /// Elastic stiffness `k_lin` (N/m).
    pub k_lin: f64,
    /// End of the elastic branch `e_yield` (m); see the module docs for how it
    /// is placed between data points.
    pub e_yield: f64,
    /// How `e_yield` was chosen.
    pub yield_choice: YieldChoice,
    /// Polynomial coefficients `a_0..a_degree` (`a_i` in N/m^i).
    pub coefficients: Vec<f64>,
    /// Force jump between the branches at `e_yield`, `poly − k_lin·e_yield` (N).
    pub jump_at_yield: f64,
    /// Elongation nearest `e_yield` where both branches give the same force (m),
    /// if they cross near it.
    pub e_meet: Option<f64>,
    /// Points in the elastic branch (`e ≤ e_yield`).
    pub n_elastic: usize,
    /// Points in the plastic branch.
    pub n_plastic: usize,
    /// R² of the elastic branch.
    pub r2_elastic: f64,
    /// R² of the plastic branch.
    pub r2_plastic: f64,
    /// R² over all points.
    pub r2_total: f64,
    /// Root-mean-square residual over all points (N).
    pub rmse: f64,
    /// F statistic against the elastic line alone (see the module docs).
    pub f_statistic: f64,
}

impl SpecimenFit {
    /// The fitted law `S(e)` (N) at elongation `e` (m).
    pub fn force(&self, e: f64) -> f64 {
        if e <= self.e_yield {
            self.k_lin * e
        } else {
            self.polynomial(e)
        }
    }

    /// The plastic polynomial alone at `e` (m), in N.
    pub fn polynomial(&self, e: f64) -> f64 {
        self.coefficients
            .iter()
            .rev()
            .fold(0.0, |acc, a| acc * e + a)
    }

    /// The fit as a campaign fragment: `{"params": {"k_lin", "e_yield", "a0".."a5"}}`
    /// with plain (fixed) values; coefficients above the degree are written as 0 so
    /// the fragment overrides any others. Replace a value by bounds to let the
    /// search refine it.
    pub fn to_campaign_fragment(&self) -> Value {
        let mut params = serde_json::Map::new();
        params.insert("k_lin".into(), json!(self.k_lin));
        params.insert("e_yield".into(), json!(self.e_yield));
        for i in 0..=MAX_POLY_DEGREE {
            let a = self.coefficients.get(i).copied().unwrap_or(0.0);
            params.insert(format!("a{i}"), json!(a));
        }
        json!({ "params": params })
    }
}

/// Fits the specimen law to elongation `e` (m) and force `f` (N).
///
/// # Errors
/// [`IdentifyError::DegreeOutOfRange`], [`IdentifyError::TooFewPoints`] when fewer
/// than `degree + 4` points are given, [`IdentifyError::NoPlasticRange`] when the
/// elastic line alone explains the data, [`IdentifyError::BadYield`] for a fixed
/// `e_yield` that leaves too few points on a side, and input errors.
pub fn fit(
    e: &[f64],
    f: &[f64],
    options: &SpecimenFitOptions,
) -> Result<SpecimenFit, IdentifyError> {
    let degree = options.degree;
    if degree == 0 || degree > MAX_POLY_DEGREE {
        return Err(IdentifyError::DegreeOutOfRange {
            degree,
            max: MAX_POLY_DEGREE,
        });
    }
    check_inputs("specimen data", e, f)?;
    let needed = degree + 4;
    require_points(
        "specimen data (2 elastic + degree + 2 plastic)",
        needed,
        e.len(),
    )?;
    let mut pts: Vec<(f64, f64)> = e.iter().copied().zip(f.iter().copied()).collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let scale = pts.iter().map(|p| p.0.abs()).fold(0.0, f64::max);
    if scale == 0.0 {
        return Err(IdentifyError::NoPlasticRange {
            f_statistic: 0.0,
            threshold: MIN_F_STATISTIC,
        });
    }
    let data = Data { pts, scale, degree };

    let (split, choice) = match options.e_yield {
        Some(ey) => {
            let split = data.pts.partition_point(|p| p.0 <= ey);
            let plastic = data.pts.len() - split;
            if split < 2 || plastic < degree + 2 {
                return Err(IdentifyError::BadYield {
                    e_yield: ey,
                    elastic: split,
                    plastic,
                });
            }
            (split, YieldChoice::Fixed)
        }
        None => (data.best_split()?, YieldChoice::BestTotalFit),
    };
    let e_yield = options.e_yield.unwrap_or(data.pts[split - 1].0);
    let branches = data
        .fit_split(split)
        .ok_or_else(|| IdentifyError::Numerical {
            stage: "specimen least squares",
            reason: "singular system at the chosen e_yield".into(),
        })?;

    // The plastic polynomial needs elongations spread past yield: most of
    // them at one value (a stalled extensometer) or a badly conditioned
    // system gives coefficients that only amplify the noise.
    let condition = data.plastic_condition(split);
    let plastic = &data.pts[split..];
    let middle = plastic[plastic.len() * 9 / 10].0 - plastic[plastic.len() / 10].0;
    let within = |v: f64, lo: f64, hi: f64| (lo..=hi).contains(&v);
    if !within(condition, 1.0, MAX_CONDITION)
        || !within(middle, MIN_PLASTIC_SPREAD * scale, f64::INFINITY)
        || branches.scaled.iter().any(|b| !b.is_finite())
    {
        return Err(IdentifyError::Numerical {
            stage: "specimen plastic fit",
            reason: format!(
                "the {} points past yield have elongations from {:e} to {:e} m, the middle \
                 80 % of them within {middle:.3e} m: too little spread for a degree-{degree} \
                 polynomial (condition number {condition:.1e}; a fit needs at most \
                 {MAX_CONDITION:e} and a middle spread of at least {MIN_PLASTIC_SPREAD:e} of \
                 the largest elongation), its coefficients would be meaningless; record \
                 elongations spread past yield, or fit a lower --degree",
                plastic.len(),
                plastic[0].0,
                plastic[plastic.len() - 1].0,
            ),
        });
    }
    let n = data.pts.len();
    let p = degree + 3;
    let sse = branches.sse_elastic + branches.sse_plastic;
    let (sse_line, _) = line_through_origin(&data.pts).unwrap_or((f64::INFINITY, 0.0));
    // Residuals at round-off level count as a perfect fit, not as signal.
    let f_max = data.pts.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    let sse_floor = n as f64 * (1e-10 * f_max).powi(2);
    let f_statistic = ((sse_line - sse).max(0.0) / (p - 1) as f64)
        / (sse.max(sse_floor).max(f64::MIN_POSITIVE) / n.saturating_sub(p).max(1) as f64);
    if f_statistic.is_nan() || f_statistic < MIN_F_STATISTIC {
        return Err(IdentifyError::NoPlasticRange {
            f_statistic,
            threshold: MIN_F_STATISTIC,
        });
    }

    let forces: Vec<f64> = data.pts.iter().map(|p| p.1).collect();
    let mut out = SpecimenFit {
        degree,
        k_lin: branches.k_lin,
        e_yield,
        yield_choice: choice,
        coefficients: branches
            .scaled
            .iter()
            .enumerate()
            .map(|(i, b)| b / scale.powi(i as i32))
            .collect(),
        jump_at_yield: 0.0,
        e_meet: None,
        n_elastic: split,
        n_plastic: n - split,
        r2_elastic: r_squared(branches.sse_elastic, &forces[..split]),
        r2_plastic: r_squared(branches.sse_plastic, &forces[split..]),
        r2_total: r_squared(sse, &forces),
        rmse: (sse / n as f64).sqrt(),
        f_statistic,
    };
    let lo = data.pts[split.saturating_sub(1 + n / 10)].0;
    let hi = data.pts[(split + n / 10).min(n - 1)].0;
    out.e_meet = meeting_point(&out, lo, hi);
    if let (YieldChoice::BestTotalFit, Some(meet)) = (choice, out.e_meet) {
        // Any e_yield in the gap [last elastic, first plastic) leaves the SSE
        // unchanged: take the one closest to where the branches meet.
        let (a, b) = (data.pts[split - 1].0, data.pts[split].0);
        out.e_yield = meet.clamp(a, b - 1e-3 * (b - a));
    }
    out.jump_at_yield = out.polynomial(out.e_yield) - out.k_lin * out.e_yield;
    Ok(out)
}

struct Data {
    pts: Vec<(f64, f64)>,
    scale: f64,
    degree: usize,
}

struct Branches {
    k_lin: f64,
    scaled: Vec<f64>,
    sse_elastic: f64,
    sse_plastic: f64,
}

impl Data {
    /// Smallest-total-SSE split (number of elastic points), coarse then fine.
    fn best_split(&self) -> Result<usize, IdentifyError> {
        let lo = 2;
        let hi = self.pts.len() - (self.degree + 2);
        let step = ((hi - lo) / COARSE_CANDIDATES).max(1);
        let coarse = self.best_in((lo..=hi).step_by(step));
        let (best, _) = coarse.ok_or_else(|| IdentifyError::Numerical {
            stage: "specimen e_yield scan",
            reason: "no candidate breakpoint could be fitted".into(),
        })?;
        let fine = self.best_in(best.saturating_sub(step).max(lo)..=(best + step).min(hi));
        Ok(fine.map_or(best, |(s, _)| s))
    }

    fn best_in(&self, splits: impl Iterator<Item = usize>) -> Option<(usize, f64)> {
        splits
            .filter_map(|s| {
                let b = self.fit_split(s)?;
                Some((s, b.sse_elastic + b.sse_plastic))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// Condition number of the plastic branch's least squares with the first
    /// `split` points elastic: its columns (powers of the scaled elongation)
    /// scaled to unit norm, largest over smallest singular value.
    fn plastic_condition(&self, split: usize) -> f64 {
        let plastic = &self.pts[split..];
        let cols = self.degree + 1;
        let a = DMatrix::from_fn(plastic.len(), cols, |r, c| {
            (plastic[r].0 / self.scale).powi(c as i32)
        });
        let mut a = a;
        for mut col in a.column_iter_mut() {
            let norm = col.norm();
            if norm > 0.0 {
                col /= norm;
            }
        }
        let sv = a.singular_values();
        sv.max() / sv.min()
    }

    /// Fits both branches with the first `split` points elastic.
    fn fit_split(&self, split: usize) -> Option<Branches> {
        let (sse_elastic, k_lin) = line_through_origin(&self.pts[..split])?;
        let plastic = &self.pts[split..];
        let cols = self.degree + 1;
        let a = DMatrix::from_fn(plastic.len(), cols, |r, c| {
            (plastic[r].0 / self.scale).powi(c as i32)
        });
        let b = DVector::from_iterator(plastic.len(), plastic.iter().map(|p| p.1));
        let x = a.clone().svd(true, true).solve(&b, 1e-13).ok()?;
        let sse_plastic = (&a * &x - &b).norm_squared();
        Some(Branches {
            k_lin,
            scaled: x.iter().copied().collect(),
            sse_elastic,
            sse_plastic,
        })
    }
}

/// Least-squares line through the origin: `(SSE, slope)`.
fn line_through_origin(pts: &[(f64, f64)]) -> Option<(f64, f64)> {
    let see: f64 = pts.iter().map(|p| p.0 * p.0).sum();
    if see == 0.0 {
        return None;
    }
    let k = pts.iter().map(|p| p.0 * p.1).sum::<f64>() / see;
    Some((pts.iter().map(|p| (p.1 - k * p.0).powi(2)).sum(), k))
}

/// Root of `poly(e) − k_lin·e` in `[lo, hi]` nearest `e_yield`, by a grid scan and
/// bisection.
fn meeting_point(fit: &SpecimenFit, lo: f64, hi: f64) -> Option<f64> {
    let g = |e: f64| fit.polynomial(e) - fit.k_lin * e;
    const STEPS: usize = 400;
    let h = (hi - lo) / STEPS as f64;
    let mut best: Option<f64> = None;
    for i in 0..STEPS {
        let (mut a, mut b) = (lo + h * i as f64, lo + h * (i + 1) as f64);
        if g(a).signum() == g(b).signum() && g(a) != 0.0 {
            continue;
        }
        for _ in 0..60 {
            let m = 0.5 * (a + b);
            if g(a).signum() == g(m).signum() {
                a = m
            } else {
                b = m
            }
        }
        let root = 0.5 * (a + b);
        if best.is_none_or(|r| (root - fit.e_yield).abs() < (r - fit.e_yield).abs()) {
            best = Some(root);
        }
    }
    best
}
