//! The rig-wide layout every drive mode shares: names, the state and mode
//! variables each element owns, the checks of each element's description,
//! and coefficients lowered to the graph.

use std::collections::HashMap;

use super::names::{UNIT_EXPECTED, ident, nearest, unit_text};
use super::reach::{law_reach, literals, not_finite_found, reach_points};
use crate::compile::ir::{Graph, Id, Input};
use crate::compile::program::RegimeVar;
use crate::rig::RigError;
use crate::rig::desc::{
    BacklashDesc, Coef, DamperLaw, DriveLaw, ElementDesc, Frame, GapKind, RigDesc, SpringLaw,
};

/// State names of the base's velocity and displacement (see
/// `Layout::base_states`); no node's or element's state name starts
/// with `base_`.
pub const BASE_VELOCITY: &str = "base_velocity";
pub const BASE_DISPLACEMENT: &str = "base_displacement";

/// Rig-wide facts every drive mode shares.
pub(super) struct Layout<'a> {
    pub(super) desc: &'a RigDesc,
    pub(super) file: String,
    pub(super) params: HashMap<&'a str, u32>,
    pub(super) nodes: HashMap<&'a str, usize>,
    pub(super) elements: HashMap<&'a str, usize>,
    /// Regime variable of each element's fracture, contact, yield, friction.
    pub(super) break_var: Vec<Option<u32>>,
    pub(super) contact_var: Vec<Option<u32>>,
    pub(super) yield_var: Vec<Option<u32>>,
    pub(super) friction_var: Vec<Option<(u32, u32)>>,
    /// Regime variable and play-state slot of each backlash element.
    pub(super) backlash_var: Vec<Option<(u32, u32)>>,
    /// Regime variable of each drive's pulse (half-sine: before, on, after).
    pub(super) drive_var: Vec<Option<u32>>,
    pub(super) regimes: Vec<RegimeVar>,
    pub(super) states: Vec<String>,
    /// Slots of the base's velocity and displacement, integrated from its
    /// acceleration where an output reads a node's absolute velocity or
    /// displacement under base acceleration.
    pub(super) base_states: Option<(u32, u32)>,
}

impl<'a> Layout<'a> {
    pub(super) fn err(
        &self,
        path: impl Into<String>,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> RigError {
        RigError::new(self.file.clone(), path, expected, found)
    }

    pub(super) fn new(desc: &'a RigDesc, file: String) -> Result<Self, RigError> {
        let mut me = Layout {
            desc,
            file,
            params: HashMap::new(),
            nodes: HashMap::new(),
            elements: HashMap::new(),
            break_var: vec![],
            contact_var: vec![],
            yield_var: vec![],
            friction_var: vec![],
            backlash_var: vec![],
            drive_var: vec![],
            regimes: vec![],
            states: vec![],
            base_states: None,
        };
        if !ident(&desc.id) {
            return Err(me.err(
                "id",
                "an identifier (letters, digits, '_')",
                format!("{:?}", desc.id),
            ));
        }
        for (i, p) in desc.params.iter().enumerate() {
            let path = format!("params[{i}].name");
            if !ident(&p.name) {
                return Err(me.err(
                    path,
                    "an identifier (letters, digits, '_')",
                    format!("{:?}", p.name),
                ));
            }
            if me.params.insert(&p.name, i as u32).is_some() {
                return Err(me.err(
                    path,
                    "a unique parameter name",
                    format!("{:?} a second time", p.name),
                ));
            }
            if let Some(d) = p.default
                && !d.is_finite()
            {
                return Err(me.err(
                    format!("params[{i}].default"),
                    "a finite number",
                    d.to_string(),
                ));
            }
        }
        if desc.nodes.is_empty() {
            return Err(me.err("nodes", "at least one node", "an empty list"));
        }
        for (i, n) in desc.nodes.iter().enumerate() {
            let path = format!("nodes[{i}].name");
            if !ident(&n.name) || n.name == "ground" {
                return Err(me.err(
                    path,
                    "an identifier other than \"ground\"",
                    format!("{:?}", n.name),
                ));
            }
            if me.nodes.insert(&n.name, i).is_some() {
                return Err(me.err(
                    path,
                    "a unique node name",
                    format!("{:?} a second time", n.name),
                ));
            }
            if let Coef::Number(m) = n.mass
                && !(m > 0.0 && m.is_finite())
            {
                return Err(me.err(format!("nodes[{i}].mass"), "a mass > 0 (kg)", m.to_string()));
            }
        }
        let n = desc.nodes.len();
        me.states = desc.nodes.iter().map(|x| format!("x_{}", x.name)).collect();
        me.states
            .extend(desc.nodes.iter().map(|x| format!("v_{}", x.name)));
        if desc.elements.is_empty() {
            return Err(me.err("elements", "at least one element", "an empty list"));
        }
        let mut touched = vec![false; n];
        for (i, e) in desc.elements.iter().enumerate() {
            let path = format!("elements[{i}]");
            if !ident(&e.name) {
                return Err(me.err(
                    format!("{path}.name"),
                    "an identifier",
                    format!("{:?}", e.name),
                ));
            }
            if me.elements.insert(&e.name, i).is_some() {
                return Err(me.err(
                    format!("{path}.name"),
                    "a unique element name",
                    format!("{:?} a second time", e.name),
                ));
            }
            for (s, end) in e.between.iter().enumerate() {
                if end != "ground" {
                    let Some(&k) = me.nodes.get(end.as_str()) else {
                        return Err(me.err(
                            format!("{path}.between[{s}]"),
                            "a node name or \"ground\"",
                            format!("{end:?}"),
                        ));
                    };
                    touched[k] = true;
                }
            }
            if e.between[0] == e.between[1] {
                return Err(me.err(
                    format!("{path}.between"),
                    "two different ends",
                    format!("{:?} twice", e.between[0]),
                ));
            }
            if e.spring.is_none() && e.damper.is_none() && e.friction.is_none() {
                return Err(me.err(path, "a \"spring\", \"damper\" or \"friction\" law", "none"));
            }
            if e.gap.is_some() && e.spring.is_none() && e.friction.is_none() {
                return Err(me.err(
                    format!("{path}.gap"),
                    "a gap on an element with a spring (a damper alone behind a gap has no contact force to close on)",
                    "a gap on a damper",
                ));
            }
            if e.gap.is_some() && e.friction.is_some() {
                return Err(me.err(
                    format!("{path}.gap"),
                    "no gap on a friction element",
                    "both",
                ));
            }
            let var = |me: &mut Self, suffix: &str, values: Vec<&'static str>| {
                me.regimes.push(RegimeVar {
                    name: format!("{}.{suffix}", e.name),
                    values,
                });
                Some(me.regimes.len() as u32 - 1)
            };
            let b = if e.breaks_at.is_some() {
                var(&mut me, "fracture", vec!["intact", "broken"])
            } else {
                None
            };
            me.break_var.push(b);
            let c = match e.gap.as_ref().map(|g| g.kind) {
                Some(GapKind::FreePlay) => {
                    var(&mut me, "contact", vec!["open", "tension", "compression"])
                }
                Some(_) => var(&mut me, "contact", vec!["open", "closed"]),
                None => None,
            };
            me.contact_var.push(c);
            let y = if matches!(e.spring, Some(SpringLaw::LinearThenPolynomial { .. })) {
                var(&mut me, "yield", vec!["elastic", "plastic"])
            } else {
                None
            };
            me.yield_var.push(y);
            let f = if e.friction.is_some() {
                let v = var(
                    &mut me,
                    "friction",
                    vec!["stuck", "slip_forward", "slip_backward"],
                )
                .unwrap();
                me.states.push(format!("s_{}", e.name));
                Some((v, me.states.len() as u32 - 1))
            } else {
                None
            };
            me.friction_var.push(f);
            let p = if let Some(bd) = &e.backlash {
                me.check_backlash(e, bd, &path)?;
                let v = var(&mut me, "backlash", vec!["play", "tension", "compression"]).unwrap();
                me.states.push(format!("p_{}", e.name));
                Some((v, me.states.len() as u32 - 1))
            } else {
                None
            };
            me.backlash_var.push(p);
        }
        let base_moves = desc
            .drives
            .iter()
            .any(|d| super::drive::moves_the_base(&d.law));
        let absolute_motion = desc.outputs.iter().flat_map(|o| &o.sum).any(|t| {
            t.frame == Some(Frame::Absolute) && (t.displacement.is_some() || t.velocity.is_some())
        });
        if base_moves && absolute_motion {
            me.states.push(BASE_VELOCITY.into());
            me.states.push(BASE_DISPLACEMENT.into());
            let v = me.states.len() as u32 - 2;
            me.base_states = Some((v, v + 1));
        }
        for (i, d) in desc.drives.iter().enumerate() {
            let v = if matches!(d.law, DriveLaw::HalfSine { .. }) {
                me.regimes.push(RegimeVar {
                    name: format!("drives[{i}].pulse"),
                    values: vec!["before", "on", "after"],
                });
                Some(me.regimes.len() as u32 - 1)
            } else {
                None
            };
            me.drive_var.push(v);
        }
        me.check_outputs_and_reach()?;
        for (k, t) in touched.iter().enumerate() {
            if !t {
                return Err(me.err(
                    format!("nodes[{k}]"),
                    "a node joined to the network by at least one element",
                    format!("{:?} touches no element", desc.nodes[k].name),
                ));
            }
        }
        Ok(me)
    }

    /// Output names are identifiers, unique; units (outputs' and
    /// parameters') are short and of a plain unit charset: both reach CSV
    /// headers and summaries as they are written. A reach is finite and > 0.
    fn check_outputs_and_reach(&self) -> Result<(), RigError> {
        let desc = self.desc;
        for (i, p) in desc.params.iter().enumerate() {
            if !unit_text(&p.unit) {
                return Err(self.err(
                    format!("params[{i}].unit"),
                    UNIT_EXPECTED,
                    crate::base::text::echo(&p.unit),
                ));
            }
        }
        let mut seen: HashMap<&str, usize> = HashMap::new();
        for (o, out) in desc.outputs.iter().enumerate() {
            if !ident(&out.name) {
                return Err(self.err(
                    format!("outputs[{o}].name"),
                    "an identifier (letters, digits, '_'; not starting with a digit)",
                    crate::base::text::echo(&out.name),
                ));
            }
            if let Some(first) = seen.insert(&out.name, o) {
                return Err(self.err(
                    format!("outputs[{o}].name"),
                    "a unique output name",
                    format!("{:?}, already the name of outputs[{first}]", out.name),
                ));
            }
            if !unit_text(&out.unit) {
                return Err(self.err(
                    format!("outputs[{o}].unit"),
                    UNIT_EXPECTED,
                    crate::base::text::echo(&out.unit),
                ));
            }
        }
        self.check_frames()?;
        if let Some(r) = desc.reach {
            for (what, v, unit) in [("elongation", r.elongation, "m"), ("rate", r.rate, "m/s")] {
                if !(v.is_finite() && v > 0.0) {
                    return Err(self.err(
                        format!("reach.{what}"),
                        format!("a finite number > 0 ({unit})"),
                        v.to_string(),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Every node-motion term of a rig whose base moves says its frame
    /// (absolute: what an accelerometer on the node reads; relative: what a
    /// sensor between base and node reads); no other term has one.
    fn check_frames(&self) -> Result<(), RigError> {
        let desc = self.desc;
        let base = desc
            .drives
            .iter()
            .position(|d| super::drive::moves_the_base(&d.law));
        for (o, out) in desc.outputs.iter().enumerate() {
            for (j, t) in out.sum.iter().enumerate() {
                let motion = [
                    (t.displacement.is_some(), "displacement"),
                    (t.velocity.is_some(), "velocity"),
                    (t.acceleration.is_some(), "acceleration"),
                ];
                let other = [
                    (t.force.is_some(), "force"),
                    (t.controller.is_some(), "controller"),
                ];
                let picked: Vec<&str> = motion
                    .iter()
                    .chain(&other)
                    .filter(|(on, _)| *on)
                    .map(|(_, w)| *w)
                    .collect();
                let path = format!("outputs[{o}].sum[{j}].frame");
                match (picked.as_slice(), t.frame) {
                    // Several quantities: the lowering names that.
                    ([_, _, ..], _) => {}
                    ([], Some(_)) => {
                        return Err(self.err(
                            path,
                            "no frame on a constant term (a frame belongs to a displacement, velocity or acceleration term)",
                            "a frame",
                        ));
                    }
                    ([w @ ("force" | "controller")], Some(_)) => {
                        return Err(self.err(
                            path,
                            "no frame on a force or controller term (a frame belongs to a displacement, velocity or acceleration term)",
                            format!("a frame on a {w} term"),
                        ));
                    }
                    ([w], None) if *w != "force" && *w != "controller" => {
                        if let Some(d) = base {
                            return Err(self.err(
                                path,
                                format!(
                                    "\"absolute\" (what an accelerometer or vibrometer on the node reads) or \"relative\" (to the moving base: what a sensor between the base and the node reads), for a term reading a node's {w} in a rig whose base moves (drives[{d}] accelerates it)"
                                ),
                                "no frame",
                            ));
                        }
                    }
                    _ => {}
                }
            }
        }
        Ok(())
    }

    /// What a backlash element needs: a spring and a viscous damper (the play
    /// moves with `ṗ = ė + F_s/c`, singular for `c = 0`), no gap and no
    /// friction, a half-width ≥ 0. Literal coefficients are checked here; a
    /// damping parameter is checked per run (`CompiledRig::check`).
    pub(super) fn check_backlash(
        &self,
        e: &ElementDesc,
        bd: &BacklashDesc,
        path: &str,
    ) -> Result<(), RigError> {
        let at = format!("{path}.backlash");
        if e.gap.is_some() {
            return Err(self.err(
                at,
                "no gap on a backlash element (the play is its gap)",
                "both",
            ));
        }
        if e.friction.is_some() {
            return Err(self.err(at, "no friction on a backlash element", "both"));
        }
        if e.spring.is_none() || e.damper.is_none() {
            let found = if e.spring.is_none() {
                "no spring"
            } else {
                "no damper"
            };
            return Err(self.err(
                at,
                "a backlash element with both a spring and a viscous damper",
                found,
            ));
        }
        let Some(DamperLaw::Viscous { c }) = &e.damper else {
            return Err(self.err(
                format!("{path}.damper"),
                "a viscous damper on a backlash element (the play's motion divides by c)",
                "another damper law",
            ));
        };
        if let Some(v) = literals(c).into_iter().find(|v| *v <= 0.0) {
            return Err(self.err(
                format!("{path}.damper.c"),
                "a damping > 0 (N·s/m) on a backlash element (the play's motion divides by c)",
                v.to_string(),
            ));
        }
        if let Some(v) = literals(&bd.half_width).into_iter().find(|v| *v < 0.0) {
            return Err(self.err(
                format!("{at}.half_width"),
                "a half-width ≥ 0 (m)",
                v.to_string(),
            ));
        }
        Ok(())
    }

    /// How a law's parse or lowering error at `path` reads: the law (its
    /// first 60 characters), the column and what is wrong there.
    pub(super) fn law_error<'s>(
        &'s self,
        path: &'s str,
        expected: &'s str,
        src: &str,
    ) -> impl Fn(crate::compile::front::expr::ExprError) -> RigError + 's {
        let short: String = src.chars().take(60).collect();
        move |e| {
            self.err(
                path,
                expected,
                format!("{short:?}, column {}: {}", e.column, e.message),
            )
        }
    }

    /// Lowers a coefficient at `path`.
    /// An expression law: `src` lowered with `var` (`x` or `v`) bound to its
    /// value and every other name a parameter; errors name the column.
    pub(super) fn expression(
        &self,
        g: &mut Graph,
        src: &str,
        var: (&str, Id),
        path: &str,
    ) -> Result<Id, RigError> {
        let expected = format!(
            "a formula of {} and the rig's parameters (+ - * / ^, abs, sign, exp, ln, sqrt, sin, cos, tanh, min, max, spow)",
            var.0
        );
        let short: String = src.chars().take(60).collect();
        let at = self.law_error(path, &expected, src);
        let e = crate::compile::front::expr::parse(src).map_err(&at)?;
        let (reach, unit) = if var.0 == "x" {
            (law_reach(self.desc, None).0, "m")
        } else {
            (law_reach(self.desc, None).1, "m/s")
        };
        if let Some(nf) = e.fixed_part_not_finite(var.0, &reach_points(reach)) {
            return Err(self.err(
                path,
                format!(
                    "a law finite for every {} in [-{reach:e}, {reach:e}] {unit} (the rig's reach)",
                    var.0
                ),
                not_finite_found(&short, &nf, var.0),
            ));
        }
        let params = &self.params;
        e.lower(g, &mut |g, name| {
            if name == var.0 {
                return Ok(var.1);
            }
            match params.get(name) {
                Some(&i) => Ok(g.input(Input::Slot(i))),
                None => {
                    let names = params.keys().copied().chain([var.0]);
                    let near = nearest(names, name)
                        .map(|n| format!(" (did you mean '{n}'?)"))
                        .unwrap_or_default();
                    Err(format!(
                        "unknown name '{name}': not '{}' nor a parameter declared in \"params\"{near}",
                        var.0
                    ))
                }
            }
        })
        .map_err(at)
    }

    pub(super) fn coef(&self, g: &mut Graph, c: &Coef, path: &str) -> Result<Id, RigError> {
        match c {
            Coef::Number(v) if v.is_finite() => Ok(g.c(*v)),
            Coef::Number(v) => Err(self.err(path, "a finite number", v.to_string())),
            Coef::Param(name) => match self.params.get(name.as_str()) {
                Some(&i) => Ok(g.input(Input::Slot(i))),
                None => {
                    let near = nearest(self.params.keys().copied(), name)
                        .map(|n| format!(" (did you mean {n:?}?)"))
                        .unwrap_or_default();
                    Err(self.err(
                        path,
                        "a parameter declared in \"params\"",
                        format!("{name:?}{near}"),
                    ))
                }
            },
            Coef::Switch(s) => {
                let Some(&el) = self.elements.get(s.broken.as_str()) else {
                    return Err(self.err(
                        format!("{path}.broken"),
                        "an element name",
                        format!("{:?}", s.broken),
                    ));
                };
                let Some(var) = self.break_var[el] else {
                    return Err(self.err(
                        format!("{path}.broken"),
                        "an element with \"breaks_at\"",
                        format!("{:?}, which never breaks", s.broken),
                    ));
                };
                let before = self.coef(g, &s.before, &format!("{path}.before"))?;
                let after = self.coef(g, &s.after, &format!("{path}.after"))?;
                let m = g.input(Input::Regime(var));
                let one = g.c(1.0);
                let broken = g.eq(m, one);
                Ok(g.select(broken, after, before))
            }
        }
    }
}
