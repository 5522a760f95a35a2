//! Drive signals and tables lowered to the graph.

use super::layout::Layout;
use crate::base::PiecewiseLinear;
use crate::compile::ir::{Graph, Id, Input};
use crate::compile::program::{Direction, Transition};
use crate::rig::RigError;
use crate::rig::desc::{Coef, DriveLaw, Quantity, TableDesc};

pub(super) fn table(
    lay: &Layout,
    path: &str,
    t: &[f64],
    v: &[f64],
) -> Result<PiecewiseLinear, RigError> {
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

/// A table drive's signal `gain·table(t)`: its own table (`t`, `value`), or
/// in a `"force"`-mode program without them the experiment's table (pushed to
/// `tables` as `None`).
pub(super) fn table_drive(
    lay: &Layout,
    g: &mut Graph,
    tables: &mut Vec<Option<PiecewiseLinear>>,
    path: &str,
    mode: &str,
    desc: &TableDesc,
) -> Result<Id, RigError> {
    let tab = match (&desc.t, &desc.value) {
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
    if let Some(gain) = &desc.gain {
        let gain = lay.coef(g, gain, &format!("{path}.law.gain"))?;
        f = g.mul(gain, f);
    }
    Ok(f)
}

/// Whether a drive law moves the base (and so names no node).
pub(super) fn moves_the_base(law: &DriveLaw) -> bool {
    match law {
        DriveLaw::BaseAccelerationTable(_) => true,
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
pub(super) fn signal(
    lay: &Layout,
    g: &mut Graph,
    law: &DriveLaw,
    i: usize,
    path: &str,
    t: Id,
    trans: &mut Vec<Transition>,
) -> Result<(Id, Id, Id), RigError> {
    use crate::compile::ir::Op;
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
            let on = started(g, t, zero);
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
            let on = started(g, t, zero);
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
                guard: Vec::new(),
            });
            trans.push(Transition {
                name: format!("{path} pulse ends"),
                var,
                from: 1,
                to: 2,
                g: left,
                dir: Direction::Up,
                guard: Vec::new(),
            });
            let pi = g.c(std::f64::consts::PI);
            let w = g.div(pi, tau);
            let phi = g.mul(w, since);
            let m = g.input(Input::Regime(var));
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

/// 1 from `t = 0` on, 0 before: a periodic drive is at rest until it starts.
/// At `t = 0` itself the drive is on: the step from 0 integrates over `[0, h]`,
/// so its first stage needs the drive's value just after the start (a sine's
/// displacement starts with velocity `A·ω`). Taking the value before the start
/// there cost RK4 its order: every run was first order in the step.
fn started(g: &mut Graph, t: Id, zero: Id) -> Id {
    g.le(zero, t)
}
