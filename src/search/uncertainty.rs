//! How sure the data make each gene: the Gauss–Newton covariance at a
//! least-squares optimum, in each gene's scale.
//!
//! `J` is the Jacobian of the residuals with respect to the scale-space genome
//! (the logarithm for log genes). With one block of residuals the covariance is
//! `s² (JᵀJ)⁻¹`, `s² = Σ r² / (N − n)` over `N` residuals and `n` genes. The
//! residuals of a campaign come in blocks, one per experiment, each scaled by
//! its record's weight and spread: the same measurement noise becomes a
//! different residual variance in each block, so one pooled `s²` would make the
//! genes that a short or quiet record determines look too sure. Each block `e`
//! therefore gets its own `s_e² = Σ_e r² / (N_e − n N_e / N)` and the covariance
//! is the sandwich `(JᵀJ)⁻¹ (Σ_e s_e² J_eᵀJ_e) (JᵀJ)⁻¹` (the least-squares
//! estimate with the campaign's weights, whose noise differs by block). It
//! assumes independent residuals of equal variance within a block: true for
//! white measurement noise, optimistic where the misfit is systematic (a model
//! that cannot follow the record) or the noise is correlated from sample to
//! sample.

use nalgebra::{DMatrix, SymmetricEigen};
use serde::Serialize;

use super::genes::GeneSpec;
use crate::base::Scale;

/// Two-sided 95 % quantile of the normal distribution. The residual count of a
/// record is in the thousands, where Student's t is the normal to three digits.
pub const Z95: f64 = 1.959_963_984_540_054;

/// One-sided 95 % quantile of the normal distribution: the interval of a gene
/// at a bound is open on the bound's side.
pub const Z95_ONE_SIDED: f64 = 1.644_853_626_951_472;

/// A gene within this fraction of its scale-space range from a bound is at
/// that bound: the optimum the data want may lie beyond it.
pub const AT_BOUND_MARGIN: f64 = 1e-3;

/// Which bound a gene sits at.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum AtBound {
    /// The gene's `min`.
    Lower,
    /// The gene's `max`.
    Upper,
}

/// Absolute correlation above which two genes are reported as entangled.
pub const CORRELATION_FLAG: f64 = 0.99;

/// Eigenvalues of the unit-diagonal `JᵀJ` below this fraction of the largest
/// count as zero: directions the data do not see at all.
const SINGULAR: f64 = 1e-10;

/// Squared weight of a gene in a zero-eigenvalue direction above which the
/// gene counts as undetermined.
const NULL_SHARE: f64 = 1e-6;

/// One gene's uncertainty.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GeneUncertainty {
    /// Gene name.
    pub name: String,
    /// Value at the optimum.
    pub value: f64,
    /// Standard error in scale space (log genes: of ln value, i.e. relative);
    /// `None` where `JᵀJ` is singular in the gene's direction.
    pub std_error_scaled: Option<f64>,
    /// Standard error in the gene's unit (log genes: value × the scale-space
    /// error, to first order).
    pub std_error: Option<f64>,
    /// 95 % interval in the gene's unit: `x ± 1.96 σ` in scale space mapped
    /// back (log genes: asymmetric about the value). Not clipped to the bounds.
    /// At a bound, one-sided: `x ∓ 1.645 σ` on the side away from the bound
    /// and open (infinite, `null` in JSON, for every scale) on the bound's side.
    pub interval_95: Option<[f64; 2]>,
    /// False where the data do not determine the gene: it sits at a bound,
    /// its 95 % interval is wider (in scale space) than its bounds, or `JᵀJ`
    /// is singular in its direction.
    pub determined: bool,
    /// The bound the gene sits at (within [`AT_BOUND_MARGIN`] of its range).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub at_bound: Option<AtBound>,
    /// Why the gene is not determined.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// Genes whose correlation with this one exceeds
    /// [`CORRELATION_FLAG`] in magnitude: the data fix a combination, not each.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub correlated_with: Vec<String>,
}

/// One block of residuals with its own noise level (one experiment's fit
/// window): its `J_eᵀJ_e` (scale space), residual sum of squares and count.
#[derive(Debug, Clone, PartialEq)]
pub struct ResidualBlock {
    /// `J_eᵀJ_e`, `n × n`.
    pub jtj: DMatrix<f64>,
    /// `Σ_e r²`.
    pub ssr: f64,
    /// `N_e`.
    pub residuals: usize,
}

/// The uncertainty of every gene at an optimum.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Uncertainty {
    /// Residuals `N` (fit-window samples over all experiments).
    pub residuals: usize,
    /// Degrees of freedom `N − n`.
    pub dof: usize,
    /// `s²`: the pooled residual variance `Σ r² / (N − n)`, in the units of the
    /// weighted residuals (their sum of squares is the joint `1 − R²`).
    pub residual_variance: f64,
    /// `s_e²` of each block (experiment), in block order; the covariance uses
    /// these.
    pub block_variances: Vec<f64>,
    /// Per gene, in genome order.
    pub genes: Vec<GeneUncertainty>,
    /// Correlation matrix of the genes (genome order); `None` where a gene is
    /// undetermined by a singular `JᵀJ`.
    pub correlation: Vec<Vec<Option<f64>>>,
}

impl Uncertainty {
    /// The uncertainty at scale-space optimum `x` from `JᵀJ` (`n × n`, scale
    /// space), the residual sum of squares `ssr` and the residual count.
    pub fn at(
        genes: &[GeneSpec],
        x: &[f64],
        jtj: &DMatrix<f64>,
        ssr: f64,
        residuals: usize,
    ) -> Self {
        let block = ResidualBlock {
            jtj: jtj.clone(),
            ssr,
            residuals,
        };
        Self::at_blocks(genes, x, std::slice::from_ref(&block))
    }

    /// The uncertainty at scale-space optimum `x` from blocks of residuals
    /// with noise levels of their own (see the module docs).
    pub fn at_blocks(genes: &[GeneSpec], x: &[f64], blocks: &[ResidualBlock]) -> Self {
        let n = genes.len();
        let residuals: usize = blocks.iter().map(|b| b.residuals).sum();
        let ssr: f64 = blocks.iter().map(|b| b.ssr).sum();
        let dof = residuals.saturating_sub(n).max(1);
        let s2 = ssr / dof as f64;
        // Each block's share of the n genes' degrees of freedom.
        let block_variances: Vec<f64> = blocks
            .iter()
            .map(|b| {
                let share = b.residuals as f64 * (1.0 - n as f64 / residuals.max(1) as f64);
                b.ssr / share.max(1.0)
            })
            .collect();
        let mut jtj = DMatrix::zeros(n, n);
        let mut meat = DMatrix::zeros(n, n);
        for (b, s2e) in blocks.iter().zip(&block_variances) {
            jtj += &b.jtj;
            meat += &b.jtj * *s2e;
        }
        let (inv, null) = pseudo_inverse(&jtj);
        let cov = &inv * meat * &inv;
        let se: Vec<Option<f64>> = (0..n)
            .map(|i| (!null[i] && cov[(i, i)].is_finite()).then(|| cov[(i, i)].max(0.0).sqrt()))
            .collect();
        let correlation: Vec<Vec<Option<f64>>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| match (se[i], se[j]) {
                        (Some(a), Some(b)) if a > 0.0 && b > 0.0 => {
                            Some((cov[(i, j)] / (a * b)).clamp(-1.0, 1.0))
                        }
                        _ => None,
                    })
                    .collect()
            })
            .collect();
        let genes = genes
            .iter()
            .enumerate()
            .map(|(i, g)| {
                let (lo, hi) = g.scaled_bounds();
                let value = g.to_value(x[i]);
                let correlated_with = (0..n)
                    .filter(|&j| {
                        j != i && correlation[i][j].is_some_and(|c| c.abs() > CORRELATION_FLAG)
                    })
                    .map(|j| genes[j].name.clone())
                    .collect();
                let margin = AT_BOUND_MARGIN * (hi - lo);
                let at_bound = if x[i] >= hi - margin {
                    Some(AtBound::Upper)
                } else if x[i] <= lo + margin {
                    Some(AtBound::Lower)
                } else {
                    None
                };
                let note = match (at_bound, se[i]) {
                    (Some(AtBound::Upper), _) => {
                        Some("it sits at its upper bound: the data may want a larger value; widen its range")
                    }
                    (Some(AtBound::Lower), _) => {
                        Some("it sits at its lower bound: the data may want a smaller value; widen its range")
                    }
                    (None, None) => {
                        Some("the data do not constrain it (JᵀJ is singular in its direction)")
                    }
                    (None, Some(s)) if 2.0 * Z95 * s > hi - lo => {
                        Some("its 95 % interval is wider than its bounds")
                    }
                    (None, Some(_)) => None,
                };
                GeneUncertainty {
                    name: g.name.clone(),
                    value,
                    std_error_scaled: se[i],
                    std_error: se[i].map(|s| match g.scale {
                        Scale::Linear => s,
                        Scale::Log => value * s,
                    }),
                    interval_95: se[i].map(|s| {
                        let back = |y: f64| match g.scale {
                            Scale::Linear => y,
                            Scale::Log => y.exp(),
                        };
                        match at_bound {
                            None => [back(x[i] - Z95 * s), back(x[i] + Z95 * s)],
                            Some(AtBound::Upper) => {
                                [back(x[i] - Z95_ONE_SIDED * s), f64::INFINITY]
                            }
                            // Open below, whatever the scale: a log gene's
                            // value is never 0, and `null` in result.json
                            // says "no bound from the data" as on the upper side.
                            Some(AtBound::Lower) => {
                                [f64::NEG_INFINITY, back(x[i] + Z95_ONE_SIDED * s)]
                            }
                        }
                    }),
                    determined: note.is_none(),
                    at_bound,
                    note: note.map(String::from),
                    correlated_with,
                }
            })
            .collect();
        Self {
            residuals,
            dof,
            residual_variance: s2,
            block_variances,
            genes,
            correlation,
        }
    }
}

/// `(JᵀJ)⁺` and, per gene, whether it lies in a null direction of `JᵀJ`.
///
/// The matrix is first scaled to unit diagonal, so the eigenvalue threshold
/// does not depend on the genes' units; a gene with a zero diagonal (its
/// residuals do not move at all) is null outright.
fn pseudo_inverse(jtj: &DMatrix<f64>) -> (DMatrix<f64>, Vec<bool>) {
    let n = jtj.nrows();
    let d: Vec<f64> = (0..n)
        .map(|i| {
            let a = jtj[(i, i)];
            if a > 0.0 && a.is_finite() {
                1.0 / a.sqrt()
            } else {
                0.0
            }
        })
        .collect();
    let scaled = DMatrix::from_fn(n, n, |i, j| jtj[(i, j)] * d[i] * d[j]);
    let eig = SymmetricEigen::new(scaled);
    let top = eig.eigenvalues.iter().fold(0.0_f64, |m, &l| m.max(l));
    let mut null: Vec<bool> = d.iter().map(|&x| x == 0.0).collect();
    let mut inv = DMatrix::zeros(n, n);
    for (k, &l) in eig.eigenvalues.iter().enumerate() {
        let v = eig.eigenvectors.column(k);
        if l > SINGULAR * top {
            inv += v * v.transpose() / l;
        } else {
            for (i, flag) in null.iter_mut().enumerate() {
                if d[i] != 0.0 && v[i] * v[i] > NULL_SHARE {
                    *flag = true;
                }
            }
        }
    }
    (
        DMatrix::from_fn(n, n, |i, j| inv[(i, j)] * d[i] * d[j]),
        null,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Straight line y = a + b t: the covariance is known in closed form.
    #[test]
    fn a_straight_line_has_the_textbook_errors() {
        let t: Vec<f64> = (0..50).map(|k| k as f64 / 10.0).collect();
        let jac = DMatrix::from_fn(t.len(), 2, |k, j| if j == 0 { 1.0 } else { t[k] });
        let jtj = jac.transpose() * &jac;
        let genes = vec![
            GeneSpec::new("a", -10.0, 10.0, Scale::Linear),
            GeneSpec::new("b", -10.0, 10.0, Scale::Linear),
        ];
        let ssr = 2.4;
        let u = Uncertainty::at(&genes, &[1.0, 2.0], &jtj, ssr, t.len());
        let s2 = ssr / 48.0;
        let n = t.len() as f64;
        let sxx: f64 = t.iter().map(|x| x * x).sum::<f64>() - t.iter().sum::<f64>().powi(2) / n;
        let mean = t.iter().sum::<f64>() / n;
        let se_b = (s2 / sxx).sqrt();
        let se_a = (s2 * (1.0 / n + mean * mean / sxx)).sqrt();
        let near = |x: f64, y: f64| (x / y - 1.0).abs() < 1e-10;
        assert!(near(u.genes[0].std_error.unwrap(), se_a));
        assert!(near(u.genes[1].std_error.unwrap(), se_b));
        let [lo, hi] = u.genes[1].interval_95.unwrap();
        assert!(near(hi - lo, 2.0 * Z95 * se_b));
        let c = u.correlation[0][1].unwrap();
        assert!(near(
            c,
            -mean / (1.0 / n + mean * mean / sxx).sqrt() / sxx.sqrt()
        ));
        assert!(u.genes.iter().all(|g| g.determined));
    }

    /// A line `y = a + b t` seen by two records with different noise (a short,
    /// noisy one and a long, quiet one), fitted by plain least squares over
    /// both: per-block variances give 95 % intervals that hold the truth 95 %
    /// of the time; one pooled variance makes the noisy record's gene look
    /// far too sure.
    #[test]
    fn blocks_with_their_own_noise_give_intervals_of_the_stated_coverage() {
        use rand::SeedableRng;
        let ta: Vec<f64> = (0..100).map(|k| k as f64 / 100.0).collect();
        let tb: Vec<f64> = (0..300).map(|k| 1.0 + k as f64 / 100.0).collect();
        let (sa, sb) = (2.0, 0.1);
        let jac = |t: &[f64]| DMatrix::from_fn(t.len(), 2, |k, j| if j == 0 { 1.0 } else { t[k] });
        let (ja, jb) = (jac(&ta), jac(&tb));
        let jtj = ja.tr_mul(&ja) + jb.tr_mul(&jb);
        let inv = jtj.clone().try_inverse().unwrap();
        let genes = vec![
            GeneSpec::new("a", -10.0, 10.0, Scale::Linear),
            GeneSpec::new("b", -10.0, 10.0, Scale::Linear),
        ];
        let truth = [0.5, -0.3];
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let trials = 2000;
        let (mut blocked, mut pooled) = ([0usize; 2], [0usize; 2]);
        for _ in 0..trials {
            let mut noisy = |t: &[f64], s: f64| -> Vec<f64> {
                t.iter()
                    .map(|t| truth[0] + truth[1] * t + s * crate::base::noise::gaussian(&mut rng))
                    .collect()
            };
            let (ya, yb) = (noisy(&ta, sa), noisy(&tb, sb));
            let jty = ja.tr_mul(&nalgebra::DVector::from_vec(ya.clone()))
                + jb.tr_mul(&nalgebra::DVector::from_vec(yb.clone()));
            let x = &inv * jty;
            let ssr = |t: &[f64], y: &[f64]| -> f64 {
                t.iter()
                    .zip(y)
                    .map(|(t, y)| (x[0] + x[1] * t - y).powi(2))
                    .sum()
            };
            let blocks = [
                ResidualBlock {
                    jtj: ja.tr_mul(&ja),
                    ssr: ssr(&ta, &ya),
                    residuals: ta.len(),
                },
                ResidualBlock {
                    jtj: jb.tr_mul(&jb),
                    ssr: ssr(&tb, &yb),
                    residuals: tb.len(),
                },
            ];
            let b = Uncertainty::at_blocks(&genes, x.as_slice(), &blocks);
            let p = Uncertainty::at(
                &genes,
                x.as_slice(),
                &jtj,
                blocks[0].ssr + blocks[1].ssr,
                ta.len() + tb.len(),
            );
            for i in 0..2 {
                let inside = |u: &Uncertainty| {
                    let [lo, hi] = u.genes[i].interval_95.unwrap();
                    lo <= truth[i] && truth[i] <= hi
                };
                blocked[i] += usize::from(inside(&b));
                pooled[i] += usize::from(inside(&p));
            }
        }
        let rate = |c: usize| c as f64 / trials as f64;
        for (i, &c) in blocked.iter().enumerate() {
            assert!((0.93..=0.97).contains(&rate(c)), "gene {i}: {}", rate(c));
        }
        assert!(rate(pooled[0]) < 0.8, "pooled: {}", rate(pooled[0]));
    }

    #[test]
    fn an_unseen_gene_and_a_wide_interval_are_flagged() {
        // Gene 1 never moves the residuals; gene 2 barely does.
        let jtj = DMatrix::from_row_slice(3, 3, &[4.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1e-3]);
        let genes = vec![
            GeneSpec::new("a", -1.0, 1.0, Scale::Linear),
            GeneSpec::new("b", -1.0, 1.0, Scale::Linear),
            GeneSpec::new("k", 1.0, 10.0, Scale::Log),
        ];
        let u = Uncertainty::at(&genes, &[0.0, 0.0, 1.0], &jtj, 1.0, 1001);
        assert!(u.genes[0].determined);
        assert!(!u.genes[1].determined && u.genes[1].std_error.is_none());
        assert!(!u.genes[2].determined && u.genes[2].std_error.is_some());
        assert!(u.genes[2].note.as_deref().unwrap().contains("wider"));
        // A log gene's interval is symmetric in ln about the value.
        let [lo, hi] = u.genes[2].interval_95.unwrap();
        assert!(((lo * hi).sqrt() / 1.0f64.exp() - 1.0).abs() < 1e-12);
    }

    /// A gene at either bound has an interval open on that side, in every
    /// scale: infinite here, `null` in JSON (a log gene's lower end is not 0).
    #[test]
    fn an_interval_at_either_bound_is_open_on_that_side() {
        let jtj = DMatrix::from_row_slice(2, 2, &[4.0, 0.0, 0.0, 4.0]);
        let genes = vec![
            GeneSpec::new("k", 1.0, 100.0, Scale::Log),
            GeneSpec::new("c", -1.0, 1.0, Scale::Linear),
        ];
        for (x, side) in [
            ([0.0, -1.0], AtBound::Lower),
            ([100f64.ln(), 1.0], AtBound::Upper),
        ] {
            let u = Uncertainty::at(&genes, &x, &jtj, 1.0, 1001);
            for g in &u.genes {
                assert_eq!(g.at_bound, Some(side), "{}", g.name);
                let [lo, hi] = g.interval_95.unwrap();
                let (open, closed) = match side {
                    AtBound::Lower => (lo, hi),
                    AtBound::Upper => (hi, lo),
                };
                assert!(
                    open.is_infinite() && closed.is_finite(),
                    "{}: {lo} {hi}",
                    g.name
                );
                let json = serde_json::to_value(g).unwrap();
                let k = usize::from(side == AtBound::Upper);
                assert!(json["interval_95"][k].is_null(), "{json}");
                assert!(json["interval_95"][1 - k].is_number(), "{json}");
            }
        }
    }

    #[test]
    fn two_genes_that_only_act_together_are_null() {
        // Residuals depend on a + b only.
        let jac = DMatrix::from_fn(20, 2, |k, _| 1.0 + k as f64);
        let u = Uncertainty::at(
            &[
                GeneSpec::new("a", -1.0, 1.0, Scale::Linear),
                GeneSpec::new("b", -1.0, 1.0, Scale::Linear),
            ],
            &[0.0, 0.0],
            &(jac.transpose() * &jac),
            1.0,
            20,
        );
        assert!(u.genes.iter().all(|g| !g.determined));
    }

    #[test]
    fn strongly_correlated_genes_name_each_other() {
        let jac = DMatrix::from_fn(40, 2, |k, j| 1.0 + k as f64 + 0.02 * (j * k % 3) as f64);
        let genes = vec![
            GeneSpec::new("a", -1e6, 1e6, Scale::Linear),
            GeneSpec::new("b", -1e6, 1e6, Scale::Linear),
        ];
        let u = Uncertainty::at(&genes, &[0.0, 0.0], &(jac.transpose() * &jac), 1e-3, 40);
        assert!(u.correlation[0][1].unwrap().abs() > CORRELATION_FLAG);
        assert_eq!(u.genes[0].correlated_with, ["b"]);
        assert_eq!(u.genes[1].correlated_with, ["a"]);
    }
}
