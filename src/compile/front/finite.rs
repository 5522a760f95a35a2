//! Expression laws evaluated over the rig's reach at a campaign's parameter
//! values: a law that is not a finite number there (a division by a
//! parameter's bound of 0, `ln` of a negative) would make every candidate's
//! run meaningless, so it is refused before any work.
//!
//! The parts of a law that read no parameter are checked when the rig is
//! lowered ([`super::expr::Expr::fixed_part_not_finite`]); this check needs
//! the parameters' values, which only a campaign gives.

use super::expr;
use super::reach::{law_reach, reach_points};
use crate::rig::RigError;
use crate::rig::desc::{DamperLaw, RigDesc, SpringLaw};

/// Every expression law of `desc`: its JSON path, its text and its variable.
pub fn expression_laws(desc: &RigDesc) -> Vec<(String, &str, &'static str)> {
    let mut out = vec![];
    for (i, e) in desc.elements.iter().enumerate() {
        if let Some(SpringLaw::Expression { force }) = &e.spring {
            out.push((format!("elements[{i}].spring.force"), force.as_str(), "x"));
        }
        if let Some(DamperLaw::Expression { force }) = &e.damper {
            out.push((format!("elements[{i}].damper.force"), force.as_str(), "v"));
        }
    }
    out
}

/// Refuses the first expression law of `desc` (read from `file`) that is not
/// finite for its variable over the rig's reach with the parameters at any
/// of `corners` (full parameter vectors in the rig's order: a campaign's
/// lower and upper bounds).
pub fn check_laws(desc: &RigDesc, file: &str, corners: &[&[f64]]) -> Result<(), RigError> {
    for (path, src, var) in expression_laws(desc) {
        // Lowering parsed every law already; one that does not parse is not
        // this check's to report.
        let Ok(e) = expr::parse(src) else { continue };
        let mut names = vec![];
        e.names(&mut names);
        for values in corners {
            let (elongation, rate) = law_reach(desc, Some(values));
            let (reach, unit) = if var == "x" {
                (elongation, "m")
            } else {
                (rate, "m/s")
            };
            let value_of = |n: &str| -> f64 {
                desc.params
                    .iter()
                    .position(|p| p.name == n)
                    .and_then(|i| values.get(i).copied())
                    .unwrap_or(f64::NAN)
            };
            for x in reach_points(reach) {
                let v = e.eval(&|n| if n == var { x } else { value_of(n) });
                if v.is_finite() {
                    continue;
                }
                let mut params: Vec<String> = names
                    .iter()
                    .filter(|(n, _)| n != var)
                    .map(|(n, _)| format!("{n} = {:e}", value_of(n)))
                    .collect();
                params.sort_unstable();
                params.dedup();
                let short: String = src.chars().take(60).collect();
                let mut found = format!("{short:?}, which is {v} at {var} = {x:e}");
                if !params.is_empty() {
                    found += &format!(" with {}", params.join(", "));
                }
                return Err(RigError::new(
                    file,
                    path,
                    format!(
                        "a law finite for every {var} in [-{reach:e}, {reach:e}] {unit} (the \
                         rig's reach) with every parameter at either of its bounds"
                    ),
                    found,
                ));
            }
        }
    }
    Ok(())
}
