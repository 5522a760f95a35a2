//! Rig description → [`Program`]s: every element law lowered to the IR, every
//! switch a [`Transition`]. Checks the description on the way and names the
//! JSON path of anything wrong.
//!
//! State layout: node displacements in node order, then node velocities, then
//! the elements' internal states (the stretch of each friction element's
//! tangential spring, the play position of each backlash element) in element
//! order.

use std::collections::HashMap;

use super::ir::{Graph, Id, Input};
use super::program::{Direction, ModeVar, Program, Transition};
use crate::model::PiecewiseLinear;
use crate::rig::RigError;
use crate::rig::desc::{
    BacklashDesc, Coef, DamperLaw, DriveLaw, ElementDesc, FrictionLaw, GapKind, Quantity, RigDesc,
    SpringLaw,
};

/// The whole rig, checked: names, modes, one [`Program`] per drive mode.
#[derive(Debug, Clone)]
pub struct Lowered {
    /// State names (`x_load_cell`, `v_load_cell`, `z_friction`, …).
    pub states: Vec<String>,
    /// Mode variables.
    pub modes: Vec<ModeVar>,
    /// Drive modes, `"velocity"` first.
    pub programs: Vec<Program>,
}

/// Highest polynomial degree a law accepts.
pub const MAX_DEGREE: usize = 5;

/// Rig-wide facts every drive mode shares.
struct Layout<'a> {
    desc: &'a RigDesc,
    file: String,
    params: HashMap<&'a str, u32>,
    nodes: HashMap<&'a str, usize>,
    elements: HashMap<&'a str, usize>,
    /// Mode variable of each element's fracture, contact, yield, friction.
    break_var: Vec<Option<u32>>,
    contact_var: Vec<Option<u32>>,
    yield_var: Vec<Option<u32>>,
    friction_var: Vec<Option<(u32, u32)>>,
    /// Mode variable and play-state slot of each backlash element.
    backlash_var: Vec<Option<(u32, u32)>>,
    /// Mode variable of each drive's pulse (half-sine: before, on, after).
    drive_var: Vec<Option<u32>>,
    modes: Vec<ModeVar>,
    states: Vec<String>,
}

impl<'a> Layout<'a> {
    fn err(
        &self,
        path: impl Into<String>,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> RigError {
        RigError::new(self.file.clone(), path, expected, found)
    }

    fn new(desc: &'a RigDesc, file: String) -> Result<Self, RigError> {
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
            modes: vec![],
            states: vec![],
        };
        let ident = |s: &str| {
            !s.is_empty()
                && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                && !s.starts_with(|c: char| c.is_ascii_digit())
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
                me.modes.push(ModeVar {
                    name: format!("{}.{suffix}", e.name),
                    values,
                });
                Some(me.modes.len() as u32 - 1)
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
        for (i, d) in desc.drives.iter().enumerate() {
            let v = if matches!(d.law, DriveLaw::HalfSine { .. }) {
                me.modes.push(ModeVar {
                    name: format!("drives[{i}].pulse"),
                    values: vec!["before", "on", "after"],
                });
                Some(me.modes.len() as u32 - 1)
            } else {
                None
            };
            me.drive_var.push(v);
        }
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

    /// What a backlash element needs: a spring and a viscous damper (the play
    /// moves with `ṗ = ė + F_s/c`, singular for `c = 0`), no gap and no
    /// friction, a half-width ≥ 0. Literal coefficients are checked here; a
    /// damping parameter is checked per run (`CompiledRig::check`).
    fn check_backlash(
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

    /// Lowers a coefficient at `path`.
    /// An expression law: `src` lowered with `var` (`x` or `v`) bound to its
    /// value and every other name a parameter; errors name the column.
    fn expression(
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
        let at = |e: super::expr::ExprError| {
            self.err(
                path,
                expected.clone(),
                format!("{short:?}, column {}: {}", e.column, e.message),
            )
        };
        let e = super::expr::parse(src).map_err(at)?;
        let params = &self.params;
        e.lower(g, &mut |g, name| {
            if name == var.0 {
                return Ok(var.1);
            }
            match params.get(name) {
                Some(&i) => Ok(g.input(Input::Slot(i))),
                None => {
                    let mut names: Vec<&str> = params.keys().copied().collect();
                    names.push(var.0);
                    names.sort_unstable();
                    let near = names
                        .iter()
                        .min_by_key(|n| strsim::levenshtein(n, name))
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

    fn coef(&self, g: &mut Graph, c: &Coef, path: &str) -> Result<Id, RigError> {
        match c {
            Coef::Number(v) if v.is_finite() => Ok(g.c(*v)),
            Coef::Number(v) => Err(self.err(path, "a finite number", v.to_string())),
            Coef::Param(name) => match self.params.get(name.as_str()) {
                Some(&i) => Ok(g.input(Input::Slot(i))),
                None => {
                    let mut names: Vec<&str> = self.params.keys().copied().collect();
                    names.sort_unstable();
                    let near = names
                        .iter()
                        .copied()
                        .min_by(|a, b| {
                            strsim::levenshtein(a, name).cmp(&strsim::levenshtein(b, name))
                        })
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
                let m = g.input(Input::Mode(var));
                let one = g.c(1.0);
                let broken = g.eq(m, one);
                Ok(g.select(broken, after, before))
            }
        }
    }
}

/// The numbers written into a coefficient (both sides of a switch).
fn literals(c: &Coef) -> Vec<f64> {
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

/// One node's motion in a drive mode: (x, v) ids and how it is moved.
#[derive(Clone, Copy)]
struct Motion {
    x: Id,
    v: Id,
    /// Acceleration where prescribed.
    a: Option<Id>,
}

/// The parameter that holds state `state`'s initial value (`initial_v_mass`).
pub fn initial_param(state: &str) -> String {
    format!("initial_{state}")
}

/// The state names of `desc` (`x_<node>`, `v_<node>`, `s_<friction element>`,
/// `p_<backlash element>`), in state order, with the description checked as far as the layout needs.
pub fn state_names(desc: &RigDesc, file: &str) -> Result<Vec<String>, RigError> {
    Ok(Layout::new(desc, file.to_string())?.states)
}

/// Lowers `desc` (read from `file`) for every drive mode it declares.
pub fn lower(desc: &RigDesc, file: &str) -> Result<Lowered, RigError> {
    let lay = Layout::new(desc, file.to_string())?;
    let mut modes: Vec<String> = vec!["velocity".into()];
    for (i, d) in desc.drives.iter().enumerate() {
        if d.mode != "velocity" && d.mode != "force" {
            return Err(lay.err(
                format!("drives[{i}].mode"),
                "\"velocity\" or \"force\"",
                format!("{:?}", d.mode),
            ));
        }
        if !modes.contains(&d.mode) {
            modes.push(d.mode.clone());
        }
    }
    if desc.outputs.is_empty() {
        return Err(lay.err(
            "outputs",
            "at least one output (output 0 is fitted)",
            "an empty list",
        ));
    }
    let programs = modes
        .iter()
        .map(|m| lower_mode(&lay, m))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Lowered {
        states: lay.states.clone(),
        modes: lay.modes.clone(),
        programs,
    })
}

fn table(lay: &Layout, path: &str, t: &[f64], v: &[f64]) -> Result<PiecewiseLinear, RigError> {
    if t.is_empty() || t.len() != v.len() {
        return Err(lay.err(
            path,
            "\"t\" and \"value\" of the same, non-zero length",
            format!("{} and {}", t.len(), v.len()),
        ));
    }
    if t.iter().chain(v).any(|x| !x.is_finite()) || t.windows(2).any(|w| w[1] <= w[0]) {
        return Err(lay.err(
            format!("{path}.t"),
            "finite, strictly increasing times and finite values",
            "otherwise",
        ));
    }
    Ok(PiecewiseLinear {
        t: t.to_vec(),
        value: v.to_vec(),
    })
}

fn lower_mode(lay: &Layout, mode: &str) -> Result<Program, RigError> {
    let desc = lay.desc;
    let n = desc.nodes.len();
    let mut g = Graph::new();
    let mut tables: Vec<Option<PiecewiseLinear>> = vec![];
    let t = g.input(Input::Time);
    let zero = g.c(0.0);
    let one = g.c(1.0);
    let mut motion: Vec<Motion> = (0..n)
        .map(|k| Motion {
            x: g.input(Input::State(k as u32)),
            v: g.input(Input::State((n + k) as u32)),
            a: None,
        })
        .collect();
    let mut external: Vec<Vec<Id>> = vec![vec![]; n];
    let mut base_accel: Vec<Id> = vec![];
    let mut trans: Vec<Transition> = vec![];

    for (i, d) in desc.drives.iter().enumerate() {
        if d.mode != mode {
            continue;
        }
        let path = format!("drives[{i}]");
        let node = match (&d.node, &d.law) {
            (_, law) if moves_the_base(law) => None,
            (Some(name), _) => match lay.nodes.get(name.as_str()) {
                Some(&k) => Some(k),
                None => {
                    return Err(lay.err(
                        format!("{path}.node"),
                        "a node name",
                        format!("{name:?}"),
                    ));
                }
            },
            (None, _) => {
                return Err(lay.err(format!("{path}.node"), "the node the drive acts on", "none"));
            }
        };
        match &d.law {
            DriveLaw::VelocityRamp { velocity, ramp } => {
                let k = node.expect("checked");
                if motion[k].a.is_some() {
                    return Err(lay.err(
                        format!("{path}.node"),
                        "one prescribed motion per node",
                        "a second one",
                    ));
                }
                let v = lay.coef(&mut g, velocity, &format!("{path}.law.velocity"))?;
                let r = lay.coef(&mut g, ramp, &format!("{path}.law.ramp"))?;
                let rest = g.le(t, zero);
                let no_ramp = g.le(r, zero);
                let vr = g.div(v, r);
                let v_over_r = g.select(no_ramp, zero, vr);
                let e = g.mul(v_over_r, t);
                let e = g.neg(e);
                let m = g.push(super::ir::Op::Expm1(e));
                let vt = g.mul(v, t);
                let rm = g.mul(r, m);
                let ramped_x = g.add(vt, rm);
                let vm = g.mul(v, m);
                let ramped_v = g.neg(vm);
                let vvr = g.mul(v, v_over_r);
                let m1 = g.add(m, one);
                let ramped_a = g.mul(vvr, m1);
                let x = g.select(no_ramp, vt, ramped_x);
                let vel = g.select(no_ramp, v, ramped_v);
                let acc = g.select(no_ramp, zero, ramped_a);
                motion[k] = Motion {
                    x: g.select(rest, zero, x),
                    v: g.select(rest, zero, vel),
                    a: Some(g.select(rest, zero, acc)),
                };
            }
            DriveLaw::ForceTable { t: tt, value, gain } => {
                let k = node.expect("checked");
                let f = table_drive(lay, &mut g, &mut tables, &path, mode, tt, value, gain)?;
                external[k].push(f);
            }
            DriveLaw::BaseAccelerationTable { t: tt, value, gain } => {
                if d.node.is_some() {
                    return Err(lay.err(
                        format!("{path}.node"),
                        "no node (the base moves every node)",
                        "a node",
                    ));
                }
                let a = table_drive(lay, &mut g, &mut tables, &path, mode, tt, value, gain)?;
                base_accel.push(a);
            }
            DriveLaw::Sine { quantity, .. }
            | DriveLaw::Chirp { quantity, .. }
            | DriveLaw::HalfSine { quantity, .. } => {
                if *quantity == Quantity::BaseAcceleration && d.node.is_some() {
                    return Err(lay.err(
                        format!("{path}.node"),
                        "no node (the base moves every node)",
                        "a node",
                    ));
                }
                let (s, ds, dds) = signal(lay, &mut g, &d.law, i, &path, t, &mut trans)?;
                match (quantity, node) {
                    (Quantity::Force, Some(k)) => external[k].push(s),
                    (Quantity::Displacement, Some(k)) => {
                        if motion[k].a.is_some() {
                            return Err(lay.err(
                                format!("{path}.node"),
                                "one prescribed motion per node",
                                "a second one",
                            ));
                        }
                        motion[k] = Motion {
                            x: s,
                            v: ds,
                            a: Some(dds),
                        };
                    }
                    _ => base_accel.push(s),
                }
            }
        }
    }

    // Element forces.
    let mut forces: Vec<Id> = vec![];
    let mut internal: Vec<(u32, Id)> = vec![];
    let ground = Motion {
        x: zero,
        v: zero,
        a: Some(zero),
    };
    for (i, e) in desc.elements.iter().enumerate() {
        let end = |s: &str| {
            if s == "ground" {
                ground
            } else {
                motion[lay.nodes[s]]
            }
        };
        let (a, b) = (end(&e.between[0]), end(&e.between[1]));
        let el = g.sub(b.x, a.x);
        let rate = g.sub(b.v, a.v);
        let f = element_force(lay, &mut g, e, i, el, rate, &mut trans, &mut internal)?;
        forces.push(f);
    }

    // Node accelerations.
    let mut deriv = vec![zero; lay.states.len()];
    let mut accel: Vec<Id> = vec![zero; n];
    for k in 0..n {
        let node = &desc.nodes[k];
        if let Some(a) = motion[k].a {
            accel[k] = a;
            continue;
        }
        let mut sum = zero;
        for (i, e) in desc.elements.iter().enumerate() {
            if e.between[0] == node.name {
                sum = g.add(sum, forces[i]);
            }
            if e.between[1] == node.name {
                sum = g.sub(sum, forces[i]);
            }
        }
        for &f in &external[k] {
            sum = g.add(sum, f);
        }
        let m = lay.coef(&mut g, &node.mass, &format!("nodes[{k}].mass"))?;
        let inv_m = g.div(one, m);
        let mut acc = g.mul(sum, inv_m);
        for &ab in &base_accel {
            acc = g.sub(acc, ab);
        }
        accel[k] = acc;
        deriv[k] = motion[k].v;
        deriv[n + k] = acc;
    }
    for (slot, dz) in internal {
        deriv[slot as usize] = dz;
    }
    let mut full_state: Vec<Id> = (0..lay.states.len())
        .map(|s| g.input(Input::State(s as u32)))
        .collect();
    for k in 0..n {
        full_state[k] = motion[k].x;
        full_state[n + k] = motion[k].v;
    }

    // Outputs.
    let mut outputs = vec![];
    for (o, out) in desc.outputs.iter().enumerate() {
        if out.sum.is_empty() {
            return Err(lay.err(
                format!("outputs[{o}].sum"),
                "at least one term",
                "an empty list",
            ));
        }
        let mut sum = zero;
        for (j, term) in out.sum.iter().enumerate() {
            let path = format!("outputs[{o}].sum[{j}]");
            let picks = [
                term.force.as_ref().map(|s| ("force", s)),
                term.displacement.as_ref().map(|s| ("displacement", s)),
                term.velocity.as_ref().map(|s| ("velocity", s)),
                term.acceleration.as_ref().map(|s| ("acceleration", s)),
            ];
            let picked: Vec<_> = picks.iter().flatten().collect();
            if picked.len() != 1 {
                return Err(lay.err(
                    path,
                    "exactly one of force, displacement, velocity, acceleration",
                    format!("{}", picked.len()),
                ));
            }
            let (what, name) = *picked[0];
            let v = if what == "force" {
                match lay.elements.get(name.as_str()) {
                    Some(&i) => forces[i],
                    None => {
                        return Err(lay.err(
                            format!("{path}.force"),
                            "an element name",
                            format!("{name:?}"),
                        ));
                    }
                }
            } else {
                let Some(&k) = lay.nodes.get(name.as_str()) else {
                    return Err(lay.err(
                        format!("{path}.{what}"),
                        "a node name",
                        format!("{name:?}"),
                    ));
                };
                match what {
                    "displacement" => motion[k].x,
                    "velocity" => motion[k].v,
                    _ => accel[k],
                }
            };
            if !term.gain.is_finite() {
                return Err(lay.err(
                    format!("{path}.gain"),
                    "a finite number",
                    term.gain.to_string(),
                ));
            }
            let gain = g.c(term.gain);
            let v = g.mul(gain, v);
            sum = g.add(sum, v);
        }
        outputs.push(sum);
    }

    // A state starts from the rig's `initial_<state>` parameter where it has
    // one (a campaign's `"initial"` declares it), else at rest.
    let initial = lay
        .states
        .iter()
        .map(|s| match lay.params.get(initial_param(s).as_str()) {
            Some(&i) => g.input(Input::Slot(i)),
            None => zero,
        })
        .collect();
    let mut p = Program {
        mode: mode.to_string(),
        graph: g,
        deriv,
        outputs,
        full_state,
        transitions: trans,
        run_constant: vec![],
        tables,
        initial,
    };
    p.mark_run_constants();
    Ok(p)
}

/// The force of element `i` (tension positive), registering its switches.
#[expect(
    clippy::too_many_arguments,
    reason = "one lowering step, all of it needed"
)]
fn element_force(
    lay: &Layout,
    g: &mut Graph,
    e: &ElementDesc,
    i: usize,
    el: Id,
    rate: Id,
    trans: &mut Vec<Transition>,
    internal: &mut Vec<(u32, Id)>,
) -> Result<Id, RigError> {
    let path = format!("elements[{i}]");
    let zero = g.c(0.0);
    let one = g.c(1.0);
    let mode_is = |g: &mut Graph, var: u32, value: f64| {
        let m = g.input(Input::Mode(var));
        let v = g.c(value);
        g.eq(m, v)
    };
    let push = |trans: &mut Vec<Transition>,
                name: String,
                var: u32,
                from: u32,
                to: u32,
                g: Id,
                dir: Direction| {
        trans.push(Transition {
            name,
            var,
            from,
            to,
            g,
            dir,
        });
    };

    // Contact: the elongation(s) the laws see, and how the force is gated.
    let gap = match &e.gap {
        Some(gd) => {
            let size = lay.coef(g, &gd.size, &format!("{path}.gap.size"))?;
            if let Coef::Number(s) = gd.size
                && s < 0.0
            {
                return Err(lay.err(format!("{path}.gap.size"), "a gap ≥ 0 (m)", s.to_string()));
            }
            let var = lay.contact_var[i].expect("allocated");
            let d_t = g.sub(el, size);
            let d_c = g.add(el, size);
            let n = e.name.clone();
            match gd.kind {
                GapKind::Tension => {
                    push(trans, format!("{n} closes"), var, 0, 1, d_t, Direction::Up);
                    push(trans, format!("{n} opens"), var, 1, 0, d_t, Direction::Down);
                }
                GapKind::Compression => {
                    push(
                        trans,
                        format!("{n} closes"),
                        var,
                        0,
                        1,
                        d_c,
                        Direction::Down,
                    );
                    push(trans, format!("{n} opens"), var, 1, 0, d_c, Direction::Up);
                }
                GapKind::FreePlay => {
                    push(
                        trans,
                        format!("{n} closes in tension"),
                        var,
                        0,
                        1,
                        d_t,
                        Direction::Up,
                    );
                    push(
                        trans,
                        format!("{n} opens from tension"),
                        var,
                        1,
                        0,
                        d_t,
                        Direction::Down,
                    );
                    push(
                        trans,
                        format!("{n} closes in compression"),
                        var,
                        0,
                        2,
                        d_c,
                        Direction::Down,
                    );
                    push(
                        trans,
                        format!("{n} opens from compression"),
                        var,
                        2,
                        0,
                        d_c,
                        Direction::Up,
                    );
                }
            }
            Some((gd.kind, var, d_t, d_c))
        }
        None => None,
    };

    let law_force = |g: &mut Graph, trans: &mut Vec<Transition>, d: Id| -> Result<Id, RigError> {
        let mut f = zero;
        if let Some(s) = &e.spring {
            let sp = format!("{path}.spring");
            let fs = match s {
                SpringLaw::Linear { k } => {
                    let k = lay.coef(g, k, &format!("{sp}.k"))?;
                    g.mul(k, d)
                }
                SpringLaw::Polynomial { coeffs } => poly(lay, g, coeffs, &sp, d)?,
                SpringLaw::LinearThenPolynomial { k, limit, coeffs } => {
                    let k = lay.coef(g, k, &format!("{sp}.k"))?;
                    let lim = lay.coef(g, limit, &format!("{sp}.limit"))?;
                    let pl = poly(lay, g, coeffs, &sp, d)?;
                    let lin = g.mul(k, d);
                    let var = lay.yield_var[i].expect("allocated");
                    let gy = g.sub(d, lim);
                    // Registered once (the gap branches share one yield variable).
                    if !trans.iter().any(|t| t.var == var) {
                        trans.push(Transition {
                            name: format!("{} yields", e.name),
                            var,
                            from: 0,
                            to: 1,
                            g: gy,
                            dir: Direction::Up,
                        });
                        trans.push(Transition {
                            name: format!("{} unloads below the limit", e.name),
                            var,
                            from: 1,
                            to: 0,
                            g: gy,
                            dir: Direction::Down,
                        });
                    }
                    let plastic = mode_is(g, var, 1.0);
                    g.select(plastic, pl, lin)
                }
                SpringLaw::ExpLinear { a, b, c, k } => {
                    let a = lay.coef(g, a, &format!("{sp}.a"))?;
                    let b = lay.coef(g, b, &format!("{sp}.b"))?;
                    let c = lay.coef(g, c, &format!("{sp}.c"))?;
                    let k = lay.coef(g, k, &format!("{sp}.k"))?;
                    // Knee d* = ln((k − c)/a)/b (0 when k ≤ a + c) and G(d*):
                    // per-run constants, computed once on the host.
                    let apc = g.add(a, c);
                    let flat = g.le(k, apc);
                    let kmc = g.sub(k, c);
                    let ratio = g.div(kmc, a);
                    let safe = g.select(flat, one, ratio);
                    let ln = g.push(super::ir::Op::Ln(safe));
                    let knee = g.div(ln, b);
                    let d_star = g.select(flat, zero, knee);
                    let a_over_b = g.div(a, b);
                    let exp_law = |g: &mut Graph, x: Id| {
                        let bx = g.mul(b, x);
                        let em = g.push(super::ir::Op::Expm1(bx));
                        let t1 = g.mul(a_over_b, em);
                        let t2 = g.mul(c, x);
                        g.add(t1, t2)
                    };
                    let g_star = exp_law(g, d_star);
                    let curved = exp_law(g, d);
                    let dd = g.sub(d, d_star);
                    let kd = g.mul(k, dd);
                    let straight = g.add(g_star, kd);
                    let below = g.le(d, d_star);
                    g.select(below, curved, straight)
                }
                SpringLaw::PowerLaw { k, beta } => {
                    let k = lay.coef(g, k, &format!("{sp}.k"))?;
                    let beta = lay.coef(g, beta, &format!("{sp}.beta"))?;
                    let p = g.signed_pow(d, beta);
                    g.mul(k, p)
                }
                SpringLaw::Expression { force } => {
                    lay.expression(g, force, ("x", d), &format!("{sp}.force"))?
                }
            };
            f = g.add(f, fs);
        }
        if let Some(dl) = &e.damper {
            let dp = format!("{path}.damper");
            let fd = match dl {
                DamperLaw::Viscous { c } => {
                    let c = lay.coef(g, c, &format!("{dp}.c"))?;
                    g.mul(c, rate)
                }
                DamperLaw::PowerLaw { c, alpha } => {
                    let c = lay.coef(g, c, &format!("{dp}.c"))?;
                    let al = lay.coef(g, alpha, &format!("{dp}.alpha"))?;
                    let p = g.signed_pow(rate, al);
                    g.mul(c, p)
                }
                DamperLaw::Saturating { c, c_high, v_knee } => {
                    let c = lay.coef(g, c, &format!("{dp}.c"))?;
                    let ch = lay.coef(g, c_high, &format!("{dp}.c_high"))?;
                    let vk = lay.coef(g, v_knee, &format!("{dp}.v_knee"))?;
                    let abs = g.push(super::ir::Op::Abs(rate));
                    let inner = g.le(abs, vk);
                    let lin = g.mul(c, rate);
                    let cv = g.mul(c, vk);
                    let over = g.sub(abs, vk);
                    let ho = g.mul(ch, over);
                    let mag = g.add(cv, ho);
                    let neg = g.le(rate, zero);
                    let m = g.neg(mag);
                    let sat = g.select(neg, m, mag);
                    g.select(inner, lin, sat)
                }
                DamperLaw::Asymmetric {
                    c_tension,
                    c_compression,
                } => {
                    let ct = lay.coef(g, c_tension, &format!("{dp}.c_tension"))?;
                    let cc = lay.coef(g, c_compression, &format!("{dp}.c_compression"))?;
                    let neg = g.le(rate, zero);
                    let c = g.select(neg, cc, ct);
                    g.mul(c, rate)
                }
                DamperLaw::Expression { force } => {
                    lay.expression(g, force, ("v", rate), &format!("{dp}.force"))?
                }
            };
            f = g.add(f, fd);
        }
        Ok(f)
    };

    let mut f = match (gap, &e.backlash) {
        (None, None) => law_force(g, trans, el)?,
        (None, Some(bd)) => {
            // The play position p is the state; the laws see the stretch
            // d = e − q, with q = p in play and the stop ±b in contact, taken
            // from the stored mode (never from the sign of p − b). In play
            // F_s(d) + c·ė is c·ṗ, the rate at which the play moves; in contact
            // it is the element's force.
            let b = lay.coef(g, &bd.half_width, &format!("{path}.backlash.half_width"))?;
            let (var, slot) = lay.backlash_var[i].expect("allocated");
            let Some(DamperLaw::Viscous { c }) = &e.damper else {
                unreachable!("checked in Layout::new")
            };
            let c = lay.coef(g, c, &format!("{path}.damper.c"))?;
            let p = g.input(Input::State(slot));
            let play = mode_is(g, var, 0.0);
            let ten = mode_is(g, var, 1.0);
            let com = mode_is(g, var, 2.0);
            let nb = g.neg(b);
            let stop = g.select(com, nb, p);
            let q = g.select(ten, b, stop);
            let d = g.sub(el, q);
            let lf = law_force(g, trans, d)?;
            let n = &e.name;
            let to_ten = g.sub(p, b);
            let to_com = g.add(p, b);
            push(
                trans,
                format!("{n} takes up its play in tension"),
                var,
                0,
                1,
                to_ten,
                Direction::Up,
            );
            push(
                trans,
                format!("{n} takes up its play in compression"),
                var,
                0,
                2,
                to_com,
                Direction::Down,
            );
            push(
                trans,
                format!("{n} leaves tension contact"),
                var,
                1,
                0,
                lf,
                Direction::Down,
            );
            push(
                trans,
                format!("{n} leaves compression contact"),
                var,
                2,
                0,
                lf,
                Direction::Up,
            );
            let rate_p = g.div(lf, c);
            let dp = g.select(play, rate_p, zero);
            internal.push((slot, dp));
            g.select(play, zero, lf)
        }
        (Some(_), Some(_)) => unreachable!("refused in Layout::new"),
        (Some((GapKind::Tension, var, d_t, _)), None) => {
            let closed = mode_is(g, var, 1.0);
            let lf = law_force(g, trans, d_t)?;
            g.select(closed, lf, zero)
        }
        (Some((GapKind::Compression, var, _, d_c)), None) => {
            let closed = mode_is(g, var, 1.0);
            let lf = law_force(g, trans, d_c)?;
            g.select(closed, lf, zero)
        }
        (Some((GapKind::FreePlay, var, d_t, d_c)), None) => {
            let ten = mode_is(g, var, 1.0);
            let com = mode_is(g, var, 2.0);
            let ft = law_force(g, trans, d_t)?;
            let fc = law_force(g, trans, d_c)?;
            let inner = g.select(com, fc, zero);
            g.select(ten, ft, inner)
        }
    };

    if let Some(FrictionLaw::StickSlip { f_c, k_t }) = &e.friction {
        let fp = format!("{path}.friction");
        let fc = lay.coef(g, f_c, &format!("{fp}.f_c"))?;
        let kt = lay.coef(g, k_t, &format!("{fp}.k_t"))?;
        let (var, slot) = lay.friction_var[i].expect("allocated");
        // The state is the tangential spring's stretch s = e − z (z the slider's
        // position), not z: while the element slips, s stands still, so the
        // spring force stays at ±f_c to the last bit in f32 as in f64 (a slider
        // position integrated beside the elongation drifts from it by rounding).
        let stretch = g.input(Input::State(slot));
        let ff = g.mul(kt, stretch);
        let over = g.sub(ff, fc);
        let under = g.add(ff, fc);
        let n = &e.name;
        push(
            trans,
            format!("{n} slips forward"),
            var,
            0,
            1,
            over,
            Direction::Up,
        );
        push(
            trans,
            format!("{n} slips backward"),
            var,
            0,
            2,
            under,
            Direction::Down,
        );
        push(
            trans,
            format!("{n} sticks after slipping forward"),
            var,
            1,
            0,
            rate,
            Direction::Down,
        );
        push(
            trans,
            format!("{n} sticks after slipping backward"),
            var,
            2,
            0,
            rate,
            Direction::Up,
        );
        // Stuck, the spring takes the whole elongation rate; slipping, the
        // slider follows the elongation and the stretch stands still.
        let stuck = mode_is(g, var, 0.0);
        let ds = g.select(stuck, rate, zero);
        internal.push((slot, ds));
        f = g.add(f, ff);
    }

    if let Some(lim) = &e.breaks_at {
        let lim = lay.coef(g, lim, &format!("{path}.breaks_at"))?;
        let var = lay.break_var[i].expect("allocated");
        let gb = g.sub(el, lim);
        push(
            trans,
            format!("{} breaks", e.name),
            var,
            0,
            1,
            gb,
            Direction::Up,
        );
        let broken = mode_is(g, var, 1.0);
        f = g.select(broken, zero, f);
    }
    Ok(f)
}

fn poly(lay: &Layout, g: &mut Graph, coeffs: &[Coef], sp: &str, d: Id) -> Result<Id, RigError> {
    if coeffs.is_empty() || coeffs.len() > MAX_DEGREE + 1 {
        return Err(lay.err(
            format!("{sp}.coeffs"),
            format!(
                "1 to {} coefficients (degree ≤ {MAX_DEGREE})",
                MAX_DEGREE + 1
            ),
            coeffs.len().to_string(),
        ));
    }
    let cs = coeffs
        .iter()
        .enumerate()
        .map(|(j, c)| lay.coef(g, c, &format!("{sp}.coeffs[{j}]")))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(g.poly(d, &cs))
}

/// A table drive's signal `gain·table(t)`: its own table (`t`, `value`), or
/// in a `"force"`-mode program without them the experiment's table (pushed to
/// `tables` as `None`).
#[allow(clippy::too_many_arguments)]
fn table_drive(
    lay: &Layout,
    g: &mut Graph,
    tables: &mut Vec<Option<PiecewiseLinear>>,
    path: &str,
    mode: &str,
    tt: &Option<Vec<f64>>,
    value: &Option<Vec<f64>>,
    gain: &Option<Coef>,
) -> Result<Id, RigError> {
    let tab = match (tt, value) {
        (Some(tt), Some(vv)) => Some(table(lay, &format!("{path}.law"), tt, vv)?),
        (None, None) if mode == "force" => None,
        (None, None) => {
            return Err(lay.err(
                format!("{path}.law"),
                "\"t\" and \"value\" (only a \"force\"-mode drive reads the experiment's table)",
                "neither",
            ));
        }
        _ => {
            return Err(lay.err(
                format!("{path}.law"),
                "both \"t\" and \"value\"",
                "one of them",
            ));
        }
    };
    tables.push(tab);
    let mut f = g.input(Input::Table(tables.len() as u32 - 1));
    if let Some(gain) = gain {
        let gain = lay.coef(g, gain, &format!("{path}.law.gain"))?;
        f = g.mul(gain, f);
    }
    Ok(f)
}

/// Whether a drive law moves the base (and so names no node).
fn moves_the_base(law: &DriveLaw) -> bool {
    match law {
        DriveLaw::BaseAccelerationTable { .. } => true,
        DriveLaw::Sine { quantity, .. }
        | DriveLaw::Chirp { quantity, .. }
        | DriveLaw::HalfSine { quantity, .. } => *quantity == Quantity::BaseAcceleration,
        _ => false,
    }
}

/// A sine, chirp or half-sine drive's signal and its first two time
/// derivatives `(s, ṡ, s̈)`, from `Sin`/`Cos` of the phase; 0 where the drive is
/// off. A half-sine's start and end are located transitions of its own mode
/// variable, so the kinks in `ṡ` fall on step boundaries.
fn signal(
    lay: &Layout,
    g: &mut Graph,
    law: &DriveLaw,
    i: usize,
    path: &str,
    t: Id,
    trans: &mut Vec<Transition>,
) -> Result<(Id, Id, Id), RigError> {
    use super::ir::Op;
    let lp = format!("{path}.law");
    let zero = g.c(0.0);
    let two_pi = g.c(std::f64::consts::TAU);
    // (phase φ, φ̇, φ̈, amplitude, gate: 1 where the drive is on)
    let (phi, dphi, ddphi, amp, on) = match law {
        DriveLaw::Sine {
            amplitude,
            frequency,
            phase,
            ..
        } => {
            let a = lay.coef(g, amplitude, &format!("{lp}.amplitude"))?;
            let f = lay.coef(g, frequency, &format!("{lp}.frequency"))?;
            let p = match phase {
                Some(p) => lay.coef(g, p, &format!("{lp}.phase"))?,
                None => zero,
            };
            let w = g.mul(two_pi, f);
            let wt = g.mul(w, t);
            let phi = g.add(wt, p);
            let before = g.le(t, zero);
            let one = g.c(1.0);
            let on = g.select(before, zero, one);
            (phi, w, zero, a, on)
        }
        DriveLaw::Chirp {
            amplitude,
            f_start,
            rate,
            ..
        } => {
            let a = lay.coef(g, amplitude, &format!("{lp}.amplitude"))?;
            let f0 = lay.coef(g, f_start, &format!("{lp}.f_start"))?;
            let r = lay.coef(g, rate, &format!("{lp}.rate"))?;
            // φ = 2π(f0·t + r·t²/2), φ̇ = 2π(f0 + r·t), φ̈ = 2π·r.
            let half = g.c(0.5);
            let rt = g.mul(r, t);
            let hrt = g.mul(half, rt);
            let inner = g.add(f0, hrt);
            let cyc = g.mul(inner, t);
            let phi = g.mul(two_pi, cyc);
            let f_now = g.add(f0, rt);
            let dphi = g.mul(two_pi, f_now);
            let ddphi = g.mul(two_pi, r);
            let before = g.le(t, zero);
            let one = g.c(1.0);
            let on = g.select(before, zero, one);
            (phi, dphi, ddphi, a, on)
        }
        DriveLaw::HalfSine {
            amplitude,
            duration,
            start,
            ..
        } => {
            let a = lay.coef(g, amplitude, &format!("{lp}.amplitude"))?;
            if let Coef::Number(d) = duration
                && d.is_finite()
                && *d <= 0.0
            {
                return Err(lay.err(
                    format!("{lp}.duration"),
                    "a pulse length > 0 (s)",
                    d.to_string(),
                ));
            }
            let tau = lay.coef(g, duration, &format!("{lp}.duration"))?;
            let t0 = match start {
                Some(s) => lay.coef(g, s, &format!("{lp}.start"))?,
                None => zero,
            };
            let var = lay.drive_var[i].expect("allocated");
            let since = g.sub(t, t0);
            let left = g.sub(since, tau);
            trans.push(Transition {
                name: format!("{path} pulse starts"),
                var,
                from: 0,
                to: 1,
                g: since,
                dir: Direction::Up,
            });
            trans.push(Transition {
                name: format!("{path} pulse ends"),
                var,
                from: 1,
                to: 2,
                g: left,
                dir: Direction::Up,
            });
            let pi = g.c(std::f64::consts::PI);
            let w = g.div(pi, tau);
            let phi = g.mul(w, since);
            let m = g.input(Input::Mode(var));
            let one = g.c(1.0);
            let on = g.eq(m, one);
            (phi, w, zero, a, on)
        }
        _ => unreachable!("only signal drives"),
    };
    let sin = g.push(Op::Sin(phi));
    let cos = g.push(Op::Cos(phi));
    // s = A·sin φ, ṡ = A·cos φ·φ̇, s̈ = A·(cos φ·φ̈ − sin φ·φ̇²).
    let s = g.mul(amp, sin);
    let c1 = g.mul(cos, dphi);
    let ds = g.mul(amp, c1);
    let d2 = g.mul(dphi, dphi);
    let sd2 = g.mul(sin, d2);
    let cdd = g.mul(cos, ddphi);
    let acc = g.sub(cdd, sd2);
    let dds = g.mul(amp, acc);
    Ok((
        g.select(on, s, zero),
        g.select(on, ds, zero),
        g.select(on, dds, zero),
    ))
}
