//! Rig description → [`Program`]s: every element law lowered to the IR, every
//! switch a [`Transition`]. Checks the description on the way and names the
//! JSON path of anything wrong.
//!
//! State layout: node displacements in node order, then node velocities, then
//! the elements' internal states (the stretch of each friction element's
//! tangential spring, the play position of each backlash element) in element
//! order, then, where an output reads a node's absolute velocity or
//! displacement under base acceleration, the base's velocity and displacement
//! (`base_velocity`, `base_displacement`: integrated from the base's
//! acceleration, from rest unless a campaign's `"initial"` gives them).
//!
//! Under base acceleration the node states are relative to the base; an
//! output term's `"frame": "absolute"` adds the base's own motion back.

mod controller;
mod drive;
mod element;
pub mod expr;
pub mod finite;
mod layout;
mod names;
mod reach;

use super::program::{Program, RegimeVar, Transition};
use crate::base::PiecewiseLinear;
use crate::compile::ir::{Graph, Id, Input};
use crate::rig::RigError;
use crate::rig::desc::{DriveLaw, Frame, Quantity, RigDesc};
use drive::{moves_the_base, signal, table_drive};
use element::element_force;
use layout::Layout;
pub use layout::{BASE_DISPLACEMENT, BASE_VELOCITY};

/// The whole rig, checked: names, regimes, one [`Program`] per drive mode.
#[derive(Debug, Clone)]
pub struct Lowered {
    /// State names (`x_load_cell`, `v_load_cell`, `z_friction`, …).
    pub states: Vec<String>,
    /// Regime variables.
    pub regimes: Vec<RegimeVar>,
    /// Drive modes, `"velocity"` first.
    pub programs: Vec<Program>,
}

/// Highest polynomial degree a law accepts.
pub const MAX_DEGREE: usize = 5;

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
    let mut drive_modes: Vec<String> = vec!["velocity".into()];
    for (i, d) in desc.drives.iter().enumerate() {
        if d.mode != "velocity" && d.mode != "force" {
            return Err(lay.err(
                format!("drives[{i}].mode"),
                "\"velocity\" or \"force\"",
                format!("{:?}", d.mode),
            ));
        }
        if !drive_modes.contains(&d.mode) {
            drive_modes.push(d.mode.clone());
        }
    }
    for c in &desc.controllers {
        if c.mode == "force" && !drive_modes.contains(&c.mode) {
            drive_modes.push(c.mode.clone());
        }
    }
    if desc.outputs.is_empty() {
        return Err(lay.err(
            "outputs",
            "at least one output (output 0 is fitted)",
            "an empty list",
        ));
    }
    let programs = drive_modes
        .iter()
        .map(|m| lower_mode(&lay, m))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Lowered {
        states: lay.states.clone(),
        regimes: lay.regimes.clone(),
        programs,
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
                let m = g.push(crate::compile::ir::Op::Expm1(e));
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
            DriveLaw::ForceTable(table) => {
                let k = node.expect("checked");
                let f = table_drive(lay, &mut g, &mut tables, &path, mode, table)?;
                external[k].push(f);
            }
            DriveLaw::BaseAccelerationTable(table) => {
                if d.node.is_some() {
                    return Err(lay.err(
                        format!("{path}.node"),
                        "no node (the base moves every node)",
                        "a node",
                    ));
                }
                let a = table_drive(lay, &mut g, &mut tables, &path, mode, table)?;
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

    let controllers = controller::Controllers::of_mode(lay, mode)?;
    for (k, f) in controllers.forces(lay, &mut g)? {
        external[k].push(f);
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
    // The base's own acceleration, what an absolute reading adds back to the
    // states' motion relative to the base (0 in a mode that does not move it).
    // Built only where read, so a rig without absolute terms lowers as before.
    let reads_base = desc
        .outputs
        .iter()
        .flat_map(|o| &o.sum)
        .any(|t| t.frame == Some(Frame::Absolute));
    let mut base_a = zero;
    if reads_base {
        for &ab in &base_accel {
            base_a = g.add(base_a, ab);
        }
    }
    let base_vx = lay.base_states.map(|(v, x)| {
        deriv[v as usize] = base_a;
        let bv = g.input(Input::State(v));
        deriv[x as usize] = bv;
        (bv, g.input(Input::State(x)))
    });
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
                term.controller.as_ref().map(|s| ("controller", s)),
                term.force.as_ref().map(|s| ("force", s)),
                term.displacement.as_ref().map(|s| ("displacement", s)),
                term.velocity.as_ref().map(|s| ("velocity", s)),
                term.acceleration.as_ref().map(|s| ("acceleration", s)),
            ];
            let picked: Vec<_> = picks.iter().flatten().collect();
            let gain = lay.coef(&mut g, &term.gain, &format!("{path}.gain"))?;
            let (what, name) = match picked.as_slice() {
                // No quantity: the constant `gain` (a sensor's zero offset).
                [] => {
                    sum = g.add(sum, gain);
                    continue;
                }
                [one] => **one,
                many => {
                    return Err(lay.err(
                        path,
                        "at most one of controller, force, displacement, velocity, acceleration",
                        format!("{}", many.len()),
                    ));
                }
            };
            let v = if what == "controller" {
                if !desc.controllers.iter().any(|c| &c.name == name) {
                    return Err(lay.err(
                        format!("{path}.controller"),
                        "a controller name",
                        format!("{name:?}"),
                    ));
                }
                // Held at 0 in a drive mode the controller does not run in.
                match controllers.command(&mut g, name) {
                    Some(c) => c,
                    None => zero,
                }
            } else if what == "force" {
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
                let absolute = term.frame == Some(Frame::Absolute);
                let (bv, bx) = base_vx.unwrap_or((zero, zero));
                match (what, absolute) {
                    ("displacement", false) => motion[k].x,
                    ("velocity", false) => motion[k].v,
                    (_, false) => accel[k],
                    ("displacement", true) => g.add(motion[k].x, bx),
                    ("velocity", true) => g.add(motion[k].v, bv),
                    (_, true) => g.add(accel[k], base_a),
                }
            };
            let v = g.mul(gain, v);
            sum = g.add(sum, v);
        }
        outputs.push(sum);
    }

    let sampling = controllers.sampling(lay, &mut g, &outputs, &mut tables)?;

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
        sampling,
    };
    p.mark_run_constants();
    Ok(p)
}
