//! Direct parameter estimation on the restoring-force surface (*A New Fatigue Testing
//! Rig Based on Inertial Forces*, §3.3 "Parameter Estimation", Eq. 6–7).
//!
//! The restoring force is written as a sum of chosen terms, linear in their
//! coefficients once the exponents are fixed:
//!
//! ```text
//! C(ẋ) = cf1·ẋ + cf2·ẋ³ + cf3·|ẋ|^α·sgn ẋ + fc·sgn ẋ
//! K(x) = kf1·x + kf2·x³ + kf3·|x|^β·sgn x
//! ```
//!
//! (*A New Fatigue Testing Rig Based on Inertial Forces* names the damping exponent α
//! and the stiffness exponent β; its Eq. 6 prints `ẋ` in the stiffness terms, which the
//! sentence after it corrects to `x`). For fixed `(α, β)` the coefficients solve the
//! over-determined system Eq. 7 by least squares. The exponents are found as the paper
//! does (its ref. \[21\]): a grid of step `h` around a centre `(α₀, β₀)`; the centre moves
//! to the grid point of least squared error; the step is halved; this repeats until the
//! step is below a tolerance. The paper gives neither the grid's extent, its start nor
//! the tolerance: rigfit uses a 5 × 5 grid (±2h), `h₀ = 0.25`, centre `(1, 2)` and
//! tolerance 10⁻³, with α kept in `[0, 2]` and β in `[1, 3]`. A grid point where the
//! terms are linearly dependent (α = 1 beside a viscous term, β = 3 beside a cubic one,
//! …) is skipped.

use serde::Serialize;
use serde_json::{Value, json};

use super::IdentifyError;
use super::lsq::{LinearFit, least_squares};
use super::rfs::Surface;
use super::signal::sign;

/// A term of the restoring force.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Term {
    /// `cf1·ẋ` (N·s/m).
    Viscous,
    /// `cf2·ẋ³` (N·s³/m³).
    CubicDamping,
    /// `cf3·|ẋ|^α·sgn ẋ` (N·(s/m)^α).
    PowerDamping,
    /// `fc·sgn ẋ` (N), Coulomb friction.
    Coulomb,
    /// `kf1·x` (N/m).
    Linear,
    /// `kf2·x³` (N/m³).
    Cubic,
    /// `kf3·|x|^β·sgn x` (N/m^β).
    PowerStiffness,
}

impl Term {
    /// Every term, in the order of Eq. 7 (Coulomb after the damping terms).
    pub const ALL: [Term; 7] = [
        Term::Viscous,
        Term::CubicDamping,
        Term::PowerDamping,
        Term::Coulomb,
        Term::Linear,
        Term::Cubic,
        Term::PowerStiffness,
    ];

    /// The campaign parameter the coefficient goes to.
    pub fn param(self) -> &'static str {
        match self {
            Term::Viscous => "cf1",
            Term::CubicDamping => "cf2",
            Term::PowerDamping => "cf3",
            Term::Coulomb => "fc",
            Term::Linear => "kf1",
            Term::Cubic => "kf2",
            Term::PowerStiffness => "kf3",
        }
    }

    /// Unit of the coefficient.
    pub fn unit(self) -> &'static str {
        match self {
            Term::Viscous => "N·s/m",
            Term::CubicDamping => "N·s³/m³",
            Term::PowerDamping => "N·(s/m)^α",
            Term::Coulomb => "N",
            Term::Linear => "N/m",
            Term::Cubic => "N/m³",
            Term::PowerStiffness => "N/m^β",
        }
    }

    /// The term's basis function at `(x, ẋ)` for exponents `(α, β)`.
    pub fn basis(self, x: f64, v: f64, alpha: f64, beta: f64) -> f64 {
        match self {
            Term::Viscous => v,
            Term::CubicDamping => v * v * v,
            Term::PowerDamping => signed_power(v, alpha),
            Term::Coulomb => sign(v),
            Term::Linear => x,
            Term::Cubic => x * x * x,
            Term::PowerStiffness => signed_power(x, beta),
        }
    }
}

/// `|v|^p·sgn v`, zero at zero.
pub fn signed_power(v: f64, p: f64) -> f64 {
    if v == 0.0 {
        0.0
    } else {
        v.abs().powf(p) * sign(v)
    }
}

/// The exponent search (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridOptions {
    /// Starting centre `(α₀, β₀)`.
    pub centre: (f64, f64),
    /// Starting step `h₀`.
    pub step: f64,
    /// Stop once the step is below this.
    pub tolerance: f64,
    /// Grid points on each side of the centre.
    pub half_width: usize,
    /// Allowed α.
    pub alpha_range: (f64, f64),
    /// Allowed β.
    pub beta_range: (f64, f64),
}

impl Default for GridOptions {
    fn default() -> Self {
        Self {
            centre: (1.0, 2.0),
            step: 0.25,
            tolerance: 1e-3,
            half_width: 2,
            alpha_range: (0.0, 2.0),
            beta_range: (1.0, 3.0),
        }
    }
}

/// Options of [`estimate`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DpeOptions {
    /// The terms to fit.
    pub terms: Vec<Term>,
    /// A fixed damping exponent α; searched when `None` and the power-law
    /// damping term is chosen.
    pub alpha: Option<f64>,
    /// A fixed stiffness exponent β; searched likewise.
    pub beta: Option<f64>,
    /// The exponent search.
    pub grid: GridOptions,
}

/// One estimated coefficient.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Coefficient {
    /// Which term.
    pub term: Term,
    /// Its campaign parameter name.
    pub param: &'static str,
    /// The estimate.
    pub value: f64,
    /// Its standard error (white residuals assumed).
    pub std_error: f64,
    /// The unit.
    pub unit: &'static str,
}

/// One level of the exponent search: the centre it moved to.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridLevel {
    /// Step of this level.
    pub step: f64,
    /// Best α on this level's grid.
    pub alpha: f64,
    /// Best β on this level's grid.
    pub beta: f64,
    /// Its sum of squared residuals (N²).
    pub sse: f64,
}

/// The fitted power-law exponents.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Exponents {
    /// Damping exponent α, when the power-law damping term is fitted.
    pub alpha: Option<f64>,
    /// Stiffness exponent β, when the power-law stiffness term is fitted.
    pub beta: Option<f64>,
}

/// The result of direct parameter estimation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DpeReport {
    /// Samples used.
    pub samples: usize,
    /// Mass used for the restoring force (kg).
    pub mass: f64,
    /// The coefficients, in the order of [`Term::ALL`].
    pub coefficients: Vec<Coefficient>,
    /// The power-law exponents (`alpha` and `beta` in the JSON).
    #[serde(flatten)]
    pub exponents: Exponents,
    /// R² of the restoring force.
    pub r2: f64,
    /// RMS residual force (N).
    pub rms_residual: f64,
    /// Largest |residual| (N).
    pub max_residual: f64,
    /// Condition number of the scaled regressor matrix.
    pub condition: f64,
    /// The exponent search, level by level (empty when nothing was searched).
    pub search: Vec<GridLevel>,
}

impl DpeReport {
    /// The fitted restoring force at `(x, ẋ)`.
    pub fn force(&self, x: f64, v: f64) -> f64 {
        self.damping(v) + self.stiffness(x)
    }

    /// The fitted damping force `C(ẋ)`.
    pub fn damping(&self, v: f64) -> f64 {
        self.sum(0.0, v, |t| {
            matches!(
                t,
                Term::Viscous | Term::CubicDamping | Term::PowerDamping | Term::Coulomb
            )
        })
    }

    /// The fitted stiffness force `K(x)`.
    pub fn stiffness(&self, x: f64) -> f64 {
        self.sum(x, 0.0, |t| {
            matches!(t, Term::Linear | Term::Cubic | Term::PowerStiffness)
        })
    }

    fn sum(&self, x: f64, v: f64, keep: impl Fn(Term) -> bool) -> f64 {
        let Exponents { alpha, beta } = self.exponents;
        let (alpha, beta) = (alpha.unwrap_or(1.0), beta.unwrap_or(1.0));
        self.coefficients
            .iter()
            .filter(|c| keep(c.term))
            .map(|c| c.value * c.term.basis(x, v, alpha, beta))
            .sum()
    }

    /// The coefficient of `term`, if fitted.
    pub fn get(&self, term: Term) -> Option<f64> {
        self.coefficients
            .iter()
            .find(|c| c.term == term)
            .map(|c| c.value)
    }

    /// The campaign fragment: the mass fixed, each fitted coefficient free with
    /// `init` at the estimate and bounds of ±max(10 standard errors, 50 %) around
    /// it, each fitted exponent free within ±0.1 of its estimate (inside its
    /// allowed range), and every term not chosen fixed at 0. With `fixed`, every
    /// value is a plain number instead.
    pub fn to_campaign_fragment(&self, fixed: bool, grid: &GridOptions) -> Value {
        let mut params = serde_json::Map::new();
        params.insert("m".into(), json!(self.mass));
        for term in Term::ALL {
            let entry = match self.coefficients.iter().find(|c| c.term == term) {
                Some(c) if !fixed => {
                    let w = (10.0 * c.std_error).max(0.5 * c.value.abs());
                    json!({"min": c.value - w, "max": c.value + w, "init": c.value})
                }
                Some(c) => json!(c.value),
                // `inertial_sdof` has no Coulomb term: name it only when chosen.
                None if term == Term::Coulomb => continue,
                None => json!(0.0),
            };
            params.insert(term.param().into(), entry);
        }
        for (name, value, range) in [
            ("alpha", self.exponents.alpha, grid.alpha_range),
            ("beta", self.exponents.beta, grid.beta_range),
        ] {
            let entry = match value {
                Some(v) if !fixed => json!({
                    "min": (v - 0.1).max(range.0),
                    "max": (v + 0.1).min(range.1),
                    "init": v
                }),
                Some(v) => json!(v),
                None => json!(1.0),
            };
            params.insert(name.into(), entry);
        }
        json!({ "params": params })
    }
}

fn validate(opts: &DpeOptions) -> Result<(), IdentifyError> {
    if opts.terms.is_empty() {
        return Err(IdentifyError::InvalidOption {
            name: "terms",
            reason: "choose at least one term".into(),
        });
    }
    let g = &opts.grid;
    if !(g.step > 0.0 && g.tolerance > 0.0 && g.half_width >= 1) {
        return Err(IdentifyError::InvalidOption {
            name: "grid",
            reason: "the step, the tolerance and the half-width must be positive".into(),
        });
    }
    for (name, v, (lo, hi)) in [
        ("alpha", opts.alpha, g.alpha_range),
        ("beta", opts.beta, g.beta_range),
    ] {
        if let Some(v) = v
            && !(v.is_finite() && v >= lo && v <= hi)
        {
            return Err(IdentifyError::InvalidOption {
                name,
                reason: format!("{v} is outside [{lo}, {hi}]"),
            });
        }
    }
    Ok(())
}

/// Fits the chosen terms to the surface for fixed exponents.
fn fit_fixed(
    surface: &Surface,
    terms: &[Term],
    alpha: f64,
    beta: f64,
) -> Result<LinearFit, IdentifyError> {
    let columns: Vec<Vec<f64>> = terms
        .iter()
        .map(|t| {
            surface
                .x
                .iter()
                .zip(&surface.v)
                .map(|(&x, &v)| t.basis(x, v, alpha, beta))
                .collect()
        })
        .collect();
    least_squares(&columns, &surface.f)
}

/// The exponents one grid level tries on one axis: `centre + i·step` for `i`
/// in `−half_width..=half_width`, inside `range`; the centre alone on an axis
/// that is not searched.
fn axis_points(
    centre: f64,
    step: f64,
    half_width: i64,
    searched: bool,
    range: (f64, f64),
) -> Vec<f64> {
    (-half_width..=half_width)
        .filter(|&i| searched || i == 0)
        .map(|i| centre + i as f64 * step)
        .filter(|x| (range.0..=range.1).contains(x))
        .collect()
}

/// Direct parameter estimation on a restoring-force surface.
///
/// # Errors
/// [`IdentifyError::InvalidOption`] for no terms or a bad exponent or grid,
/// [`IdentifyError::Numerical`] when no grid point gives independent regressors,
/// and the errors of the least-squares solve.
pub fn estimate(surface: &Surface, opts: &DpeOptions) -> Result<DpeReport, IdentifyError> {
    validate(opts)?;
    let mut terms: Vec<Term> = Term::ALL
        .into_iter()
        .filter(|t| opts.terms.contains(t))
        .collect();
    terms.dedup();
    let search_alpha = terms.contains(&Term::PowerDamping) && opts.alpha.is_none();
    let search_beta = terms.contains(&Term::PowerStiffness) && opts.beta.is_none();
    let g = &opts.grid;
    let mut alpha = opts.alpha.unwrap_or(g.centre.0);
    let mut beta = opts.beta.unwrap_or(g.centre.1);
    let mut search = Vec::new();
    if search_alpha || search_beta {
        let mut step = g.step;
        let hw = g.half_width as i64;
        while step >= g.tolerance {
            let mut best: Option<(f64, f64, f64)> = None;
            let alphas = axis_points(alpha, step, hw, search_alpha, g.alpha_range);
            let betas = axis_points(beta, step, hw, search_beta, g.beta_range);
            for &a in &alphas {
                for &b in &betas {
                    if let Ok(fit) = fit_fixed(surface, &terms, a, b)
                        && best.is_none_or(|(_, _, s)| fit.sse < s)
                    {
                        best = Some((a, b, fit.sse));
                    }
                }
            }
            let Some((a, b, sse)) = best else {
                return Err(IdentifyError::Numerical {
                    stage: "exponent search",
                    reason: format!(
                        "no grid point around (α, β) = ({alpha}, {beta}) gives independent regressors"
                    ),
                });
            };
            (alpha, beta) = (a, b);
            search.push(GridLevel {
                step,
                alpha,
                beta,
                sse,
            });
            step /= 2.0;
        }
    }
    let fit = fit_fixed(surface, &terms, alpha, beta)?;
    let coefficients = terms
        .iter()
        .zip(&fit.coefficients)
        .map(|(&term, c)| Coefficient {
            term,
            param: term.param(),
            value: c.value,
            std_error: c.std_error,
            unit: term.unit(),
        })
        .collect();
    let mut report = DpeReport {
        samples: surface.f.len(),
        mass: surface.mass,
        coefficients,
        exponents: Exponents {
            alpha: terms.contains(&Term::PowerDamping).then_some(alpha),
            beta: terms.contains(&Term::PowerStiffness).then_some(beta),
        },
        r2: fit.r2,
        rms_residual: fit.rms,
        max_residual: 0.0,
        condition: fit.condition,
        search,
    };
    report.max_residual = surface
        .x
        .iter()
        .zip(&surface.v)
        .zip(&surface.f)
        .map(|((&x, &v), &f)| (f - report.force(x, v)).abs())
        .fold(0.0, f64::max);
    Ok(report)
}

/// Panels of the restoring-force figure: the stiffness slice (`|ẋ|` within 5 %
/// of its range) with `K(x)`, the damping slice (`|x|` within 5 %) with `C(ẋ)`,
/// and the samples' spread over the phase plane (*A New Fatigue Testing Rig Based on
/// Inertial Forces*, Fig. 6–7).
pub fn figure(surface: &Surface, report: &DpeReport) -> Vec<super::plot::Panel> {
    use super::plot::{FIT, MEASURED, Panel, Series, Style, thin};
    let curve = |xs: &[f64], f: &dyn Fn(f64) -> f64| -> Vec<(f64, f64)> {
        let (lo, hi) = xs
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        (0..=200)
            .map(|i| lo + (hi - lo) * i as f64 / 200.0)
            .map(|v| (v, f(v)))
            .collect()
    };
    let slice = |velocity_slice: bool| -> Vec<(f64, f64)> {
        let axis = if velocity_slice {
            &surface.v
        } else {
            &surface.x
        };
        thin(
            surface
                .slice(velocity_slice, 0.05)
                .into_iter()
                .map(|i| (axis[i], surface.f[i]))
                .collect(),
            3000,
        )
    };
    vec![
        Panel {
            caption: "stiffness slice (ẋ ≈ 0)".into(),
            x_desc: "x (m)".into(),
            y_desc: "restoring force (N)".into(),
            series: vec![
                Series {
                    label: "−m(a + ẍ)".into(),
                    points: slice(false),
                    style: Style::Dots,
                    color: MEASURED,
                },
                Series {
                    label: "K(x) fitted".into(),
                    points: curve(&surface.x, &|x| report.stiffness(x)),
                    style: Style::Line,
                    color: FIT,
                },
            ],
        },
        Panel {
            caption: "damping slice (x ≈ 0)".into(),
            x_desc: "ẋ (m/s)".into(),
            y_desc: "restoring force (N)".into(),
            series: vec![
                Series {
                    label: "−m(a + ẍ)".into(),
                    points: slice(true),
                    style: Style::Dots,
                    color: MEASURED,
                },
                Series {
                    label: "C(ẋ) fitted".into(),
                    points: curve(&surface.v, &|v| report.damping(v)),
                    style: Style::Line,
                    color: FIT,
                },
            ],
        },
        Panel {
            caption: "samples over the phase plane".into(),
            x_desc: "x (m)".into(),
            y_desc: "ẋ (m/s)".into(),
            series: vec![Series {
                label: "samples".into(),
                points: thin(
                    surface
                        .x
                        .iter()
                        .copied()
                        .zip(surface.v.iter().copied())
                        .collect(),
                    4000,
                ),
                style: Style::Dots,
                color: MEASURED,
            }],
        },
    ]
}
