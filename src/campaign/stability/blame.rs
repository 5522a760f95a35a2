//! Which free ranges a too-high frequency bound comes from, for a refusal's
//! remedy: the bound names the law that sets it (the stiffest spring at the
//! lightest node), which may be a fixed parameter — when a free mass's lower
//! bound (or a free stiffness's upper one) is what makes it too high, the
//! remedy names that free bound instead.

use crate::base::text::echo_bare;
use crate::eval::ExperimentData;
use crate::model::CompiledRig;

/// A free parameter held at one end lowers the bound below this share of it
/// to count as one that sets it.
pub(super) const DRIVER_SHARE: f64 = 0.9;

/// At most this many free parameters are named.
const MOST_NAMED: usize = 3;

/// One free parameter whose range sets the bound: its index, whether its
/// lower end is the one to move (a mass too light: raise it) rather than its
/// upper end, and the bound (rad/s) with it held at its other end.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Driver {
    pub index: usize,
    pub lower_end: bool,
    pub omega: f64,
}

/// The free parameters of a run over `lo..hi` (to model time `t_end`) that
/// each, held at their favourable end, bring its bound `omega` below
/// [`DRIVER_SHARE`] of it, the one that lowers it most first.
pub(super) fn drivers(
    model: &CompiledRig,
    x: &ExperimentData,
    lo: &[f64],
    hi: &[f64],
    t_end: f64,
    omega: f64,
) -> Vec<Driver> {
    let mut out = Vec::new();
    for i in 0..lo.len().min(hi.len()) {
        if lo[i].partial_cmp(&hi[i]) != Some(std::cmp::Ordering::Less) {
            continue;
        }
        let held = |v: f64| {
            let (mut a, mut b) = (lo.to_vec(), hi.to_vec());
            a[i] = v;
            b[i] = v;
            model.omega_bound_in_run(&a, &b, &x.drive, t_end).0
        };
        // Held at its upper end, the lower end is out of the box: if that
        // lowers the bound, the lower end is what raised it.
        let (at_hi, at_lo) = (held(hi[i]), held(lo[i]));
        let (w, lower_end) = if at_hi.total_cmp(&at_lo).is_le() {
            (at_hi, true)
        } else {
            (at_lo, false)
        };
        if w.is_finite() && w < DRIVER_SHARE * omega {
            out.push(Driver {
                index: i,
                lower_end,
                omega: w,
            });
        }
    }
    out.sort_by(|a, b| a.omega.total_cmp(&b.omega));
    out.truncate(MOST_NAMED);
    out
}

/// The JSON path of the gene that searches parameter `name` in experiment
/// `e` (its own, else the shared one), `None` for a fixed parameter.
pub(super) fn gene_path(
    model: &CompiledRig,
    genes: &[crate::campaign::Gene],
    e: usize,
    name: &str,
) -> Option<String> {
    use crate::campaign::GeneTarget;
    let i = model.params().iter().position(|p| p.name == name)?;
    let g = genes
        .iter()
        .filter(|g| g.target == GeneTarget::Param(i))
        .find(|g| g.experiment == Some(e))
        .or_else(|| {
            genes
                .iter()
                .find(|g| g.target == GeneTarget::Param(i) && g.experiment.is_none())
        })?;
    Some(match g.experiment {
        Some(x) => format!("experiments[{x}].params.{name}"),
        None => format!("params.{name}"),
    })
}

/// What to change in the campaign so that the bound `omega`, which `named`
/// limits, comes down: the named parameter's range where it is free and
/// nothing else sets it, else the free bounds that set it (`raise m2's lower
/// bound (params.m2.min = 1e-7 kg)`), saying that `named` is fixed; `None`
/// where no free range sets the bound (only the sample interval or the
/// substeps can then help).
pub(super) fn remedy(
    model: &CompiledRig,
    genes: &[crate::campaign::Gene],
    e: usize,
    x: &ExperimentData,
    (lo, hi, t_end): (&[f64], &[f64], f64),
    omega: f64,
    named: &str,
) -> Option<String> {
    let infos = model.params();
    let named_index = infos.iter().position(|p| p.name == named);
    let named_free = named_index.is_some_and(|i| lo[i] < hi[i]);
    let found = drivers(model, x, lo, hi, t_end, omega);
    if named_free && found.first().is_none_or(|d| Some(d.index) == named_index) {
        return Some(format!("narrow the range of '{}'", echo_bare(named)));
    }
    if found.is_empty() {
        return None;
    }
    let moves: Vec<String> = found
        .iter()
        .map(|d| {
            let p = &infos[d.index];
            let name = echo_bare(&p.name);
            let (verb, end, key, v) = if d.lower_end {
                ("raise", "lower", "min", lo[d.index])
            } else {
                ("lower", "upper", "max", hi[d.index])
            };
            let at = gene_path(model, genes, e, &p.name)
                .map_or_else(String::new, |path| format!("{path}.{key} = "));
            format!(
                "{verb} {name}'s {end} bound ({at}{v:e} {}; ω ≤ {:.3e} rad/s with {name} held \
                 at its other end)",
                p.unit, d.omega
            )
        })
        .collect();
    let why = if named_free {
        String::new()
    } else {
        format!(
            " ('{}' is fixed: the free range{} named set{} the bound)",
            echo_bare(named),
            if moves.len() > 1 { "s" } else { "" },
            if moves.len() > 1 { "" } else { "s" },
        )
    };
    Some(format!("{}{why}", moves.join(", or ")))
}
