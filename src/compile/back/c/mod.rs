//! A program's lane code ([`crate::compile::exec::lane_code`]) written as C for the native
//! lane ensemble ([`crate::compile::back::native`]): the same instructions on the same
//! registers, but each register a local vector variable (GCC's vector
//! extension, as wide as the processor's vector registers: 64 bytes on
//! AVX-512, 32 on AVX2, 16 otherwise, each holding as many f64 or f32 lanes
//! as fit, [`Arith`]) instead of a row of the register file, so the C
//! compiler keeps the temporaries in vector registers and the lanes' loads
//! and stores are left to the states, regimes and per-run constants. A
//! vector wider than the registers is split by the compiler into two or
//! four, whose temporaries no longer fit the register file and spill: built
//! for AVX2 alone, the tensile rig's step took 2–3× as long per lane in
//! 64-byte vectors as in 32-byte ones.
//!
//! In f64 the C evaluates every operation as the interpreter does: no
//! contraction of a multiply and an add (`-ffp-contract=off`), `eˣ` and
//! `eˣ − 1`, `ln`, `sin` and `cos` as [`crate::compile::math`]'s
//! branch-free forms step for step (a `sin` or `cos` of more than 10⁶ from
//! the C library, lane by lane, as there), so each lane's bits are the
//! scalar reference's. In f32 the
//! same operations round to f32, a multiply and an add fused where the
//! processor can (`-ffp-contract=fast`: 14 % off the tensile step); the
//! register file still holds f64, so the runner around them is the same.
//!
//! Functions over blocks `0..nb` of the register file (`R`, rows of
//! `BLOCKS` blocks): `rig_rk4` (one RK4 step, the start kept in `Y`, then
//! the event list on the new state while it is still in registers, and a bit
//! per lane past an armed switch), `rig_report` and `rig_measured` (one list,
//! roots stored back where the interpreter leaves them); `rig_deriv1`
//! and `rig_events1`, one run's derivative and event functions in f64; and
//! `rig_redo`, the steps of an f64 vector's lanes redone with their switches
//! located (where the code has switches and reads no table).
//!
//! The C that is the same for every program is kept as C beside this file
//! (`prelude.h`, `scalar.h`, `f64_lanes.h`, `f32_lanes.h`, `lane_ops.h`,
//! `redo_ops.h`, `redo.c`); the Rust writes what each program's lane code
//! decides.

mod redo;
mod rk4;
mod statements;

use std::fmt::Write;

use redo::redo;
use rk4::{STORE_HITS, hoist, lane_bits, rk4_loop};
use statements::{declare, inputs, list_fn, load, statement, store, vector_ops};

use crate::compile::exec::lane_code::{LaneCode, Reg};
use crate::compile::exec::lanes::BLOCKS;

pub use crate::compile::exec::native_calls::Arith;
pub use redo::redoes;
pub use rk4::{Hoistable, hoistable, table_stride};

/// The f64 arithmetic both precisions share: eight lanes of doubles, and
/// [`crate::compile::math`]'s `eˣ` and `eˣ − 1` step for step.
const PRELUDE: &str = include_str!("prelude.h");

/// One run's f64 arithmetic, for the derivative a redone step takes
/// (`rig_deriv1`): the f64 `eˣ` and `eˣ − 1` above, and Rust's `min`, `max`,
/// comparisons and select, on scalars.
const SCALAR: &str = include_str!("scalar.h");

/// The lane type `v` of [`Arith::F64`]: the f64 vector, `DW` lanes of a
/// register-file row (`q` counts vectors along the row).
const F64_LANES: &str = include_str!("f64_lanes.h");

/// The lane type `v` of [`Arith::F32`]: twice the f64 vector's lanes, read
/// from two f64 vectors of a register-file row and rounded to f32 (the
/// shuffles that join and split them are [`source`]'s).
const F32_LANES: &str = include_str!("f32_lanes.h");

/// What both lane types share, written on `v`: `NQ(nb)` vectors cover
/// blocks `0..nb` (the f32 vector of 64 bytes also the block after an odd
/// last one, still below `BLOCKS`).
const LANE_OPS: &str = include_str!("lane_ops.h");

/// `a, a + 1, …, b − 1`, as a shuffle's indices.
fn indices(a: usize, b: usize) -> String {
    (a..b).map(|i| i.to_string()).collect::<Vec<_>>().join(", ")
}

/// `x, x, …` for `n` lanes: a splat as an initialiser, not a loop over the
/// lanes (at -O2 GCC builds the loop's vector in memory and reloads it, a
/// stalled store-to-load forward on every splat of a loop-varying value,
/// which took the tensile event list 350 ns per 64 lanes instead of 133).
fn all_lanes(n: usize) -> String {
    vec!["x"; n].join(", ")
}

/// [`PRELUDE`] for vectors of `vector_bytes`, with the definitions it reads.
fn prelude(vector_bytes: usize) -> String {
    use crate::compile::math::TRIG_REDUCED_UP_TO;
    format!(
        "#define BLOCKS {BLOCKS}\n#define VBYTES {vector_bytes}\n#define DALL(x) {}\n#define TRIG_MAX {TRIG_REDUCED_UP_TO:?}\n{PRELUDE}",
        all_lanes(vector_bytes / 8)
    )
}

/// The C source of `code`'s four functions on vectors of `vector_bytes`
/// (16, 32 or 64: the processor's vector registers, [`crate::compile::exec::lanes::Isa::vector_bytes`]).
pub fn source(code: &LaneCode, arith: Arith, vector_bytes: usize) -> String {
    assert!(
        matches!(vector_bytes, 16 | 32 | 64),
        "{vector_bytes}-byte vectors"
    );
    let mut s = prelude(vector_bytes);
    let f64_lanes = vector_bytes / 8;
    let lanes = match arith {
        Arith::F64 => f64_lanes,
        Arith::F32 => 2 * f64_lanes,
    };
    let _ = writeln!(s, "#define VALL(x) {}", all_lanes(lanes));
    match arith {
        Arith::F64 => s.push_str(F64_LANES),
        Arith::F32 => {
            let _ = writeln!(
                s,
                "#define JOIN {}\n#define LO {}\n#define HI {}",
                indices(0, lanes),
                indices(0, f64_lanes),
                indices(f64_lanes, lanes)
            );
            s.push_str(F32_LANES);
        }
    }
    s.push_str(LANE_OPS);
    s.push_str(&vector_ops('v', "v", "m", "splat", "pick"));
    s.push_str(&lane_bits(lanes));
    let table_regs: Vec<(u32, Reg)> = code
        .lists()
        .iter()
        .flat_map(|l| l.tables.iter().copied())
        .collect();
    let table_of = |reg: Reg| table_regs.iter().find(|&&(_, r)| r == reg).map(|&(k, _)| k);

    // rig_rk4: tt[4] the derivative's times (tt[1] == tt[2] = t + h/2), tab[4 * table_stride] the
    // tables at them, ch = 0.5·h, h, h6 = h/6 (computed by the caller as the
    // interpreter does); `hoist`: every constant `hoistable` lists is the
    // same in every lane; `hit`: a bit per lane past an armed switch at the
    // step's end.
    let hoisted = hoistable(code);
    s.push_str(
        "void rig_rk4(blk *restrict R, blk *restrict Y, long nb, const double *tt, const double *tab, double ch, double h, double h6, long hoist, unsigned char *hit) {\n  const v CH = splat(ch), H = splat(h), H6 = splat(h6), TWO = splat(2.0);\n  unsigned long long hits = 0;\n  m kor = (m){0}, ks[(BLOCKS * 8 + WV - 1) / WV];\n",
    );
    if hoisted.deriv.contains(&true) || hoisted.events.contains(&true) {
        s.push_str("  if (hoist) {\n  const long q = 0;\n");
        declare(&mut s, code, "v");
        for &reg in &hoisted.reads {
            load(&mut s, reg, "", code, &|_| None);
        }
        for stage in [0, 1, 3] {
            let keep = format!("u{stage}_");
            hoist(&mut s, code, &code.deriv, &hoisted.deriv, stage, &keep);
        }
        hoist(&mut s, code, &code.events, &hoisted.events, 3, "e_");
        rk4_loop(&mut s, code, Some(&hoisted));
        s.push_str(STORE_HITS);
        s.push_str("  return;\n  }\n");
    }
    rk4_loop(&mut s, code, None);
    s.push_str(STORE_HITS);
    s.push_str("}\n");

    // rig_deriv1 and rig_events1 where no rig_redo is built: one run's
    // derivative and event functions for the steps its stepper redoes; `R`
    // its scalar register file (states, regimes, held states and per-run
    // constants at their registers), `out` the slopes or the event
    // functions' values.
    if redoes(code) {
        redo(&mut s, code);
    } else {
        s.push_str(SCALAR);
        for (name, list) in [("deriv1_", &code.deriv), ("events1_", &code.events)] {
            let head = format!(
                "static __attribute__((noinline)) void {name}(const double *restrict R, double t, const double *tab, double *restrict out) {{\n    (void)t; (void)tab;"
            );
            list_fn(&mut s, code, list, &head, ("double", 's'), &|reg| {
                if reg == code.time {
                    "t".to_string()
                } else if let Some(k) = table_of(reg) {
                    format!("tab[{k}]")
                } else {
                    format!("R[{reg}]")
                }
            });
        }
        s.push_str(
            "void rig_deriv1(const double *restrict R, double t, const double *tab, double *restrict out) { deriv1_(R, t, tab, out); }\n\
             void rig_events1(const double *restrict R, double t, const double *tab, double *restrict out) { events1_(R, t, tab, out); }\n",
        );
    }

    for (name, list) in [
        ("rig_report", &code.report),
        ("rig_measured", &code.measured),
        ("rig_update", &code.update),
    ] {
        let _ = writeln!(
            s,
            "void {name}(blk *restrict R, long nb, double t, const double *tab) {{\n  for (long q = 0; q < NQ(nb); q++) {{"
        );
        declare(&mut s, code, "v");
        let tabs = |reg: Reg| table_of(reg).map(|k| format!("tab[{k}]"));
        for &reg in &inputs(list) {
            load(&mut s, reg, "t", code, &tabs);
        }
        for ins in &list.code {
            s.push_str(&statement(ins.dest, &ins.op, 'v'));
        }
        for &root in &list.roots {
            store(&mut s, code, root);
        }
        s.push_str("  }\n}\n");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compile::math;

    /// The prelude's `sin` and `cos` as the lanes call them, for vectors of
    /// `vector_bytes` and for one value, on each of `xs` (in lanes of
    /// `DW`): the bits of the vector `sin`, `cos`, then the scalar ones.
    fn c_trig(xs: &[f64], vector_bytes: usize) -> Vec<[u64; 4]> {
        let dir = tempfile::tempdir().unwrap();
        let main = r#"#include <stdio.h>
#include <string.h>
int main(void) {
  unsigned long long b[DW];
  for (;;) {
    for (int l = 0; l < DW; l++) if (scanf("%llx", &b[l]) != 1) return 0;
    d x; memcpy(&x, b, sizeof x);
    d s = dsin(x), c = dcos(x);
    for (int l = 0; l < DW; l++) {
      double o[4] = {s[l], c[l], dsin1(x[l]), dcos1(x[l])};
      unsigned long long ob[4]; memcpy(ob, o, sizeof o);
      printf("%llx %llx %llx %llx\n", ob[0], ob[1], ob[2], ob[3]);
    }
  }
}
"#;
        let src = format!("{}{main}", prelude(vector_bytes));
        let (c, exe) = (dir.path().join("trig.c"), dir.path().join("trig"));
        std::fs::write(&c, src).unwrap();
        let built = std::process::Command::new(crate::compile::back::native::compiler::compiler())
            .args(["-O2", "-march=native", "-ffp-contract=off", "-w", "-o"])
            .arg(&exe)
            .arg(&c)
            .arg("-lm")
            .output()
            .expect("the C compiler runs");
        assert!(
            built.status.success(),
            "{}",
            String::from_utf8_lossy(&built.stderr)
        );
        let input: String = xs.iter().map(|x| format!("{:x}\n", x.to_bits())).collect();
        let args = dir.path().join("args");
        std::fs::write(&args, input).unwrap();
        let out = std::process::Command::new(&exe)
            .stdin(std::fs::File::open(&args).unwrap())
            .output()
            .unwrap();
        assert!(out.status.success());
        String::from_utf8(out.stdout)
            .unwrap()
            .lines()
            .map(|l| {
                let v: Vec<u64> = l
                    .split(' ')
                    .map(|h| u64::from_str_radix(h, 16).unwrap())
                    .collect();
                [v[0], v[1], v[2], v[3]]
            })
            .collect()
    }

    #[test]
    fn c_sin_and_cos_are_the_reference_bit_for_bit() {
        // Next to multiples of π/2, where the reduction takes its second
        // and third rounds, mixed in every vector with ordinary arguments,
        // ones beyond the reduced range, ±∞, NaN, signed zeros and
        // subnormals, so a vector takes each round for some lanes only.
        let mut xs = vec![];
        for k in 1..3000_i64 {
            let x = k as f64 * std::f64::consts::FRAC_PI_2 * (1.0 + (k % 7) as f64 * 37.0);
            let near = f64::from_bits(x.to_bits().wrapping_add_signed(k % 5 - 2));
            xs.extend([near, 0.1 * k as f64, -near]);
        }
        xs.extend([
            1.5e6,
            -3e9,
            1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            0.0,
            -0.0,
            5e-324,
            -1e-310,
            1e-8,
        ]);
        for vector_bytes in [16, 32, 64] {
            let lanes = vector_bytes / 8;
            let mut padded = xs.clone();
            padded.resize(xs.len().div_ceil(lanes) * lanes, 0.25);
            let got = c_trig(&padded, vector_bytes);
            assert_eq!(got.len(), padded.len());
            for (x, g) in padded.iter().zip(&got) {
                let want = [math::sin(*x), math::cos(*x)];
                for (k, bits) in g.iter().enumerate() {
                    let (a, b) = (f64::from_bits(*bits), want[k % 2]);
                    assert!(
                        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                        "{vector_bytes}-byte vectors, output {k} at {x:e}: {a:e} against {b:e}"
                    );
                }
            }
        }
    }
}
