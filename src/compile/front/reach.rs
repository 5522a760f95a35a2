//! The reach a law is checked over (how far an element's elongation and
//! rate go), and what a law found not finite there is said to be.

use crate::rig::desc::{Coef, RigDesc};

/// How far an element's elongation (m) and rate (m/s) reach: the rig's
/// `reach`, else the largest `breaks_at` (literal, or a parameter's value in
/// `values`) and 10 m/s, else 0.01 m and 10 m/s (as the stability bound).
pub fn law_reach(desc: &RigDesc, values: Option<&[f64]>) -> (f64, f64) {
    if let Some(r) = desc.reach {
        return (r.elongation, r.rate);
    }
    let value = |c: &Coef| -> f64 {
        match c {
            Coef::Number(v) => v.abs(),
            Coef::Param(n) => values
                .and_then(|v| {
                    let i = desc.params.iter().position(|p| &p.name == n)?;
                    v.get(i).map(|x| x.abs())
                })
                .unwrap_or(0.0),
            Coef::Switch(_) => literals(c).iter().fold(0.0, |m, v| m.max(v.abs())),
        }
    };
    let e = desc
        .elements
        .iter()
        .filter_map(|e| e.breaks_at.as_ref())
        .map(value)
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    (if e > 0.0 { e } else { 0.01 }, 10.0)
}

/// Where a law is evaluated over a reach: 201 points from `−reach` to
/// `reach`, 0 among them.
pub fn reach_points(reach: f64) -> Vec<f64> {
    (0..=200)
        .map(|j| reach * (f64::from(j) / 100.0 - 1.0))
        .collect()
}

/// What a law that is not finite is said to be: its text, the part and where.
pub fn not_finite_found(short: &str, nf: &super::expr::NotFinite, var: &str) -> String {
    let part = crate::base::text::echo(&nf.part);
    if nf.division {
        format!(
            "{short:?}, which divides by zero at {var} = {:e}: {part}",
            nf.at
        )
    } else {
        format!(
            "{short:?}, whose part {part} is {} at {var} = {:e}",
            nf.value, nf.at
        )
    }
}

/// The numbers written into a coefficient (both sides of a switch).
pub(super) fn literals(c: &Coef) -> Vec<f64> {
    match c {
        Coef::Number(v) => vec![*v],
        Coef::Param(_) => vec![],
        Coef::Switch(s) => {
            let mut v = literals(&s.before);
            v.extend(literals(&s.after));
            v
        }
    }
}
