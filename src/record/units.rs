//! A channel's recorded unit against the unit the rig's output declares,
//! given the campaign's scale: `kN` against `N` needs a scale of 1e3, `mV`
//! against `N` needs some scale (the sensor's sensitivity), `N` against `N`
//! needs none.

/// SI prefixes a recorded unit may carry, with their factors.
const PREFIXES: [(&str, f64); 9] = [
    ("p", 1e-12),
    ("n", 1e-9),
    ("µ", 1e-6),
    ("μ", 1e-6),
    ("u", 1e-6),
    ("m", 1e-3),
    ("c", 1e-2),
    ("k", 1e3),
    ("M", 1e6),
];

/// How a recorded unit relates to the rig's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Agreement {
    /// The same unit, or one whose prefix the scale converts.
    Agrees,
    /// A scale far from what the units say: the prefix factor it should be
    /// (1 for the same unit).
    ScaleOff(f64),
    /// Another quantity (`mV` against `N`): only a stated scale can relate them.
    Other,
}

/// `unit` in one spelling: blanks and brackets dropped, `^2`, `**2`, `2` after
/// a slash read as `²`, `·` and `*` and `.` between factors as `·`.
pub fn normal(unit: &str) -> String {
    let u: String = unit
        .trim()
        .trim_start_matches(['[', '('])
        .trim_end_matches([']', ')'])
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect();
    let u = u.replace("**2", "²").replace("^2", "²").replace('*', "·");
    match u.strip_suffix('2') {
        Some(head) if head.contains('/') && head.ends_with(|c: char| c.is_alphabetic()) => {
            format!("{head}²")
        }
        _ => u,
    }
}

/// The factor turning `recorded` into `expected` where one is the other with
/// an SI prefix (`kN` → `N`: 1e3), 1 where they are the same.
pub fn factor(recorded: &str, expected: &str) -> Option<f64> {
    let (r, e) = (normal(recorded), normal(expected));
    if r == e {
        return Some(1.0);
    }
    let prefixed = |a: &str, b: &str| {
        PREFIXES
            .iter()
            .find(|(p, _)| a.strip_prefix(p) == Some(b))
            .map(|&(_, f)| f)
    };
    // `mm/s²` against `m/s²`, and `N` against `kN` (a record finer than the rig).
    prefixed(&r, &e).or_else(|| prefixed(&e, &r).map(|f| 1.0 / f))
}

/// How a channel recorded in `recorded` and scaled by `scale` meets a rig
/// output in `expected`. A scale within a factor of 2 of the prefix factor
/// agrees (a sensor's calibration correction).
pub fn agreement(recorded: &str, expected: &str, scale: f64) -> Agreement {
    match factor(recorded, expected) {
        Some(f) if (scale / f).abs().log10().abs() <= 2f64.log10() + 1e-12 => Agreement::Agrees,
        Some(f) => Agreement::ScaleOff(f),
        None => Agreement::Other,
    }
}

/// Why a channel in `recorded` scaled by `scale` cannot be the output
/// `output` in `expected`, or none where it can; the wording names the
/// campaign key that fixes it (`key`: `"scale"` or `"time_scale"`).
pub fn refusal(
    recorded: &str,
    expected: &str,
    scale: f64,
    output: &str,
    key: &str,
) -> Option<String> {
    let said = |f: f64| crate::base::text::number(f);
    match agreement(recorded, expected, scale) {
        Agreement::Agrees => None,
        Agreement::ScaleOff(f) => Some(format!(
            "the record is in {recorded} and {output} is in {expected}: \"{key}\" {} (it is {})",
            said(f),
            said(scale)
        )),
        Agreement::Other if scale == 1.0 => Some(format!(
            "the record is in {recorded} and {output} is in {expected}: another quantity, which \
             only a \"{key}\" converts (a sensor's sensitivity, {expected} per {recorded})"
        )),
        Agreement::Other => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefixes_and_spellings_agree_when_the_scale_converts() {
        assert_eq!(agreement("N", "N", 1.0), Agreement::Agrees);
        assert_eq!(agreement("[kN]", "N", 1e3), Agreement::Agrees);
        assert_eq!(agreement("kN", "N", 1.0), Agreement::ScaleOff(1e3));
        assert_eq!(agreement("mm", "m", 1e-3), Agreement::Agrees);
        assert_eq!(agreement("m/s^2", "m/s²", 1.0), Agreement::Agrees);
        assert_eq!(agreement("m/s2", "m/s²", 1.0), Agreement::Agrees);
        assert_eq!(agreement("µm", "m", 1.02e-6), Agreement::Agrees);
        assert_eq!(agreement("ms", "s", 1e-3), Agreement::Agrees);
        assert_eq!(agreement("mV", "N", 1.0), Agreement::Other);
        assert_eq!(agreement("N", "kN", 1e-3), Agreement::Agrees);
    }

    #[test]
    fn a_refusal_names_the_key_and_the_factor() {
        let r = refusal("kN", "N", 1.0, "load_cell_force", "scale").unwrap();
        assert!(
            r.contains("\"scale\" 1000") || r.contains("\"scale\" 1e3"),
            "{r}"
        );
        let r = refusal("mV", "N", 1.0, "load_cell_force", "scale").unwrap();
        assert!(r.contains("sensitivity"), "{r}");
        assert_eq!(refusal("mV", "N", 2.5, "load_cell_force", "scale"), None);
        assert_eq!(refusal("N", "N", 1.0, "f", "scale"), None);
    }
}
