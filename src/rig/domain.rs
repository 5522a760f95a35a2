//! A rig parameter's physical domain: the values that mean something
//! physically (a mass > 0, a damping ≥ 0, a velocity of either sign).
//!
//! A rig file may say it with a parameter's `"domain"` key; without one it is
//! derived ([`of`]) from what the rig does with the parameter (its roles: a
//! node's mass is positive, a linear spring's stiffness or a viscous
//! damper's coefficient nonnegative, …), from its unit where that alone is
//! unambiguous (kg, kg·m²: masses and inertias, positive), and from its
//! search scale (`"log"`: positive); the strictest of those holds, and a
//! parameter with none of them takes any value. A campaign's fixed value,
//! bound or `init` outside the domain is refused before any work.

use serde::Deserialize;

use super::desc::{Coef, DamperLaw, DriveLaw, FrictionLaw, ParamDesc, RigDesc, SpringLaw};
use crate::base::Scale;

/// The values a parameter may take.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Domain {
    /// Any finite value (or `null`, +∞, where the rig reads it as "never").
    Any,
    /// `≥ 0`.
    Nonnegative,
    /// `> 0`.
    Positive,
}

impl Domain {
    /// Whether `v` lies in the domain (+∞ lies in all of them).
    pub fn contains(self, v: f64) -> bool {
        match self {
            Domain::Any => !v.is_nan(),
            Domain::Nonnegative => v >= 0.0,
            Domain::Positive => v > 0.0,
        }
    }

    /// The key's word (`"positive"`).
    pub fn word(self) -> &'static str {
        match self {
            Domain::Any => "any",
            Domain::Nonnegative => "nonnegative",
            Domain::Positive => "positive",
        }
    }

    /// The condition on a value (`"> 0"`).
    pub fn condition(self) -> &'static str {
        match self {
            Domain::Any => "any value",
            Domain::Nonnegative => "≥ 0",
            Domain::Positive => "> 0",
        }
    }
}

/// A parameter's domain and where it comes from, for messages.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamDomain {
    /// The values it may take.
    pub domain: Domain,
    /// Why: `"declared"` for a `"domain"` key, else what it was derived from
    /// (`"a linear spring's stiffness (elements[0].spring.k)"`).
    pub why: String,
}

/// Parameter `name`'s domain in `rig` (`Any` for a name the rig lacks).
pub fn of(rig: &RigDesc, name: &str) -> ParamDomain {
    let Some(p) = rig.params.iter().find(|p| p.name == name) else {
        return ParamDomain {
            domain: Domain::Any,
            why: "not a parameter of the rig file".into(),
        };
    };
    if let Some(d) = p.domain {
        return ParamDomain {
            domain: d,
            why: "declared".into(),
        };
    }
    let mut best = (
        Domain::Any,
        String::from("no role, unit or scale that bounds it"),
    );
    let mut take = |d: Domain, why: String| {
        if d > best.0 {
            best = (d, why);
        }
    };
    if let Some(d) = unit_domain(&p.unit) {
        take(d, format!("its unit {} (a mass or an inertia)", p.unit));
    }
    for (d, why) in roles(rig, name) {
        take(d, why);
    }
    if p.scale == Scale::Log {
        take(Domain::Positive, "its search scale \"log\"".into());
    }
    ParamDomain {
        domain: best.0,
        why: best.1,
    }
}

/// The message's words for a value of `p` outside its domain `d` in rig `rig`:
/// `a value > 0: rig 'tensile4' declares k1 (N/m) positive (derived from …)`.
pub fn expected(rig: &str, p: &ParamDesc, d: &ParamDomain) -> String {
    let from = if d.why == "declared" {
        "its \"domain\" key".to_string()
    } else {
        format!(
            "derived from {}; a \"domain\" key on the parameter would say otherwise",
            d.why
        )
    };
    format!(
        "a value {}: rig '{rig}' declares {} ({}) {} ({from})",
        d.domain.condition(),
        p.name,
        p.unit,
        d.domain.word()
    )
}

/// Units that are a mass's or an inertia's whatever the role.
fn unit_domain(unit: &str) -> Option<Domain> {
    let u: String = unit.chars().filter(|c| !c.is_whitespace()).collect();
    matches!(
        u.as_str(),
        "kg" | "kg·m²" | "kg·m^2" | "kg*m^2" | "kg.m^2" | "kgm^2" | "kg·m2" | "kgm²"
    )
    .then_some(Domain::Positive)
}

/// What the rig does with parameter `name` that bounds it, with the JSON
/// path of each use.
fn roles(rig: &RigDesc, name: &str) -> Vec<(Domain, String)> {
    use Domain::{Nonnegative as N, Positive as P};
    let mut out = Vec::new();
    let mut role = |c: &Coef, d: Domain, what: &str, path: String| {
        if mentions(c, name) {
            out.push((d, format!("{what} ({path})")));
        }
    };
    for (k, node) in rig.nodes.iter().enumerate() {
        role(&node.mass, P, "a node's mass", format!("nodes[{k}].mass"));
    }
    for (k, e) in rig.elements.iter().enumerate() {
        let at = format!("elements[{k}]");
        match &e.spring {
            Some(SpringLaw::Linear { k: s }) => role(
                s,
                N,
                "a linear spring's stiffness",
                format!("{at}.spring.k"),
            ),
            Some(SpringLaw::LinearThenPolynomial { k: s, .. })
            | Some(SpringLaw::ExpLinear { k: s, .. }) => {
                role(s, N, "a spring's stiffness", format!("{at}.spring.k"))
            }
            // A power-law term's coefficient may take either sign (a
            // correction to the element's other terms); its exponent not.
            Some(SpringLaw::PowerLaw { beta, .. }) => {
                role(
                    beta,
                    N,
                    "a power law's exponent",
                    format!("{at}.spring.beta"),
                );
            }
            _ => {}
        }
        match &e.damper {
            Some(DamperLaw::Viscous { c }) => role(
                c,
                N,
                "a viscous damper's coefficient",
                format!("{at}.damper.c"),
            ),
            Some(DamperLaw::PowerLaw { alpha, .. }) => {
                role(
                    alpha,
                    N,
                    "a power law's exponent",
                    format!("{at}.damper.alpha"),
                );
            }
            Some(DamperLaw::Saturating { c, c_high, v_knee }) => {
                role(c, N, "a damper's coefficient", format!("{at}.damper.c"));
                role(
                    c_high,
                    N,
                    "a damper's coefficient",
                    format!("{at}.damper.c_high"),
                );
                role(v_knee, N, "a knee velocity", format!("{at}.damper.v_knee"));
            }
            Some(DamperLaw::Asymmetric {
                c_tension,
                c_compression,
            }) => {
                let d = "a damper's coefficient";
                role(c_tension, N, d, format!("{at}.damper.c_tension"));
                role(c_compression, N, d, format!("{at}.damper.c_compression"));
            }
            _ => {}
        }
        if let Some(FrictionLaw::StickSlip { f_c, k_t }) = &e.friction {
            role(f_c, N, "a slip force", format!("{at}.friction.f_c"));
            role(
                k_t,
                N,
                "a tangential stiffness",
                format!("{at}.friction.k_t"),
            );
        }
        if let Some(g) = &e.gap {
            role(&g.size, N, "a gap's size", format!("{at}.gap.size"));
        }
        if let Some(b) = &e.backlash {
            let path = format!("{at}.backlash.half_width");
            role(&b.half_width, N, "a play's half-width", path);
        }
        if let Some(b) = &e.breaks_at {
            let what = "an elongation at break (reached from rest, at 0)";
            role(b, N, what, format!("{at}.breaks_at"));
        }
    }
    for (k, d) in rig.drives.iter().enumerate() {
        let at = format!("drives[{k}].law");
        match &d.law {
            DriveLaw::VelocityRamp { ramp, .. } => {
                role(ramp, N, "a ramp length", format!("{at}.ramp"))
            }
            DriveLaw::Sine { frequency, .. } => {
                role(frequency, N, "a frequency", format!("{at}.frequency"))
            }
            DriveLaw::Chirp { f_start, .. } => {
                role(f_start, N, "a start frequency", format!("{at}.f_start"))
            }
            DriveLaw::HalfSine { duration, .. } => {
                role(duration, P, "a pulse length", format!("{at}.duration"))
            }
            _ => {}
        }
    }
    out
}

/// Whether parameter `name` is a node's mass in `rig` (in any stage): the
/// compiled rig's own check refuses such a value ≤ 0 as "a mass > 0".
pub fn is_node_mass(rig: &RigDesc, name: &str) -> bool {
    rig.nodes.iter().any(|n| mentions(&n.mass, name))
}

/// Whether coefficient `c` reads parameter `name` (in any stage).
fn mentions(c: &Coef, name: &str) -> bool {
    match c {
        Coef::Number(_) => false,
        Coef::Param(n) => n == name,
        Coef::Switch(s) => mentions(&s.before, name) || mentions(&s.after, name),
    }
}

/// Checks a parsed rig's own values against its parameters' domains: each
/// `default` inside its domain. Returns the JSON path and what was expected.
pub fn check_defaults(rig: &RigDesc) -> Result<(), (String, String, f64)> {
    for (i, p) in rig.params.iter().enumerate() {
        let Some(v) = p.default else { continue };
        let d = of(rig, &p.name);
        if !d.domain.contains(v) {
            return Err((format!("params[{i}].default"), expected(&rig.id, p, &d), v));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rig(extra: &str) -> RigDesc {
        let text = format!(
            r#"{{"id": "r", "params": [
                {{"name": "m", "unit": "kg"}},
                {{"name": "k", "unit": "N/m"}},
                {{"name": "c", "unit": "N·s/m"}},
                {{"name": "a1", "unit": "N/m"}},
                {{"name": "lk", "unit": "N/m", "scale": "log"}},
                {{"name": "e_break", "unit": "m"}},
                {{"name": "x0", "unit": "m"}},
                {{"name": "j", "unit": "kg·m²"}},
                {{"name": "v", "unit": "m/s"}},
                {{"name": "r", "unit": "m"}}
                {extra}
            ],
            "nodes": [{{"name": "n", "mass": "m"}}],
            "elements": [
                {{"name": "s", "between": ["ground", "n"],
                  "spring": {{"law": "linear", "k": "k"}},
                  "damper": {{"law": "viscous", "c": "c"}},
                  "breaks_at": "e_break"}},
                {{"name": "p", "between": ["ground", "n"],
                  "spring": {{"law": "polynomial", "coeffs": ["a1", "lk"]}}}}
            ],
            "drives": [{{"node": "n", "law": {{"type": "velocity_ramp", "velocity": "v", "ramp": "r"}}}}],
            "outputs": [{{"name": "f", "unit": "N", "sum": [{{"force": "s"}}]}}]}}"#
        );
        serde_json::from_str(&text).unwrap()
    }

    #[test]
    fn roles_units_and_scales_derive_the_domain() {
        let r = rig("");
        let d = |n: &str| of(&r, n).domain;
        assert_eq!(d("m"), Domain::Positive);
        assert_eq!(d("k"), Domain::Nonnegative);
        assert_eq!(d("c"), Domain::Nonnegative);
        assert_eq!(
            d("a1"),
            Domain::Any,
            "a polynomial coefficient may be negative"
        );
        assert_eq!(d("lk"), Domain::Positive, "a log-scale parameter");
        assert_eq!(d("e_break"), Domain::Nonnegative);
        assert_eq!(d("x0"), Domain::Any);
        assert_eq!(d("j"), Domain::Positive);
        assert_eq!(d("v"), Domain::Any, "a velocity has a direction");
        assert_eq!(d("r"), Domain::Nonnegative);
        assert!(of(&r, "k").why.contains("elements[0].spring.k"));
        assert!(is_node_mass(&r, "m") && !is_node_mass(&r, "j"));
    }

    #[test]
    fn a_declared_domain_overrides_the_derivation() {
        let r = rig(r#", {"name": "kx", "unit": "N/m", "domain": "any", "scale": "log"}"#);
        assert_eq!(of(&r, "kx").domain, Domain::Any);
        assert_eq!(of(&r, "kx").why, "declared");
        let r = rig(r#", {"name": "g", "unit": "m", "domain": "positive"}"#);
        assert_eq!(of(&r, "g").domain, Domain::Positive);
        assert!(serde_json::from_str::<Domain>(r#""negative""#).is_err());
    }

    #[test]
    fn membership_is_strict_where_it_says() {
        assert!(Domain::Positive.contains(f64::INFINITY));
        assert!(!Domain::Positive.contains(0.0));
        assert!(Domain::Nonnegative.contains(0.0));
        assert!(!Domain::Nonnegative.contains(-1e-300));
        assert!(Domain::Any.contains(-5.0));
    }

    #[test]
    fn a_default_outside_its_domain_is_found() {
        let r = rig(r#", {"name": "cc", "unit": "N·s/m", "default": -1.0}"#);
        // Unused: the unit alone does not bound a damping.
        assert!(check_defaults(&r).is_ok());
        let r = rig(r#", {"name": "mm", "unit": "kg", "default": -1.0}"#);
        let (path, expected, v) = check_defaults(&r).unwrap_err();
        assert_eq!(path, "params[10].default");
        assert!(
            expected.contains("rig 'r' declares mm (kg) positive"),
            "{expected}"
        );
        assert_eq!(v, -1.0);
    }
}
