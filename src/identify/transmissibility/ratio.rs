//! The transmissibility to channel `c`, `T_c = Σ_s U_s*·Y_{c,s} / Σ_s |U_s|²`
//! over the block spectra's segments (an H1 estimate with a measured output as
//! the input, the "transmissibility function formulation" of *Data interrogation
//! for vehicle suspensions*), with its coherence; and the figure that shows it
//! beside the element model and the ARX features.

use rustfft::num_complex::Complex64;

use super::arx::ArxLine;
use super::element::ElementFit;
use super::spectra::BlockSpectra;
use crate::identify::plot::{FIT, MEASURED, OTHER, Panel, Series, Style, THIRD, line_over};
use crate::identify::psd::lines_in_band;

impl BlockSpectra {
    /// `T_c(k)` and its coherence for response channel `c`.
    pub fn transmissibility(&self, c: usize) -> (Vec<Complex64>, Vec<f64>) {
        let y = &self.responses[c];
        (0..self.freqs.len())
            .map(|k| {
                let (mut uu, mut yy, mut uy) = (0.0, 0.0, Complex64::new(0.0, 0.0));
                for (us, ys) in self.reference.iter().zip(y) {
                    uu += us[k].norm_sqr();
                    yy += ys[k].norm_sqr();
                    uy += us[k].conj() * ys[k];
                }
                if uu > 0.0 && yy > 0.0 {
                    (uy / uu, (uy.norm_sqr() / (uu * yy)).min(1.0))
                } else {
                    (f64::NAN.into(), 0.0)
                }
            })
            .unzip()
    }
}

/// Panels of the transmissibility figure: magnitude (dB) and phase of the
/// measured `T_1` with the element model, and the coherence beside the ARX
/// feature `1 − |A_j|` of the linear model (Fig. 7–8).
pub fn figure(
    freqs: &[f64],
    transmissibilities: &[Vec<Complex64>],
    coherence: &[f64],
    fit: Option<&ElementFit>,
    arx_lines: &[ArxLine],
    band: (f64, f64),
) -> Vec<Panel> {
    let ks = lines_in_band(freqs, band);
    let t = &transmissibilities[0];
    let model = |k: usize| {
        let beyond: Vec<Complex64> = transmissibilities[1..].iter().map(|t| t[k]).collect();
        fit.map_or(f64::NAN.into(), |e| e.model(freqs[k], &beyond))
    };
    let series =
        |label: &str, f: &dyn Fn(usize) -> f64, color| line_over(label, freqs, &ks, f, color);
    let db = |c: Complex64| 20.0 * c.norm().log10();
    let deg = |c: Complex64| c.arg().to_degrees();
    let mut mag = vec![series("measured T", &|k| db(t[k]), MEASURED)];
    let mut phase = vec![series("measured T", &|k| deg(t[k]), MEASURED)];
    if fit.is_some() {
        mag.push(series("element model", &|k| db(model(k)), FIT));
        phase.push(series("element model", &|k| deg(model(k)), FIT));
    }
    let feature = |label: &str, pick: &dyn Fn(&ArxLine) -> (f64, f64), color| Series {
        label: label.into(),
        points: arx_lines
            .iter()
            .map(|l| {
                let (re, im) = pick(l);
                (l.frequency_hz, 1.0 - re.hypot(im))
            })
            .collect(),
        style: Style::Line,
        color,
    };
    vec![
        Panel {
            caption: "transmissibility magnitude".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "dB".into(),
            series: mag,
        },
        Panel {
            caption: "transmissibility phase".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "degrees".into(),
            series: phase,
        },
        Panel {
            caption: "coherence and ARX features 1 − |A_j|".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "".into(),
            series: vec![
                series("coherence", &|k| coherence[k], MEASURED),
                feature("1 − |A₋₁|", &|l| l.a_minus, OTHER),
                feature("1 − |A₁|", &|l| l.a_plus, THIRD),
            ],
        },
    ]
}
