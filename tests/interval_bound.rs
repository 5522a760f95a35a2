//! The stability bound from the compiled graph's interval tangents
//! (`CompiledRig::interval_omega`), checked on every shipped rig: at parameter
//! sets, times, states and mode values sampled in the box it encloses, every
//! entry of the pointwise Jacobian (the f64 forward-mode tangents) lies in its
//! interval, and every eigenvalue of the Jacobian (nalgebra) is no larger in
//! magnitude than the bound. Prints each rig's interval and per-law bounds.

use rigfit::base::{Drive, PiecewiseLinear};
use rigfit::compile::analysis::interval::deriv_jacobian_box;
use rigfit::compile::analysis::tangent::deriv_jacobian;
use rigfit::compile::{Frame, Tape};
use rigfit::model::compiled::CompiledRig;

/// A small deterministic generator (xorshift), uniform in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn within(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

#[test]
fn interval_bound_encloses_sampled_jacobians_of_every_shipped_rig() {
    let table = PiecewiseLinear {
        t: vec![0.0, 1.0, 2.0],
        value: vec![0.0, 50.0, -30.0],
    };
    let t_end = 2.0;
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut finite = 0;
    let mut checked = 0;
    for (id, _) in rigfit::rig::SHIPPED {
        let desc = rigfit::rig::shipped(id).expect("a shipped rig");
        let rig = CompiledRig::new(desc, id).expect("compiles");
        // Every parameter free over [0.8, 1.25]× its default (fixed at 0
        // where the default is 0).
        let mid: Vec<f64> = rig
            .desc
            .params
            .iter()
            .map(|p| p.default.unwrap_or(1.0))
            .collect();
        let lo: Vec<f64> = mid.iter().map(|&m| (0.8 * m).min(1.25 * m)).collect();
        let hi: Vec<f64> = mid.iter().map(|&m| (0.8 * m).max(1.25 * m)).collect();
        for (pi, prog) in rig.lowered.programs.iter().enumerate() {
            let drive = match prog.mode.as_str() {
                "force" => Drive::Force(table.clone()),
                _ => Drive::Velocity,
            };
            assert_eq!(rig.program_for(&drive), Some(pi));
            let (bound, name) = rig
                .interval_omega(&lo, &hi, &drive, t_end)
                .expect("a program");
            let per_law = rig.per_law_omega(&lo, &hi, &drive);
            let used = rig.omega_bound_in_run(&lo, &hi, &drive, t_end);
            eprintln!(
                "{id} ({}): interval {bound:.4e} rad/s (driven by {name}), per-law {:.4e} ({}), used {:.4e}",
                prog.mode, per_law.0, per_law.1, used.0
            );
            assert!(
                used.0 <= per_law.0,
                "{id}: the bound used is never looser than the per-law one"
            );
            if !bound.is_finite() {
                continue;
            }
            finite += 1;
            let bx = rig.input_box(prog, &drive, &lo, &hi, t_end);
            let enclosure = deriv_jacobian_box(prog, &bx);
            let tape = Tape::new(prog);
            let n = prog.deriv.len();
            let force = match &drive {
                Drive::Force(t) => Some(t),
                Drive::Velocity => None,
            };
            for _ in 0..60 {
                let params: Vec<f64> = lo
                    .iter()
                    .zip(&hi)
                    .map(|(&a, &b)| rng.within(a, b))
                    .collect();
                let t = rng.within(0.0, t_end);
                let y: Vec<f64> = bx.y.iter().map(|iv| rng.within(iv.lo, iv.hi)).collect();
                let regimes: Vec<u32> = bx
                    .regimes
                    .iter()
                    .map(|iv| (rng.next() * (iv.hi + 1.0)).floor() as u32)
                    .collect();
                let mut frame = Frame::new(prog, &tape, &params, force);
                let jac = deriv_jacobian(prog, &tape, &mut frame, t, &y, &regimes);
                if jac.iter().any(|x| !x.is_finite()) {
                    continue;
                }
                for (k, (&x, iv)) in jac.iter().zip(&enclosure).enumerate() {
                    assert!(
                        iv.contains(x),
                        "{id} ({}): ∂f{}/∂y{} = {x} at t = {t}, y = {y:?}, regimes {regimes:?} lies outside {iv:?}",
                        prog.mode,
                        k / n,
                        k % n
                    );
                }
                let m = nalgebra::DMatrix::from_row_slice(n, n, &jac);
                let rho = m
                    .complex_eigenvalues()
                    .iter()
                    .map(|l| l.norm())
                    .fold(0.0, f64::max);
                assert!(
                    rho <= bound * (1.0 + 1e-9),
                    "{id} ({}): |λ| = {rho} above the bound {bound} at params {params:?}",
                    prog.mode
                );
                checked += 1;
            }
        }
    }
    assert!(
        finite >= 6,
        "only {finite} programs have a finite interval bound"
    );
    assert!(checked >= 300, "only {checked} sampled Jacobians checked");
}
