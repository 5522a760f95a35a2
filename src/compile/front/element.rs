//! Each element's force (spring, damper, friction, gap, backlash, yield,
//! fracture) lowered to the graph, with its switches as transitions.

use super::MAX_DEGREE;
use super::layout::Layout;
use crate::compile::ir::{Graph, Id, Input};
use crate::compile::program::Direction::{self, Down, Up};
use crate::compile::program::Transition;
use crate::rig::RigError;
use crate::rig::desc::{Coef, DamperLaw, ElementDesc, FrictionLaw, GapKind, SpringLaw};

/// The force of element `i` (tension positive), registering its switches.
#[expect(
    clippy::too_many_arguments,
    reason = "one lowering step, all of it needed"
)]
pub(super) fn element_force(
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
        let m = g.input(Input::Regime(var));
        let v = g.c(value);
        g.eq(m, v)
    };
    // Registers switches of regime variable `var`: per switch the words after
    // the element's name, the regime it leaves, the one it enters, the
    // function it fires at the zero of and the direction it fires in.
    let switches =
        |trans: &mut Vec<Transition>, var: u32, list: &[(&str, u32, u32, Id, Direction)]| {
            for &(what, from, to, g, dir) in list {
                trans.push(Transition {
                    name: format!("{} {what}", e.name),
                    var,
                    from,
                    to,
                    g,
                    dir,
                    guard: Vec::new(),
                });
            }
        };
    // The switches of a three-regime element (backlash, stick-slip): out of
    // regime 0 into 1 as `x` rises through `w` or into 2 as it falls through
    // `−w`, back into 0 as `back` falls (from 1) or rises (from 2) through
    // zero; `names` in that order.
    let three_regimes = |g: &mut Graph,
                         trans: &mut Vec<Transition>,
                         var,
                         names: [&str; 4],
                         (x, w): (Id, Id),
                         back| {
        let up = g.sub(x, w);
        let down = g.add(x, w);
        let [a, b, c, d] = names;
        let list = [
            (a, 0, 1, up, Up),
            (b, 0, 2, down, Down),
            (c, 1, 0, back, Down),
            (d, 2, 0, back, Up),
        ];
        switches(trans, var, &list);
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
            let list: &[_] = match gd.kind {
                GapKind::Tension => &[("closes", 0, 1, d_t, Up), ("opens", 1, 0, d_t, Down)],
                GapKind::Compression => &[("closes", 0, 1, d_c, Down), ("opens", 1, 0, d_c, Up)],
                GapKind::FreePlay => &[
                    ("closes in tension", 0, 1, d_t, Up),
                    ("opens from tension", 1, 0, d_t, Down),
                    ("closes in compression", 0, 2, d_c, Down),
                    ("opens from compression", 2, 0, d_c, Up),
                ],
            };
            switches(trans, var, list);
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
                        switches(
                            trans,
                            var,
                            &[
                                ("yields", 0, 1, gy, Up),
                                ("unloads below the limit", 1, 0, gy, Down),
                            ],
                        );
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
                    let ln = g.push(crate::compile::ir::Op::Ln(safe));
                    let knee = g.div(ln, b);
                    let d_star = g.select(flat, zero, knee);
                    let a_over_b = g.div(a, b);
                    let exp_law = |g: &mut Graph, x: Id| {
                        let bx = g.mul(b, x);
                        let em = g.push(crate::compile::ir::Op::Expm1(bx));
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
                    let abs = g.push(crate::compile::ir::Op::Abs(rate));
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
            three_regimes(
                g,
                trans,
                var,
                [
                    "takes up its play in tension",
                    "takes up its play in compression",
                    "leaves tension contact",
                    "leaves compression contact",
                ],
                (p, b),
                lf,
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
        three_regimes(
            g,
            trans,
            var,
            [
                "slips forward",
                "slips backward",
                "sticks after slipping forward",
                "sticks after slipping backward",
            ],
            (ff, fc),
            rate,
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
        switches(trans, var, &[("breaks", 0, 1, gb, Up)]);
        let broken = mode_is(g, var, 1.0);
        f = g.select(broken, zero, f);
    }
    Ok(f)
}

pub(super) fn poly(
    lay: &Layout,
    g: &mut Graph,
    coeffs: &[Coef],
    sp: &str,
    d: Id,
) -> Result<Id, RigError> {
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
