//! Records checked against their campaign when they are given, before any
//! search: a record in the wrong unit is refused while it is read, not
//! fitted to an R² of −0.5 or −175 585.
//!
//! - **Time scale**: a fit window that keeps fewer than
//!   [`MIN_WINDOW_SAMPLES`] samples and under [`MIN_WINDOW_SHARE`] of the
//!   record is refused (a time column in milliseconds read as seconds keeps
//!   3 of 2 501 samples in a window of 2.5 ms). A record sampled far slower
//!   than the rig moves is warned of where the step is chosen
//!   ([`crate::base::data::slow_sampling_hint`]).
//! - **Start**: a record that starts long after the model's start at rest at
//!   `t = 0` ([`LATE_START_FACTOR`] times its own span) is warned of: every
//!   run integrates that stretch first.
//! - **Magnitude**: the rig is run at the centre of the bounds (the initial
//!   values) and at their two corners; a record whose RMS over the fit window
//!   is [`MAGNITUDE_FACTOR`] times larger than the largest of those runs, or
//!   that many times smaller than the smallest, is refused with the scale
//!   that would fix it where it is off by a power of 10³ within
//!   [`UNIT_BAND`] (a force in kN against a rig in N is 1000× too small),
//!   and warned of otherwise (a drive or a window that misses the motion).

use std::ops::{ControlFlow, Range};
use std::path::Path;

use super::error::invalid;
use super::raw::RawExperiment;
use super::{Campaign, CampaignError};
use crate::base::Report;
use crate::base::data::Series;
use crate::base::text::{echo_bare, number};

/// A given fit window holding fewer samples than this, and under
/// [`MIN_WINDOW_SHARE`] of the record, is refused.
pub const MIN_WINDOW_SAMPLES: usize = 10;

/// See [`MIN_WINDOW_SAMPLES`].
pub const MIN_WINDOW_SHARE: f64 = 0.1;

/// A record whose RMS is this many times off every run of the rig at the
/// bounds is refused.
pub const MAGNITUDE_FACTOR: f64 = 100.0;

/// A record off by a power of 10³ within this factor either way is refused
/// (a unit prefix); further off, it is warned of.
pub const UNIT_BAND: f64 = 3.0;

/// RK4 steps the magnitude check may take for one experiment (its three
/// runs together: a few hundredths of a second on the CPU lanes, up to about
/// 2 s for a rig without them): a longer experiment is not checked.
pub const MAGNITUDE_MAX_STEPS: f64 = 1e6;

/// A record starting later than this many times its own span after `t = 0`
/// is warned of.
pub const LATE_START_FACTOR: f64 = 1e3;

/// The sample range `window` of experiment `at`'s record `s` (`x` read
/// it): refused when `x` gives a fit window that keeps fewer than
/// [`MIN_WINDOW_SAMPLES`] samples and under [`MIN_WINDOW_SHARE`] of them.
pub(super) fn window_share(
    file: &Path,
    at: &str,
    x: &RawExperiment,
    s: &Series,
    window: Range<usize>,
) -> Result<Range<usize>, CampaignError> {
    let Some(w) = &x.fit_window else {
        return Ok(window);
    };
    let n = s.t.len();
    let (t0, tl) = (s.t[0], s.t[n - 1]);
    let given = (w.start.unwrap_or(t0), w.end.unwrap_or(tl));
    let time_scale = x.data.time_scale;
    let kept = window.len();
    if kept >= MIN_WINDOW_SAMPLES || kept as f64 >= MIN_WINDOW_SHARE * n as f64 {
        return Ok(window);
    }
    let hint = if time_scale == 1.0 {
        format!(
            "if the record's time column holds milliseconds, set \"time_scale\": 1e-3 in \
             {at}.data (Campaign.set_data: time_scale=1e-3)"
        )
    } else {
        format!(
            "check {at}.data.time_scale ({}: the record's times in seconds are its column \
             times that)",
            number(time_scale)
        )
    };
    Err(invalid(
        file,
        format!("{at}.fit_window"),
        format!(
            "a window holding at least {MIN_WINDOW_SAMPLES} samples or {:.0} % of the record; {hint}",
            100.0 * MIN_WINDOW_SHARE
        ),
        format!(
            "[{}, {}] s holding {kept} of the record's {n} samples ({} s to {} s)",
            number(given.0),
            number(given.1),
            number(t0),
            number(tl)
        ),
    ))
}

/// The checks a loaded campaign's records get against the rig (see the
/// module's notes): warnings to add, or the refusal of a record whose
/// magnitude the rig cannot produce.
pub(super) fn check(c: &Campaign) -> Result<Vec<String>, CampaignError> {
    let mut warnings = Vec::new();
    let names = c.model.output_names();
    // A run too long for the default limit is refused with the same hint.
    let runs = c.run_length().experiments;
    for (e, x) in c.problem.experiments.iter().enumerate() {
        let owner = c.owners[e];
        let at = format!("experiments[{owner}]");
        let span = x.dt * x.window.end.saturating_sub(1).max(1) as f64;
        if x.t_first > LATE_START_FACTOR * span && runs[e].steps <= super::DEFAULT_MAX_STEPS {
            warnings.push(format!(
                "{}: {at} ('{}'): the record starts at t = {} s, {:.0e} times its own span \
                 ({} s) after the model's start at rest at t = 0, and every run integrates that \
                 stretch first; if its clock does not start with the test, shift it: \
                 \"offset\": {} in {at}",
                c.path.display(),
                echo_bare(&x.name),
                number(x.t_first),
                x.t_first / span,
                number(span),
                number(-x.t_first),
            ));
        }
        let Some(m) = magnitude(c, e) else { continue };
        let (unit_name, unit) = names
            .get(x.output)
            .map_or(("", ""), |(n, u)| (n.as_str(), u.as_str()));
        let channel = c.owners.iter().filter(|&&o| o == owner).count() > 1;
        let key = if channel {
            format!("{at}.channels (the channel of output '{unit_name}')")
        } else {
            format!("{at}.data")
        };
        let Some((message, refuse)) = refusal(&m, unit_name, unit, &key) else {
            if m.model_max == 0.0 && m.record > 0.0 {
                warnings.push(format!(
                    "{}: {at} ('{}'): the rig's output '{unit_name}' is 0 over the fit window at \
                     the centre and corners of the bounds, while the record varies: check the \
                     drive and the record's time",
                    c.path.display(),
                    echo_bare(&x.name)
                ));
            }
            continue;
        };
        let sizes = format!(
            "RMS {} to {} {unit} over the fit window at the centre and corners of the bounds",
            number(m.model_min),
            number(m.model_max)
        );
        if !refuse {
            warnings.push(format!(
                "{}: {at}.data ('{}'): the record's RMS, {} read as {unit}, is {message} ({sizes})",
                c.path.display(),
                echo_bare(&x.name),
                number(m.record)
            ));
            continue;
        }
        {
            return Err(invalid(
                &c.path,
                format!("{at}.data"),
                format!(
                    "a record of the size the rig produces ({}: {sizes})",
                    if unit_name.is_empty() {
                        "output"
                    } else {
                        unit_name
                    },
                ),
                format!("RMS {} read as {unit}, {message}", number(m.record)),
            ));
        }
    }
    Ok(warnings)
}

/// RMS over the fit window of the record and of the rig's runs.
#[derive(Debug, Clone, Copy)]
struct Magnitude {
    record: f64,
    model_min: f64,
    model_max: f64,
}

/// `m` in words, with the scale that fixes it, when the record is
/// [`MAGNITUDE_FACTOR`] times off every run, and whether to refuse it: off
/// by a power of 10³ within [`UNIT_BAND`] (a unit's prefix), else a warning;
/// `None` within reach.
fn refusal(m: &Magnitude, name: &str, unit: &str, key: &str) -> Option<(String, bool)> {
    let (ratio, needed) = if m.record > MAGNITUDE_FACTOR * m.model_max && m.model_max > 0.0 {
        let r = m.record / m.model_max;
        (format!("about {}× larger", round_ratio(r)), 1.0 / r)
    } else if m.record * MAGNITUDE_FACTOR < m.model_min && m.record > 0.0 {
        let r = m.model_min / m.record;
        (format!("about {}× smaller", round_ratio(r)), r)
    } else {
        return None;
    };
    // The power of 10³ nearest the ratio: a unit prefix.
    let k = (needed.log10() / 3.0).round() as i32;
    let scale = 10f64.powi(3 * k);
    let guess = match (k, unit.is_empty() || unit == "1") {
        (_, true) => String::new(),
        (-3, _) => format!("is it in n{unit} while the rig's '{name}' is in {unit}? "),
        (-2, _) => format!("is it in µ{unit} while the rig's '{name}' is in {unit}? "),
        (-1, _) => format!("is it in m{unit} while the rig's '{name}' is in {unit}? "),
        (1, _) => format!("is it in k{unit} while the rig's '{name}' is in {unit}? "),
        (2, _) => format!("is it in M{unit} while the rig's '{name}' is in {unit}? "),
        _ => String::new(),
    };
    let off = (needed.log10() - 3.0 * k as f64).abs();
    let fix = if k != 0 && off < 0.75 {
        format!(
            "{guess}set \"scale\": {scale:e} in {key} (Campaign.set_data: scale={scale:e}), the \
             multiplier to {}",
            if unit.is_empty() {
                "the output's unit".to_string()
            } else {
                unit.to_string()
            }
        )
    } else {
        format!("check the record's unit and the \"scale\" in {key}")
    };
    let refuse = k != 0 && off < UNIT_BAND.log10();
    Some((format!("{ratio} than the rig produces: {fix}"), refuse))
}

/// `r` with two significant digits.
fn round_ratio(r: f64) -> String {
    if !r.is_finite() {
        return number(r);
    }
    let p = 10f64.powf(r.log10().floor() - 1.0);
    number((r / p).round() * p)
}

/// The record's RMS over the fit window and the smallest and largest RMS of
/// the rig's output there at the centre and the corners of the bounds; `None`
/// where the runs would take more than [`MAGNITUDE_MAX_STEPS`], or none of
/// them stays finite.
fn magnitude(c: &Campaign, e: usize) -> Option<Magnitude> {
    let x = &c.problem.experiments[e];
    let grid = x.grid(c.base_offsets[e], c.problem.substeps);
    if 3.0 * grid.total_steps() as f64 > MAGNITUDE_MAX_STEPS || x.window.is_empty() {
        return None;
    }
    let (lo, hi) = c.bounds(e);
    let points: [&[f64]; 3] = [&c.base[e], &lo, &hi];
    let mut sums = [0.0_f64; 3];
    let mut finite = [true; 3];
    c.model
        .simulate_many(&points, &x.drive, &grid, Report::Full, &mut |run, s| {
            if x.window.contains(&s.index) {
                let y = s.outputs.get(x.output).copied().unwrap_or(f64::NAN);
                if !y.is_finite() {
                    finite[run] = false;
                    return ControlFlow::Break(());
                }
                sums[run] += y * y;
            }
            ControlFlow::Continue(())
        });
    let n = x.window.len() as f64;
    let rms: Vec<f64> = (0..3)
        .filter(|&i| finite[i])
        .map(|i| (sums[i] / n).sqrt())
        .filter(|r| r.is_finite())
        .collect();
    if rms.is_empty() {
        return None;
    }
    let w = &x.measured[x.window.clone()];
    let record = (w.iter().map(|y| y * y).sum::<f64>() / n).sqrt();
    record.is_finite().then(|| Magnitude {
        record,
        model_min: rms.iter().copied().fold(f64::INFINITY, f64::min),
        model_max: rms.iter().copied().fold(0.0, f64::max),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(record: f64, lo: f64, hi: f64) -> Magnitude {
        Magnitude {
            record,
            model_min: lo,
            model_max: hi,
        }
    }

    #[test]
    fn a_record_in_kn_against_newtons_is_refused_with_the_scale() {
        let msg = refusal(&m(4.4, 3e3, 6e3), "load_cell_force", "N", "k").expect("refused");
        assert!(msg.1, "{msg:?}");
        let msg = msg.0;
        assert!(msg.contains("smaller"), "{msg}");
        assert!(msg.contains("in kN"), "{msg}");
        assert!(msg.contains("\"scale\": 1e3"), "{msg}");
    }

    #[test]
    fn a_record_in_mm_against_metres_is_refused_with_the_scale() {
        let msg = refusal(&m(5.0, 1e-3, 8e-3), "x", "m", "k").expect("refused");
        assert!(msg.1, "{msg:?}");
        let msg = msg.0;
        assert!(msg.contains("larger") && msg.contains("in mm"), "{msg}");
        assert!(msg.contains("\"scale\": 1e-3"), "{msg}");
    }

    #[test]
    fn a_record_within_reach_of_the_bounds_passes() {
        assert!(refusal(&m(50.0, 3.0, 6e3), "f", "N", "k").is_none());
        assert!(refusal(&m(5e4, 3.0, 6e3), "f", "N", "k").is_none());
        assert!(refusal(&m(0.0, 0.0, 0.0), "f", "N", "k").is_none());
    }

    #[test]
    fn a_record_far_off_but_not_by_a_unit_prefix_is_warned_of() {
        let (msg, refuse) = refusal(&m(24.0, 0.0, 0.08), "f", "N", "k").expect("off");
        assert!(!refuse && msg.contains("300× larger"), "{msg}");
    }
}
