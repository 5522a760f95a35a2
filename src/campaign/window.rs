//! An experiment's fit window: the samples of its record that 1 − R² scores.

use std::path::Path;

use super::CampaignError;
use super::error::invalid;
use super::raw::RawExperiment;
use crate::base::data::Series;

/// The sample range of the fit window; at least 2 samples inside the record.
pub(super) fn window(
    file: &Path,
    at: &str,
    x: &RawExperiment,
    s: &Series,
    warnings: &mut Vec<String>,
) -> Result<std::ops::Range<usize>, CampaignError> {
    let n = s.t.len();
    let (t0, tl) = (s.t[0], s.t[n - 1]);
    let w = x.fit_window.clone().unwrap_or(super::raw::RawWindow {
        start: None,
        end: None,
    });
    let (start, end) = (w.start.unwrap_or(t0), w.end.unwrap_or(tl));
    let path = format!("{at}.fit_window");
    // For the messages: brief, whatever the record's time scale.
    let num = crate::base::text::number;
    let (t0_, tl_, start_, end_) = (num(t0), num(tl), num(start), num(end));
    if start >= end {
        return Err(invalid(
            file,
            format!("{path}.end"),
            format!("end > start ({start_} s)"),
            format!("{end_} s"),
        ));
    }
    let tol = 1e-6;
    let k0 = ((start - t0) / s.dt - tol).ceil().max(0.0) as usize;
    let k1f = ((end - t0) / s.dt + tol).floor();
    let k1 = if k1f < 0.0 {
        None
    } else {
        Some((k1f as usize).min(n - 1))
    };
    match k1 {
        Some(k1) if k1 > k0 => {
            if start < t0 - tol * s.dt || end > tl + tol * s.dt {
                warnings.push(format!(
                    "{}: {path}: [{start_}, {end_}] s reaches beyond the record ({t0_} s to {tl_} s); \
                     only the overlap is scored",
                    file.display()
                ));
            }
            super::plausible::window_share(file, at, x, s, k0..k1 + 1)
        }
        _ => {
            let count = k1.map_or(0, |k1| (k1 + 1).saturating_sub(k0));
            Err(invalid(
                file,
                path,
                format!("a window holding at least 2 samples of the record ({t0_} s to {tl_} s)"),
                format!("[{start_}, {end_}] s holding {count} sample(s)"),
            ))
        }
    }
}
