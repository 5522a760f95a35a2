//! Digital controllers: their discrete states laid out as held states, the
//! held command's force on its node, and the update laws lowered to the
//! graph (see [`crate::compile::program::Sampling`] for what an instant does).

use std::collections::HashMap;

use super::expr;
use super::layout::Layout;
use crate::base::PiecewiseLinear;
use crate::compile::ir::{Graph, Id, Input};
use crate::compile::program::Sampling;
use crate::rig::RigError;
use crate::rig::desc::ControllerDesc;

/// The controllers of one drive mode, checked: each one's index in the rig
/// file and its first held state (its states are consecutive).
pub(super) struct Controllers<'a> {
    pub(super) list: Vec<(usize, &'a ControllerDesc, u32)>,
}

impl<'a> Controllers<'a> {
    /// The controllers of `mode`, checked: names, periods, states, command,
    /// node.
    pub(super) fn of_mode(lay: &Layout<'a>, mode: &str) -> Result<Self, RigError> {
        let mut list = vec![];
        let mut next = 0u32;
        let mut rate: Option<(usize, f64, f64)> = None;
        for (i, c) in lay.desc.controllers.iter().enumerate() {
            let path = format!("controllers[{i}]");
            if c.mode != "velocity" && c.mode != "force" {
                return Err(lay.err(
                    format!("{path}.mode"),
                    "\"velocity\" or \"force\"",
                    format!("{:?}", c.mode),
                ));
            }
            if lay.desc.controllers[..i].iter().any(|o| o.name == c.name) {
                return Err(lay.err(
                    format!("{path}.name"),
                    "a name no other controller has",
                    format!("{:?} again", c.name),
                ));
            }
            if !(c.period.is_finite() && c.period > 0.0) {
                return Err(lay.err(
                    format!("{path}.period"),
                    "a sample period in seconds, finite and > 0",
                    c.period.to_string(),
                ));
            }
            if !(c.phase.is_finite() && c.phase >= 0.0) {
                return Err(lay.err(
                    format!("{path}.phase"),
                    "the first sample instant in seconds, finite and ≥ 0",
                    c.phase.to_string(),
                ));
            }
            if c.mode != mode {
                continue;
            }
            match rate {
                Some((j, p, ph)) if p != c.period || ph != c.phase => {
                    return Err(lay.err(
                        format!("{path}.period"),
                        format!(
                            "the period and phase of controllers[{j}] ({p} s, {ph} s): the controllers of one drive mode sample together"
                        ),
                        format!("{} s, {} s", c.period, c.phase),
                    ));
                }
                _ => rate = Some((i, c.period, c.phase)),
            }
            if c.states.is_empty() {
                return Err(lay.err(
                    format!("{path}.states"),
                    "at least one discrete state",
                    "an empty list",
                ));
            }
            for (j, st) in c.states.iter().enumerate() {
                if !super::names::ident(&st.name) {
                    return Err(lay.err(
                        format!("{path}.states[{j}].name"),
                        "letters, digits and '_', not starting with a digit",
                        format!("{:?}", st.name),
                    ));
                }
                if c.states[..j].iter().any(|o| o.name == st.name) {
                    return Err(lay.err(
                        format!("{path}.states[{j}].name"),
                        "a name no other state of this controller has",
                        format!("{:?} again", st.name),
                    ));
                }
                let clash = if lay.params.contains_key(st.name.as_str()) {
                    Some("a parameter")
                } else if lay.desc.outputs.iter().any(|o| o.name == st.name) {
                    Some("an output")
                } else if ["t", "reference", "period"].contains(&st.name.as_str()) {
                    Some("a name every update law reads")
                } else {
                    None
                };
                if let Some(what) = clash {
                    return Err(lay.err(
                        format!("{path}.states[{j}].name"),
                        "a name that is not a parameter's, an output's, 't', 'period' or 'reference'",
                        format!("{:?}, the name of {what}", st.name),
                    ));
                }
            }
            if !c.states.iter().any(|s| s.name == c.command) {
                let names: Vec<&str> = c.states.iter().map(|s| s.name.as_str()).collect();
                return Err(lay.err(
                    format!("{path}.command"),
                    format!("one of the controller's states ({})", names.join(", ")),
                    format!("{:?}", c.command),
                ));
            }
            if !lay.nodes.contains_key(c.acts_on.node.as_str()) {
                return Err(lay.err(
                    format!("{path}.acts_on.node"),
                    "a node name",
                    format!("{:?}", c.acts_on.node),
                ));
            }
            list.push((i, c, next));
            next += c.states.len() as u32;
        }
        Ok(Self { list })
    }

    /// The held command of the controller named `name` in this mode.
    pub(super) fn command(&self, g: &mut Graph, name: &str) -> Option<Id> {
        let &(_, c, first) = self.list.iter().find(|(_, c, _)| c.name == name)?;
        let k = c.states.iter().position(|s| s.name == c.command)?;
        Some(g.input(Input::Held(first + k as u32)))
    }

    /// Each controller's force on its node: (node index, `gain·command`).
    pub(super) fn forces(
        &self,
        lay: &Layout<'_>,
        g: &mut Graph,
    ) -> Result<Vec<(usize, Id)>, RigError> {
        let mut out = vec![];
        for &(i, c, _) in &self.list {
            let gain = lay.coef(
                g,
                &c.acts_on.gain,
                &format!("controllers[{i}].acts_on.gain"),
            )?;
            let cmd = self.command(g, &c.name).expect("checked");
            let f = g.mul(gain, cmd);
            out.push((lay.nodes[c.acts_on.node.as_str()], f));
        }
        Ok(out)
    }

    /// The sample instants and every state's update and initial value,
    /// where `outputs` are the rig's outputs (laws read them by name);
    /// `reference` adds the experiment's table to `tables` where a law of a
    /// `"force"`-mode controller reads it.
    pub(super) fn sampling(
        &self,
        lay: &Layout<'_>,
        g: &mut Graph,
        outputs: &[Id],
        tables: &mut Vec<Option<PiecewiseLinear>>,
    ) -> Result<Option<Sampling>, RigError> {
        let Some(&(_, first, _)) = self.list.first() else {
            return Ok(None);
        };
        let mut s = Sampling {
            period: first.period,
            phase: first.phase,
            names: vec![],
            update: vec![],
            initial: vec![],
        };
        let t = g.input(Input::Time);
        for &(i, c, base) in &self.list {
            let own: HashMap<&str, Id> = c
                .states
                .iter()
                .enumerate()
                .map(|(j, st)| (st.name.as_str(), g.input(Input::Held(base + j as u32))))
                .collect();
            for (j, st) in c.states.iter().enumerate() {
                let path = format!("controllers[{i}].states[{j}]");
                s.names.push(format!("{}.{}", c.name, st.name));
                let init = match &st.initial {
                    Some(v) => lay.coef(g, v, &format!("{path}.initial"))?,
                    None => g.c(0.0),
                };
                s.initial.push(init);
                let u = self.update_law(
                    lay,
                    g,
                    c,
                    &own,
                    outputs,
                    t,
                    tables,
                    &st.update,
                    &format!("{path}.update"),
                )?;
                s.update.push(u);
            }
        }
        Ok(Some(s))
    }

    #[expect(clippy::too_many_arguments, reason = "what a law may read")]
    fn update_law(
        &self,
        lay: &Layout<'_>,
        g: &mut Graph,
        c: &ControllerDesc,
        own: &HashMap<&str, Id>,
        outputs: &[Id],
        t: Id,
        tables: &mut Vec<Option<PiecewiseLinear>>,
        src: &str,
        path: &str,
    ) -> Result<Id, RigError> {
        let expected = "a formula of the controller's states, the rig's outputs and parameters, t, period and (in \"force\" mode) reference";
        let at = lay.law_error(path, expected, src);
        let e = expr::parse(src).map_err(&at)?;
        let desc = lay.desc;
        e.lower(g, &mut |g, name| {
            if let Some(&h) = own.get(name) {
                return Ok(h);
            }
            if let Some(o) = desc.outputs.iter().position(|o| o.name == name) {
                return Ok(outputs[o]);
            }
            if name == "t" {
                return Ok(t);
            }
            if name == "period" {
                return Ok(g.c(c.period));
            }
            if name == "reference" {
                if c.mode != "force" {
                    return Err(
                        "'reference' is the experiment's table, which only a \"force\"-mode controller has"
                            .to_string(),
                    );
                }
                let k = match tables.iter().position(Option::is_none) {
                    Some(k) => k,
                    None => {
                        tables.push(None);
                        tables.len() - 1
                    }
                };
                return Ok(g.input(Input::Table(k as u32)));
            }
            if let Some(&i) = lay.params.get(name) {
                return Ok(g.input(Input::Slot(i)));
            }
            let other = desc
                .controllers
                .iter()
                .find(|o| o.states.iter().any(|s| s.name == name))
                .map(|o| {
                    format!(
                        " ('{name}' is a state of controller '{}': a law reads only its own controller's states, so one controller reaches another only through the rig, and no two can wait on each other)",
                        o.name
                    )
                })
                .unwrap_or_default();
            let near = if other.is_empty() {
                let names = own
                    .keys()
                    .copied()
                    .chain(desc.outputs.iter().map(|o| o.name.as_str()))
                    .chain(lay.params.keys().copied())
                    .chain(["t", "period", "reference"]);
                super::names::nearest(names, name)
                    .map(|n| format!(" (did you mean '{n}'?)"))
                    .unwrap_or_default()
            } else {
                String::new()
            };
            Err(format!(
                "unknown name '{name}': not one of the controller's states, an output, a parameter, 't', 'period' or 'reference'{other}{near}"
            ))
        })
        .map_err(at)
    }
}
