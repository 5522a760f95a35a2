//! The 2 × 2 impedance and receptance matrices of a point mass in two lateral
//! directions from two impact tests (*Experimental Investigations of Lubricated Bearing
//! Stiffness*, "Parameter identification": two linearly independent forces, their DFTs,
//! the impedances by matrix multiplication, curve fits of their real and imaginary
//! parts) — the two-degree-of-freedom form of the frequency-response and modal method.
//!
//! Test 1 strikes in x, test 2 in y; each records the force and the x and y
//! displacements. Per line `ω`, with the DFTs of the whole records,
//!
//! ```text
//! F = [[F_x1, F_x2], [F_y1, F_y2]] = [[F_1, 0], [0, F_2]]     D = [[X_1, X_2], [Y_1, Y_2]]
//! F = Z·D  ⇒  Z = F·D⁻¹,   G = Z⁻¹ = D·F⁻¹  (the flexibilities, receptance)
//! Z_ij(ω) = K_ij − ω²M·δ_ij + iω·C_ij
//! ```
//!
//! The paper's equations are missing from the text; this is their reading
//! in `../shared/design/model-families.md` (§3.3). The parameters come from
//! linear least squares over a band: `Re Z_xx`, `Re Z_yy` against
//! `K_xx − ω²M`, `K_yy − ω²M` (one mass for both, or the mass given),
//! `Re Z_xy`, `Re Z_yx` against constants, and `Im Z_ij` against `ω·C_ij`; each
//! fit's coefficient of determination is its acceptance figure (the
//! document's r², whose thresholds are blank in the text). The shipped
//! `bearing_2dof` rig joins x and y by one cross element, so its parameters
//! are `k_xy = −(K_xy + K_yx)/2`, `k_x = K_xx − k_xy`, `k_y = K_yy − k_xy`, and
//! the same for the dampings.

use std::f64::consts::PI;

use nalgebra::Matrix2;
use rustfft::FftPlanner;
use rustfft::num_complex::Complex64;
use serde::Serialize;

use super::lsq::least_squares;
use super::psd::{check_rate, lines_in_band};
use super::{IdentifyError, check_inputs, r_squared, require_points};

/// One impact test: the hammer force and the x and y displacements.
#[derive(Debug, Clone, Copy)]
pub struct ImpactRecord<'a> {
    /// Force (N) in the struck direction.
    pub force: &'a [f64],
    /// x displacement (m).
    pub x: &'a [f64],
    /// y displacement (m).
    pub y: &'a [f64],
}

/// The measured matrices on the lines of the records' DFT.
#[derive(Debug, Clone, PartialEq)]
pub struct ImpedanceMatrices {
    /// Line frequencies (Hz).
    pub freqs: Vec<f64>,
    /// `Z(ω)` per line (N/m).
    pub impedance: Vec<Matrix2<Complex64>>,
    /// `G(ω) = Z⁻¹` per line (m/N).
    pub receptance: Vec<Matrix2<Complex64>>,
}

/// The DFT of `x` over `n` samples (zero-padded when shorter), times `dt`.
fn dft(x: &[f64], n: usize, dt: f64) -> Vec<Complex64> {
    let mut b: Vec<Complex64> = (0..n)
        .map(|i| Complex64::new(x.get(i).copied().unwrap_or(0.0) * dt, 0.0))
        .collect();
    FftPlanner::new().plan_fft_forward(n).process(&mut b);
    b.truncate(n / 2 + 1);
    b
}

/// `Z = F·D⁻¹` and `G = D·F⁻¹` from an x impact and a y impact sampled at `fs` (Hz).
///
/// # Errors
/// Records of unequal length or with non-finite samples, fewer than 64
/// samples, a non-positive rate.
pub fn matrices(
    x_test: ImpactRecord<'_>,
    y_test: ImpactRecord<'_>,
    fs: f64,
) -> Result<ImpedanceMatrices, IdentifyError> {
    for r in [x_test, y_test] {
        check_inputs("force and x displacement", r.force, r.x)?;
        check_inputs("force and y displacement", r.force, r.y)?;
    }
    check_rate(fs)?;
    let n = x_test.force.len().max(y_test.force.len());
    require_points("samples per impact record", 64, n)?;
    let dt = 1.0 / fs;
    let (f1, x1, y1) = (
        dft(x_test.force, n, dt),
        dft(x_test.x, n, dt),
        dft(x_test.y, n, dt),
    );
    let (f2, x2, y2) = (
        dft(y_test.force, n, dt),
        dft(y_test.x, n, dt),
        dft(y_test.y, n, dt),
    );
    let zero = Complex64::new(0.0, 0.0);
    let nan = Matrix2::from_element(Complex64::new(f64::NAN, f64::NAN));
    let mut out = ImpedanceMatrices {
        freqs: (0..f1.len()).map(|k| k as f64 * fs / n as f64).collect(),
        impedance: Vec::with_capacity(f1.len()),
        receptance: Vec::with_capacity(f1.len()),
    };
    for k in 0..f1.len() {
        let f = Matrix2::new(f1[k], zero, zero, f2[k]);
        let d = Matrix2::new(x1[k], x2[k], y1[k], y2[k]);
        match (d.try_inverse(), f.try_inverse()) {
            (Some(di), Some(fi)) => {
                out.impedance.push(f * di);
                out.receptance.push(d * fi);
            }
            _ => {
                out.impedance.push(nan);
                out.receptance.push(nan);
            }
        }
    }
    Ok(out)
}

/// The fitted coefficients.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ImpedanceFit {
    /// Mass `M` (kg), fitted or given.
    pub mass: f64,
    /// Whether the mass was given.
    pub mass_given: bool,
    /// `[[K_xx, K_xy], [K_yx, K_yy]]` (N/m).
    pub stiffness: [[f64; 2]; 2],
    /// `[[C_xx, C_xy], [C_yx, C_yy]]` (N·s/m).
    pub damping: [[f64; 2]; 2],
    /// R² of the fits of `Re Z_ij` (the diagonal pair shares one), by `ij`.
    pub r2_real: [[f64; 2]; 2],
    /// R² of the fits of `Im Z_ij`.
    pub r2_imag: [[f64; 2]; 2],
    /// Lines used.
    pub lines: usize,
    /// The band (Hz).
    pub band_hz: (f64, f64),
}

impl ImpedanceFit {
    /// The model impedance at `f` (Hz).
    pub fn model(&self, f: f64) -> Matrix2<Complex64> {
        let w = 2.0 * PI * f;
        Matrix2::from_fn(|i, j| {
            let inertia = if i == j { w * w * self.mass } else { 0.0 };
            Complex64::new(self.stiffness[i][j] - inertia, w * self.damping[i][j])
        })
    }

    /// The parameters of the shipped `bearing_2dof` rig: `m`, `k_x`, `k_y`,
    /// `k_xy`, `c_x`, `c_y`, `c_xy` (one symmetric cross element).
    pub fn bearing_params(&self) -> [(&'static str, f64); 7] {
        let (k, c) = (&self.stiffness, &self.damping);
        let kxy = -0.5 * (k[0][1] + k[1][0]);
        let cxy = -0.5 * (c[0][1] + c[1][0]);
        [
            ("m", self.mass),
            ("k_x", k[0][0] - kxy),
            ("k_y", k[1][1] - kxy),
            ("k_xy", kxy),
            ("c_x", c[0][0] - cxy),
            ("c_y", c[1][1] - cxy),
            ("c_xy", cxy),
        ]
    }

    /// `{"params": {…}}` in the names of `bearing_2dof`: free with `init` at the
    /// estimate and bounds ±50 % of the larger of the value and a tenth of the
    /// direct term, or plain numbers with `fixed`; a given mass stays fixed.
    pub fn to_campaign_fragment(&self, fixed: bool) -> serde_json::Value {
        let p = self.bearing_params();
        let direct_k = p[1].1.abs().max(p[2].1.abs());
        let direct_c = p[4].1.abs().max(p[5].1.abs());
        let mut params = serde_json::Map::new();
        for (name, v) in p {
            let entry = if fixed || (name == "m" && self.mass_given) {
                serde_json::json!(v)
            } else {
                let floor = match name {
                    "k_xy" => 0.1 * direct_k,
                    "c_xy" => 0.1 * direct_c,
                    _ => 0.0,
                };
                let w = 0.5 * v.abs().max(floor);
                let lo = if matches!(name, "k_xy" | "c_xy") {
                    v - w
                } else {
                    (v - w).max(0.0)
                };
                serde_json::json!({"min": lo, "max": v + w, "init": v})
            };
            params.insert(name.into(), entry);
        }
        serde_json::json!({ "params": params })
    }
}

/// Fits `K_ij`, `C_ij` and `M` (unless `mass` is given) over `band` (Hz).
///
/// # Errors
/// [`IdentifyError::TooFewPoints`] for fewer than four finite lines in the band,
/// and the least-squares errors.
pub fn fit(
    m: &ImpedanceMatrices,
    band: (f64, f64),
    mass: Option<f64>,
) -> Result<ImpedanceFit, IdentifyError> {
    let lines: Vec<usize> = lines_in_band(&m.freqs, band)
        .into_iter()
        .filter(|&k| m.freqs[k] > 0.0)
        .filter(|&k| {
            m.impedance[k]
                .iter()
                .all(|z| z.re.is_finite() && z.im.is_finite())
        })
        .collect();
    require_points("lines in the band", 4, lines.len())?;
    let w: Vec<f64> = lines.iter().map(|&k| 2.0 * PI * m.freqs[k]).collect();
    let z = |i: usize, j: usize| -> Vec<Complex64> {
        lines.iter().map(|&k| m.impedance[k][(i, j)]).collect()
    };
    let n = lines.len();
    // Diagonal real parts: K_xx, K_yy and the shared −ω²M.
    let (zxx, zyy) = (z(0, 0), z(1, 1));
    let (mut re_diag, mut cx, mut cy, mut cm) = (vec![], vec![], vec![], vec![]);
    for i in 0..n {
        for (zz, is_x) in [(zxx[i], true), (zyy[i], false)] {
            let known = mass.map_or(0.0, |ms| -w[i] * w[i] * ms);
            re_diag.push(zz.re - known);
            cx.push(if is_x { 1.0 } else { 0.0 });
            cy.push(if is_x { 0.0 } else { 1.0 });
            cm.push(-w[i] * w[i]);
        }
    }
    let diag = if mass.is_some() {
        least_squares(&[cx, cy], &re_diag)?
    } else {
        least_squares(&[cx, cy, cm], &re_diag)?
    };
    let (kxx, kyy) = (diag.coefficients[0].value, diag.coefficients[1].value);
    let mass_value = mass.unwrap_or(diag.coefficients.get(2).map_or(0.0, |c| c.value));
    let r2_of = |values: &[f64], model: &dyn Fn(usize) -> f64| {
        let sse: f64 = values
            .iter()
            .enumerate()
            .map(|(i, v)| (v - model(i)).powi(2))
            .sum();
        r_squared(sse, values)
    };
    let mut stiffness = [[kxx, 0.0], [0.0, kyy]];
    let mut damping = [[0.0; 2]; 2];
    let mut r2_real = [[0.0; 2]; 2];
    let mut r2_imag = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            let zij = z(i, j);
            let re: Vec<f64> = zij.iter().map(|v| v.re).collect();
            let im: Vec<f64> = zij.iter().map(|v| v.im).collect();
            if i == j {
                let kk = stiffness[i][i];
                r2_real[i][j] = r2_of(&re, &|l| kk - w[l] * w[l] * mass_value);
            } else {
                // The best constant is the mean; R² of a constant against its
                // own data is 0 by definition, so report the spread instead.
                let mean = re.iter().sum::<f64>() / n as f64;
                stiffness[i][j] = mean;
                r2_real[i][j] = 1.0
                    - re.iter().map(|v| (v - mean).powi(2)).sum::<f64>()
                        / re.iter().map(|v| v * v).sum::<f64>().max(f64::MIN_POSITIVE);
            }
            // Im Z = ω·C through the origin.
            let c = im.iter().zip(&w).map(|(v, wi)| v * wi).sum::<f64>()
                / w.iter().map(|wi| wi * wi).sum::<f64>();
            damping[i][j] = c;
            r2_imag[i][j] = r2_of(&im, &|l| w[l] * c);
        }
    }
    Ok(ImpedanceFit {
        mass: mass_value,
        mass_given: mass.is_some(),
        stiffness,
        damping,
        r2_real,
        r2_imag,
        lines: n,
        band_hz: band,
    })
}

/// Panels of the impedance figure: real and imaginary parts of the four
/// impedances with the fitted model, against frequency.
pub fn figure(m: &ImpedanceMatrices, fit: &ImpedanceFit) -> Vec<super::plot::Panel> {
    use super::plot::{FIT, MEASURED, Panel, Series, Style};
    let ks = lines_in_band(&m.freqs, fit.band_hz);
    let names = ["x", "y"];
    let mut panels = vec![];
    for (part, pick) in [
        ("Re", (|z: Complex64| z.re) as fn(Complex64) -> f64),
        ("Im", |z: Complex64| z.im),
    ] {
        for i in 0..2 {
            for j in 0..2 {
                let points = |f: &dyn Fn(usize) -> Complex64| -> Vec<(f64, f64)> {
                    ks.iter().map(|&k| (m.freqs[k], pick(f(k)))).collect()
                };
                panels.push(Panel {
                    caption: format!("{part} Z_{}{}", names[i], names[j]),
                    x_desc: "frequency (Hz)".into(),
                    y_desc: "N/m".into(),
                    series: vec![
                        Series {
                            label: "measured".into(),
                            points: points(&|k| m.impedance[k][(i, j)]),
                            style: Style::Dots,
                            color: MEASURED,
                        },
                        Series {
                            label: "fit".into(),
                            points: points(&|k| fit.model(m.freqs[k])[(i, j)]),
                            style: Style::Line,
                            color: FIT,
                        },
                    ],
                });
            }
        }
    }
    panels
}
