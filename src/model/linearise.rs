//! The linearisation of a compiled rig for modal analysis: the compiled
//! derivative's own tangents about rest, in the engaged, unbroken
//! configuration, as `M·ẍ + K·x = 0`.

use super::Linearised;
use super::compiled::{CompiledRig, prescribed};
use crate::base::Drive;
use crate::rig::desc::{Coef, GapKind};

impl CompiledRig {
    /// [`crate::model::CompiledRig::linearise`] of a compiled rig.
    pub(super) fn linearise_at_rest(&self, params: &[f64], drive: &Drive) -> Linearised {
        // About rest with every contact closed (a backlash element's play
        // taken up in tension), nothing broken or yielded and every slider
        // stuck, from the compiled derivative's own tangents.
        let mut st = self.stepper(params, drive).expect("a declared drive mode");
        for (v, m) in self.lowered.regimes.iter().enumerate() {
            st.regimes[v] =
                u32::from(m.name.ends_with(".contact") || m.name.ends_with(".backlash"));
        }
        let pi = self.program_for(drive).expect("declared");
        let prog = &self.lowered.programs[pi];
        let nodes = self.desc.nodes.len();
        let n = self.states.len();
        // A node is a degree of freedom unless the drive prescribes it (its
        // displacement slot's derivative is then the constant 0).
        let free: Vec<usize> = (0..nodes).filter(|&k| !prescribed(prog, k)).collect();
        let mass: Vec<f64> = free
            .iter()
            .map(|&k| match &self.desc.nodes[k].mass {
                Coef::Number(v) => *v,
                Coef::Param(p) => params[self.param_index(p)],
                Coef::Switch(_) => f64::NAN,
            })
            .collect();
        let d = free.len();
        let regimes = st.regimes.clone();
        let jac = crate::compile::analysis::tangent::deriv_jacobian(
            prog,
            &self.tapes[pi],
            &mut st.frame,
            0.0,
            &vec![0.0; n],
            &regimes,
        );
        // An internal state whose rate is a fixed mix of node velocities
        // (a stuck slider's tangential stretch: ṡ = v_b − v_a) moves with the
        // nodes, s = Σ_j (∂ṡ/∂v_j)·x_j + const, so its force is a stiffness
        // between them: its column folds into the node columns through that
        // mix. A state that stands still in the chosen regime (a backlash
        // play taken up, a slipping slider) has a zero mix and adds nothing.
        let follows = |s: usize| {
            (0..n)
                .filter(|&j| !(nodes..2 * nodes).contains(&j))
                .all(|j| jac[s * n + j] == 0.0)
        };
        let carried: Vec<usize> = (2 * nodes..n).filter(|&s| follows(s)).collect();
        let mut kmat = vec![0.0; d * d];
        for (i, &ki) in free.iter().enumerate() {
            let row = (nodes + ki) * n;
            for (j, &kj) in free.iter().enumerate() {
                let through: f64 = carried
                    .iter()
                    .map(|&s| jac[row + s] * jac[s * n + nodes + kj])
                    .sum();
                kmat[i * d + j] = -mass[i] * (jac[row + kj] + through);
            }
        }
        Linearised {
            dofs: free
                .iter()
                .map(|&k| self.desc.nodes[k].name.clone())
                .collect(),
            mass,
            stiffness: kmat,
        }
    }

    /// [`crate::model::CompiledRig::linearisation_point`] of a compiled rig.
    pub(super) fn rest_point(&self) -> String {
        // The same mode choice as `linearise`, said only for the kinds of
        // switching element the rig has.
        let has = |suffix: &str| {
            self.lowered
                .regimes
                .iter()
                .any(|m| m.name.ends_with(suffix))
        };
        let mut said = Vec::new();
        if has(".contact") {
            let free_play = self
                .desc
                .elements
                .iter()
                .any(|e| e.gap.as_ref().is_some_and(|g| g.kind == GapKind::FreePlay));
            said.push(if free_play {
                "every contact closed (free play in tension)"
            } else {
                "every contact closed"
            });
        }
        match (has(".fracture"), has(".yield")) {
            (true, true) => said.push("nothing broken or yielded"),
            (true, false) => said.push("nothing broken"),
            (false, true) => said.push("nothing yielded"),
            (false, false) => {}
        }
        if has(".friction") {
            said.push("every slider stuck");
        }
        if has(".backlash") {
            said.push("backlash taken up in tension");
        }
        let mut s = format!("rig {} linearised about rest", self.id);
        if !said.is_empty() {
            s += &format!(": {}", said.join(", "));
        }
        if !self.desc.controllers.is_empty() {
            // A held command is constant between samples: it adds no
            // stiffness to the continuous rig, whatever its gains.
            let names: Vec<&str> = self
                .desc
                .controllers
                .iter()
                .map(|c| c.name.as_str())
                .collect();
            s += &format!(
                " (without its digital controllers, {}: their held command is constant between samples)",
                names.join(", ")
            );
        }
        s
    }
}
