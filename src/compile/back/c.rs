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
//! `eˣ − 1`, `ln`, `sin` and `cos` as [`crate::compile::exec::math`]'s
//! branch-free forms step for step (a `sin` or `cos` of more than 10⁶ from
//! the C library, lane by lane, as there), so each lane's bits are the
//! scalar reference's. In f32 the
//! same operations round to f32, a multiply and an add fused where the
//! processor can (`-ffp-contract=fast`: 14 % off the tensile step); the
//! register file still holds f64, so the runner around them is the same.
//!
//! Functions over blocks `0..nb` of the register file (`R`, rows of
//! [`BLOCKS`] blocks): `rig_rk4` (one RK4 step, the start kept in `Y`, then
//! the event list on the new state while it is still in registers, and a bit
//! per lane past an armed switch), `rig_report` and `rig_measured` (one list,
//! roots stored back where the interpreter leaves them); `rig_deriv1`
//! and `rig_events1`, one run's derivative and event functions in f64; and
//! `rig_redo`, the steps of an f64 vector's lanes redone with their switches
//! located (where the code has switches and reads no table).

use std::fmt::Write;

use crate::compile::exec::lane_code::{LaneCode, List, Reg};
use crate::compile::exec::lanes::BLOCKS;
use crate::compile::ir::{Id, Op, operands};
use crate::compile::program::Direction;

/// The arithmetic the C code computes in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Arith {
    /// f64, eight lanes to a vector: bit for bit the scalar reference.
    F64,
    /// f32, sixteen lanes to a vector (the states and per-run constants
    /// packed as f32 in their rows, the other rows two blocks of the f64
    /// register file rounded on load): `eˣ` and `eˣ − 1` by the same reduction with an f32
    /// polynomial, `ln` (the f64 vector form), `sin`, `cos` computed in f64
    /// and rounded once.
    F32,
}

/// The f64 arithmetic both precisions share: eight lanes of doubles, and
/// [`crate::compile::exec::math`]'s `eˣ` and `eˣ − 1` step for step.
const PRELUDE: &str = r#"#include <math.h>
#define F static inline __attribute__((always_inline))
/* A block of the register file: eight f64 lanes. */
typedef double blk __attribute__((vector_size(64)));
/* The f64 vector: DW lanes in VBYTES bytes. */
typedef double d __attribute__((vector_size(VBYTES)));
typedef long long dm __attribute__((vector_size(VBYTES)));
typedef unsigned long long du __attribute__((vector_size(VBYTES)));
#define DW (VBYTES / 8)
F d dsplat(double x) { return (d){DALL(x)}; }
F d dpick(dm k, d a, d b) { return (d)((k & (dm)a) | (~k & (dm)b)); }
F d dclamp(d x, double lo, double hi) { x = dpick(x < dsplat(lo), dsplat(lo), x); return dpick(x > dsplat(hi), dsplat(hi), x); }
#define SHIFT 6755399441055744.0
F d dpoly(d r) {
  d r2 = r * r, r4 = r2 * r2, r8 = r4 * r4;
  d a0 = 1.0 + 0.5 * r;
  d a1 = (1.0 / 6.0) + (1.0 / 24.0) * r;
  d a2 = (1.0 / 120.0) + (1.0 / 720.0) * r;
  d a3 = (1.0 / 5040.0) + (1.0 / 40320.0) * r;
  d a4 = (1.0 / 362880.0) + (1.0 / 3628800.0) * r;
  d a5 = (1.0 / 39916800.0) + (1.0 / 479001600.0) * r;
  d a6 = dsplat(1.0 / 6227020800.0);
  d b0 = a0 + a1 * r2, b1 = a2 + a3 * r2, b2 = a4 + a5 * r2;
  d d0 = b0 + b1 * r4, d1 = b2 + a6 * r4;
  return (d0 + d1 * r8) * r;
}
#define LN2_HI 0x1.62e42fee00000p-1
#define LN2_LO 1.9082149292705877e-10
#define INV_LN2 1.4426950408889634
#define EXP_MAX 709.782712893384
F d dpow2(d k) { return (d)((du)(k + (1023.0 + SHIFT)) << 52); }
F d dexp(d x) {
  d c = dclamp(x, -746.0, EXP_MAX);
  d k = (c * INV_LN2 + SHIFT) - SHIFT;
  d r = (c - k * LN2_HI) - k * LN2_LO;
  d k1 = (0.5 * k + SHIFT) - SHIFT;
  d e = (dpoly(r) + 1.0) * dpow2(k1) * dpow2(k - k1);
  return dpick(x < dsplat(-745.2), dsplat(0.0), dpick(x > dsplat(EXP_MAX), dsplat(__builtin_inf()), e));
}
F d dexpm1(d x) {
  d c = dclamp(x, -41.0, 709.0);
  d k = (c * INV_LN2 + SHIFT) - SHIFT;
  d r = (c - k * LN2_HI) - k * LN2_LO;
  d p = dpoly(r), t = dpow2(k);
  d e = t * p + (t - 1.0);
  return dpick(x < dsplat(-40.0), dsplat(-1.0), dpick(x > dsplat(EXP_MAX), dsplat(__builtin_inf()), e));
}
/* ln x as math.rs's `ln` (fdlibm's log without branches): x = 2^k (1 + f)
   with 1 + f in [sqrt(2)/2, sqrt(2)), a subnormal x scaled by 2^54 first;
   k is exact either way, here from its bits (a conversion of 64-bit
   integers AVX2 lacks). */
#define SQRT_HALF_BITS 0x3fe6a09e00000000ULL
F d dlog(d x) {
  dm tiny = x < dsplat(0x1p-1022);
  d xs = dpick(tiny, x * 0x1p54, x);
  du b = (du)xs + (0x3ff0000000000000ULL - SQRT_HALF_BITS);
  d k = ((d)(((b >> 52) & 0x7ffULL) | 0x4330000000000000ULL) - 0x1p52) - 1023.0;
  k = k - dpick(tiny, dsplat(54.0), dsplat(0.0));
  d f = (d)((b & 0x000fffffffffffffULL) + SQRT_HALF_BITS) - 1.0;
  d hfsq = 0.5 * f * f;
  d s = f / (2.0 + f);
  d z = s * s, w = z * z;
  d t1 = w * (0x1.999999997fa04p-2 + w * (0x1.c71c51d8e78afp-3 + w * 0x1.39a09d078c69fp-3));
  d t2 = z * (0x1.5555555555593p-1 + w * (0x1.2492494229359p-2 + w * (0x1.7466496cb03dep-3 + w * 0x1.2f112df3e5244p-3)));
  d r = t2 + t1;
  d val = k * LN2_HI - ((hfsq - (s * (hfsq + r) + k * LN2_LO)) - f);
  d neg = dpick(x == dsplat(0.0), dsplat(-__builtin_inf()), dsplat(__builtin_nan("")));
  return dpick(x > dsplat(0.0), dpick(x == dsplat(__builtin_inf()), x, val), neg);
}
/* ln of one value: lane 0 of the vector form. */
F double dlog1(double x) { return dlog(dsplat(x))[0]; }
/* sin x (cos x where c0) as math.rs's `trig`: fdlibm's medium reduction
   x = n pi/2 + (y0 + yt), its later rounds taken only where the one before
   cancelled (a vector takes them where any lane needs them, each lane then
   keeping the round fdlibm stops at: the same bits as one value alone), the
   kernel for n's quadrant, signed by it; beyond TRIG_MAX, at +-inf and NaN,
   the C library's. The kernels are written once for doubles and vectors. */
#define INV_PIO2 0x1.45f306dc9c883p-1
#define KSIN(x, y) ({ __typeof__(x) z_ = (x) * (x), zz_ = z_ * z_, v_ = z_ * (x); \
  __typeof__(x) r_ = 0x1.111111110f8a6p-7 + z_ * (-0x1.a01a019c161d5p-13 + z_ * 0x1.71de357b1fe7dp-19) \
    + z_ * zz_ * (-0x1.ae5e68a2b9cebp-26 + z_ * 0x1.5d93a5acfd57cp-33); \
  (x) - ((z_ * (0.5 * (y) - v_ * r_) - (y)) - v_ * -0x1.5555555555549p-3); })
#define KCOS(x, y) ({ __typeof__(x) z_ = (x) * (x), zz_ = z_ * z_; \
  __typeof__(x) r_ = z_ * (0x1.555555555554cp-5 + z_ * (-0x1.6c16c16c15177p-10 + z_ * 0x1.a01a019cb1590p-16)) \
    + zz_ * zz_ * (-0x1.27e4f809c52adp-22 + z_ * (0x1.1ee9ebdb4b1c4p-29 + z_ * -0x1.8fae9be8838d4p-37)); \
  __typeof__(x) h_ = 0.5 * z_, w_ = 1.0 - h_; \
  w_ + (((1.0 - w_) - h_) + (z_ * r_ - (x) * (y))); })
/* Round 2 (PIO2_2) or 3 (PIO2_3) of the reduction from round k-1's r. */
#define ROUND(r, w, y0, n, P, PT) do { __typeof__(r) t_ = (r), p_ = (n) * (P); \
  (r) = t_ - p_; (w) = (n) * (PT) - ((t_ - (r)) - p_); (y0) = (r) - (w); } while (0)
F long long sexpo(double x) { union { double f; unsigned long long u; } b = {x}; return (b.u >> 52) & 0x7ff; }
F double strig(double x, int c0) {
  if (!(fabs(x) <= TRIG_MAX)) return c0 ? cos(x) : sin(x);
  union { double f; unsigned long long u; } sh = {x * INV_PIO2 + SHIFT};
  double n = sh.f - SHIFT;
  long long j = sexpo(x);
  double r = x - n * 0x1.921fb54400000p+0, w = n * 0x1.0b4611a626331p-34, y0 = r - w;
  if (j - sexpo(y0) > 16) {
    ROUND(r, w, y0, n, 0x1.0b4611a600000p-34, 0x1.3198a2e037073p-69);
    if (j - sexpo(y0) > 49) ROUND(r, w, y0, n, 0x1.3198a2e000000p-69, 0x1.b839a252049c1p-104);
  }
  double yt = (r - y0) - w;
  unsigned long long q = (sh.u & 3) + (unsigned long long)c0;
  double v = (q & 1) ? KCOS(y0, yt) : KSIN(y0, yt);
  return (q & 2) ? -v : v;
}
F dm dexpo(d x) { return (dm)(((du)x >> 52) & 0x7ffULL); }
F d dtrig(d x, int c0) {
  d shifted = x * INV_PIO2 + SHIFT;
  d n = shifted - SHIFT;
  dm j = dexpo(x);
  d r = x - n * 0x1.921fb54400000p+0, w = n * 0x1.0b4611a626331p-34, y0 = r - w;
  dm one = j - dexpo(y0) <= 16;
  dm ok = (d)((du)x & 0x7fffffffffffffffULL) <= dsplat(TRIG_MAX);
  long long rare = 0;
  for (int l = 0; l < DW; l++) rare |= ~one[l] | ~ok[l];
  if (rare) {
    d r2 = r, w2 = w, y2 = y0;
    ROUND(r2, w2, y2, n, 0x1.0b4611a600000p-34, 0x1.3198a2e037073p-69);
    d r3 = r2, w3 = w2, y3 = y2;
    ROUND(r3, w3, y3, n, 0x1.3198a2e000000p-69, 0x1.b839a252049c1p-104);
    dm two = j - dexpo(y2) <= 49;
    r = dpick(one, r, dpick(two, r2, r3));
    w = dpick(one, w, dpick(two, w2, w3));
    y0 = dpick(one, y0, dpick(two, y2, y3));
  }
  d yt = (r - y0) - w;
  du q = ((du)shifted & 3ULL) + (unsigned long long)c0;
  d val = dpick((dm)((q & 1ULL) != 0), KCOS(y0, yt), KSIN(y0, yt));
  val = (d)((du)val ^ ((q & 2ULL) << 62));
  if (rare)
    for (int l = 0; l < DW; l++)
      if (!ok[l]) val[l] = c0 ? cos(x[l]) : sin(x[l]);
  return val;
}
/* Built once each, not inlined at every use: inlined, they took the C
   compiler two thirds as long again on the quarter car's lanes, a cost each
   short job pays. */
static __attribute__((noinline)) d dsin(d x) { return dtrig(x, 0); }
static __attribute__((noinline)) d dcos(d x) { return dtrig(x, 1); }
static __attribute__((noinline)) double dsin1(double x) { return strig(x, 0); }
static __attribute__((noinline)) double dcos1(double x) { return strig(x, 1); }
"#;

/// One run's f64 arithmetic, for the derivative a redone step takes
/// (`rig_deriv1`): the f64 `eˣ` and `eˣ − 1` above, and Rust's `min`, `max`,
/// comparisons and select, on scalars.
const SCALAR: &str = r#"/* e^x and e^x - 1 of one value: lane 0 of the vector forms (as cheap as
   a scalar copy of them on a vector unit, and the same arithmetic). */
F double sexp(double x) { return dexp(dsplat(x))[0]; }
F double sexpm1(double x) { return dexpm1(dsplat(x))[0]; }
F double ssel(double c, double a, double b) { return c != 0.0 ? a : b; }
F double sle(double a, double b) { return a <= b ? 1.0 : 0.0; }
F double seq(double a, double b) { return a == b ? 1.0 : 0.0; }
F double smin(double a, double b) { return a != a ? b : b != b ? a : a < b ? a : b; }
F double smax(double a, double b) { return a != a ? b : b != b ? a : a > b ? a : b; }
F double sabs(double a) { return fabs(a); }
F double slog(double a) { return dlog1(a); }
F double ssin(double a) { return dsin1(a); }
F double scos(double a) { return dcos1(a); }
"#;

/// Rust's select, `<=`, `==` (1 or 0), `min` and `max` (a NaN operand gives
/// the other) on vectors of type `ty` with masks of type `mask`, as
/// `{p}sel`, `{p}le`, … built on the vectors' `splat` and `pick`: the lanes'
/// (`v…` on `v`) and the redo's (`w…` on the f64 `d`) from one text.
fn vector_ops(p: char, ty: &str, mask: &str, splat: &str, pick: &str) -> String {
    format!(
        "F {ty} {p}sel({ty} c, {ty} a, {ty} b) {{ return {pick}(c != {splat}(0.0), a, b); }}
F {ty} {p}le({ty} a, {ty} b) {{ return ({ty})((a <= b) & ({mask}){splat}(1.0)); }}
F {ty} {p}eq({ty} a, {ty} b) {{ return ({ty})((a == b) & ({mask}){splat}(1.0)); }}
/* Rust's f64::min / f64::max: a NaN operand gives the other. */
F {ty} {p}min({ty} a, {ty} b) {{ {ty} r = {pick}(a < b, a, b); r = {pick}(a != a, b, r); return {pick}(b != b, a, r); }}
F {ty} {p}max({ty} a, {ty} b) {{ {ty} r = {pick}(a > b, a, b); r = {pick}(a != a, b, r); return {pick}(b != b, a, r); }}
"
    )
}

/// The f64 vector arithmetic of [`REDO`] (its derivative and event functions
/// call it as `w…`, whatever the lanes' arithmetic), and its switches' tests.
const REDO_OPS: &str = r#"#define FIRED (MAX_EVENTS + 1)
F d wabs(d a) { return (d)((du)a & 0x7fffffffffffffffULL); }
F d wexp(d x) { return dexp(x); }
F d wexpm1(d x) { return dexpm1(x); }
F d wlog(d x) { return dlog(x); }
F d wsin(d x) { return dsin(x); }
F d wcos(d x) { return dcos(x); }
F int anyw(dm k) { long long a = 0; for (int l = 0; l < DW; l++) a |= k[l]; return a != 0; }
/* Transition i's event function oriented so that >= 0 is past its switch. */
F d orientw(int i, d g) { return DIR_UP[i] ? g : -g; }
/* Transition::fires: past the switch at the end, and on the armed side at
   the start or further past. */
F dm firesw(int i, d g0, d g1) {
  d v0 = orientw(i, g0), v1 = orientw(i, g1), zero = dsplat(0.0);
  return (v1 >= zero) & (~(v0 >= zero) | (v1 > v0));
}
"#;

/// Steps redone in C with their switches located (`rig_redo`), for the
/// lanes of one f64 vector ([`crate::compile::exec::lanes::LaneRunner`]
/// hands it those of its lanes past a switch):
/// [`crate::compile::exec::events::EventStepper`]'s `step_known` and
/// `locate_crossing` step for step in every lane, so each lane's bits are
/// the scalar reference's. The lanes go through the same loop together,
/// each with its own times, switches and search, a lane that is done kept
/// as it is by a mask: a rig driven through a switch takes its lanes past
/// it a few steps apart (the quarter car: 3.8 of 16 lanes in a step that
/// has any; with friction, 7.9), which one lane at a time took half of
/// their CPU jobs.
const REDO: &str = r#"/* rig_redo: the steps of the lanes in `act` (a bit per lane of a d vector)
   redone with their switches located, as EventStepper::step_known
   (src/compile/exec/events.rs) redoes each, step for step and in its order
   of operations, so each lane's bits are the same: R the lanes' register
   file (a row of DW lanes per register; regimes and held states set, the regimes
   each switch sets written there), y the steps' starts in and their ends
   out (NS rows), yend where the lanes' plain steps ended. Each lane l's
   fired switches' times and transitions go into ft and fi from
   l * (MAX_EVENTS + 1), their count into nf[l], and chat[l] is set where
   its step took more than MAX_EVENTS. */
/* One RK4 step of the lanes in `act` (the others' y kept). */
static void rk4w(const dr *R, d t, d h, d *y, d *k0, int known, dm act) {
  d k1[NS], k2[NS], k3[NS], tmp[NS];
  if (!known) derivw(R, t, y, k0);
  for (int i = 0; i < NS; i++) tmp[i] = y[i] + 0.5 * h * k0[i];
  derivw(R, t + 0.5 * h, tmp, k1);
  for (int i = 0; i < NS; i++) tmp[i] = y[i] + 0.5 * h * k1[i];
  derivw(R, t + 0.5 * h, tmp, k2);
  for (int i = 0; i < NS; i++) tmp[i] = y[i] + h * k2[i];
  derivw(R, t + h, tmp, k3);
  for (int i = 0; i < NS; i++)
    y[i] = dpick(act, y[i] + h / 6.0 * (k0[i] + 2.0 * k1[i] + 2.0 * k2[i] + k3[i]), y[i]);
}
/* locate_crossing on the Hermite interpolant of each lane's step [ta, ta + h],
   for transition tr in the lanes of `act`. */
static d locatew(const dr *R, int tr, d ta, d h, const d *start, const d *f0, const d *y1,
                 const d *fe, d v0, d v1, dm act) {
  const d zero = dsplat(0.0), one = dsplat(1.0), half = dsplat(0.5);
  /* Past at the start (or NaN): 0. */
  const dm searched = act & ~((v0 >= zero) | (v0 != v0));
  dm go = searched, exact = (dm){0};
  d lo = zero, hi = one, vlo = v0, vhi = v1, w0 = dsplat(2.0), w1 = w0, w2 = w0, at = zero;
  dm up = (dm){0}, down = (dm){0};
  const d tol = dsplat(LOCATE_TOL), nudge = dsplat(0.5 * LOCATE_TOL);
  d x[NS], g[NT];
  for (int it = 0; it < LOCATE_ITER; it++) {
    d w = hi - lo;
    go &= ~((w <= tol) | (w != w));
    if (!anyw(go)) break;
    d secant = lo + w * (vlo / (vlo - vhi));
    d m = dpick((w > 0.5 * w0) | ~((lo <= secant) & (secant <= hi)), lo + 0.5 * w, secant);
    m = wmin(wmax(m, lo + nudge), hi - nudge);
    w0 = dpick(go, w1, w0); w1 = dpick(go, w2, w1); w2 = dpick(go, w, w2);
    d s2 = m * m, s3 = s2 * m;
    d h00 = 2.0 * s3 - 3.0 * s2 + 1.0, h10 = (s3 - 2.0 * s2 + m) * h;
    d h01 = -2.0 * s3 + 3.0 * s2, h11 = (s3 - s2) * h;
    for (int i = 0; i < NS; i++) x[i] = h00 * start[i] + h10 * f0[i] + h01 * y1[i] + h11 * fe[i];
    eventsw(R, ta + m * h, x, g);
    d vm = orientw(tr, g[tr]);
    dm hit = go & (vm == zero);
    at = dpick(hit, m, at); exact |= hit; go &= ~hit;
    dm past = go & (vm > zero), short_ = go & ~(vm > zero);
    d f = one - vm / dpick(past, vhi, vlo);
    f = dpick(f > zero, f, half);
    vlo = dpick(past & up, vlo * f, vlo);
    hi = dpick(past, m, hi); vhi = dpick(past, vm, vhi);
    vhi = dpick(short_ & down, vhi * f, vhi);
    lo = dpick(short_, m, lo); vlo = dpick(short_, vm, vlo);
    up = (up & ~short_) | past; down = (down & ~past) | short_;
  }
  return dpick(exact, at, dpick(searched, hi, zero));
}
void rig_redo(double *restrict Rio, double *restrict yio, const double *restrict yend, double t,
              double h, long act, double *ft, long *fi, long *nf, long *chat) {
  dr *R = (dr *)Rio;
  d y[NS], ye[NS], start[NS], k0[NS], fe[NS], y1[NS], gs[NT], ge[NT];
  __builtin_memcpy(y, yio, sizeof y);
  __builtin_memcpy(ye, yend, sizeof ye);
  dm live;
  for (int l = 0; l < DW; l++) { live[l] = (act >> l & 1) ? -1 : 0; nf[l] = 0; chat[l] = 0; }
  d ta = dsplat(t), rem = dsplat(h);
  int ev;
  for (ev = 0; ev <= MAX_EVENTS; ev++) {
    for (int i = 0; i < NS; i++) start[i] = y[i];
    eventsw(R, ta, y, gs);
    if (ev == 0) {
      derivw(R, ta, y, k0);
      for (int i = 0; i < NS; i++) y[i] = dpick(live, ye[i], y[i]);
    } else {
      rk4w(R, ta, rem, y, k0, 0, live);
    }
    eventsw(R, ta + rem, y, ge);
    dm hits[NT], any = (dm){0};
    for (int i = 0; i < NT; i++) any |= hits[i] = live & armedw(R, i) & firesw(i, gs[i], ge[i]);
    live &= any;
    if (!anyw(live)) break;
    derivw(R, ta + rem, y, fe);
    for (int i = 0; i < NS; i++) y1[i] = y[i];
    d best = dsplat(0.0);
    dm tr = ~(dm){0}, have = (dm){0};
    for (int i = 0; i < NT; i++) {
      if (!anyw(hits[i])) continue;
      d th = locatew(R, i, ta, rem, start, k0, y1, fe, orientw(i, gs[i]), orientw(i, ge[i]), hits[i]);
      dm take = hits[i] & (~have | (th < best));
      best = dpick(take, th, best);
      tr = (take & (dm){DALL(i)}) | (~take & tr);
      have |= take;
    }
    d s = best * rem;
    for (int i = 0; i < NS; i++) y[i] = dpick(live, start[i], y[i]);
    rk4w(R, ta, s, y, k0, 1, live);
    for (int i = 0; i < NT; i++) R[MODE[i]] = dpick(live & (tr == (dm){DALL(i)}), dsplat(TO[i]), R[MODE[i]]);
    d tf = ta + s;
    for (int l = 0; l < DW; l++)
      if (live[l]) { ft[l * FIRED + nf[l]] = tf[l]; fi[l * FIRED + nf[l]] = tr[l]; nf[l]++; }
    ta = dpick(live, tf, ta);
    rem = dpick(live, rem - s, rem);
    live &= rem > dsplat(0.0);
    if (!anyw(live)) break;
  }
  if (ev > MAX_EVENTS)
    for (int l = 0; l < DW; l++) chat[l] = live[l] != 0;
  __builtin_memcpy(yio, y, sizeof y);
}
"#;

/// The lane type `v` of [`Arith::F64`]: the f64 vector, `DW` lanes of a
/// register-file row (`q` counts vectors along the row).
const F64_LANES: &str = r#"typedef d v; typedef dm m; typedef du u;
#define WV DW
#define LD(A, i) (((v *)&(A)[(i) * BLOCKS])[q])
#define ST(A, i, x) (((v *)&(A)[(i) * BLOCKS])[q] = (x))
#define LDP LD
#define STP ST
#define KEEP(B, A, i) (((v *)&(B)[(i) * BLOCKS])[q] = ((v *)&(A)[(i) * BLOCKS])[q])
F v vabs(v a) { return (v)((u)a & 0x7fffffffffffffffULL); }
F v vexp(v x) { return dexp(x); }
F v vexpm1(v x) { return dexpm1(x); }
F v vlog(v x) { return dlog(x); }
F v vsin(v x) { return dsin(x); }
F v vcos(v x) { return dcos(x); }
"#;

/// The lane type `v` of [`Arith::F32`]: twice the f64 vector's lanes, read
/// from two f64 vectors of a register-file row and rounded to f32 (the
/// shuffles that join and split them are [`f32_lanes`]'s).
const F32_LANES: &str = r#"typedef float v __attribute__((vector_size(VBYTES)));
typedef int m __attribute__((vector_size(VBYTES)));
typedef unsigned int u __attribute__((vector_size(VBYTES)));
typedef float h __attribute__((vector_size(VBYTES / 2)));
#define WV (2 * DW)
F v join(d lo, d hi) {
  return __builtin_shufflevector(__builtin_convertvector(lo, h), __builtin_convertvector(hi, h), JOIN);
}
F void split(v x, d *lo, d *hi) {
  *lo = __builtin_convertvector(__builtin_shufflevector(x, x, LO), d);
  *hi = __builtin_convertvector(__builtin_shufflevector(x, x, HI), d);
}
#define LD(A, i) join(((d *)&(A)[(i) * BLOCKS])[2 * q], ((d *)&(A)[(i) * BLOCKS])[2 * q + 1])
#define ST(A, i, x) split((x), &((d *)&(A)[(i) * BLOCKS])[2 * q], &((d *)&(A)[(i) * BLOCKS])[2 * q + 1])
/* A per-run constant's row and a state's hold their lanes as f32, packed at
   the row's start: read and written without rounding from f64 and back (a
   fifth of the tensile rig's step where the states were f64 rows). */
#define LDP(A, i) (((v *)&(A)[(i) * BLOCKS])[q])
#define STP(A, i, x) (((v *)&(A)[(i) * BLOCKS])[q] = (x))
/* State row i of A copied into B: the step's start kept for a redone step. */
#define KEEP(B, A, i) (((v *)&(B)[(i) * BLOCKS])[q] = ((v *)&(A)[(i) * BLOCKS])[q])
F v fsplat(float x) { return (v){VALL(x)}; }
/* ln, sin and cos in f64 on each half, rounded once. */
F v vlog(v x) { d lo, hi; split(x, &lo, &hi); return join(dlog(lo), dlog(hi)); }
F v vsin(v x) { d lo, hi; split(x, &lo, &hi); return join(dsin(lo), dsin(hi)); }
F v vcos(v x) { d lo, hi; split(x, &lo, &hi); return join(dcos(lo), dcos(hi)); }
F v fpick(m k, v a, v b) { return (v)((k & (m)a) | (~k & (m)b)); }
F v vabs(v a) { return (v)((u)a & 0x7fffffffu); }
/* e^x and e^x - 1 in f32: the f64 forms' reduction with f32 constants
   (1.5·2^23 shift, ln 2 split as 0x1.62e4p-1 + rest) and the degree-8
   Taylor polynomial of e^r - 1, |r| <= ln2/2 (truncation below 1e-8). */
#define FSHIFT 12582912.0f
F v fpoly(v r) {
  v r2 = r * r, r4 = r2 * r2;
  v a0 = 1.0f + 0.5f * r, a1 = (1.0f / 6.0f) + (1.0f / 24.0f) * r;
  v a2 = (1.0f / 120.0f) + (1.0f / 720.0f) * r, a3 = (1.0f / 5040.0f) + (1.0f / 40320.0f) * r;
  return ((a0 + a1 * r2) + (a2 + a3 * r2) * r4) * r;
}
F void freduce(v c, v *k, v *r) {
  *k = (c * 1.44269504f + FSHIFT) - FSHIFT;
  *r = (c - *k * 0x1.62e4p-1f) - *k * 0x1.7f7d1cp-20f;
}
F v fpow2(v k) { return (v)((u)(k + (127.0f + FSHIFT)) << 23); }
F v vexp(v x) {
  v c = fpick(x < fsplat(-104.0f), fsplat(-104.0f), x); c = fpick(c > fsplat(88.7f), fsplat(88.7f), c);
  v k, r; freduce(c, &k, &r);
  v k1 = (0.5f * k + FSHIFT) - FSHIFT;
  v e = (fpoly(r) + 1.0f) * fpow2(k1) * fpow2(k - k1);
  return fpick(x < fsplat(-103.9f), fsplat(0.0f), fpick(x > fsplat(88.72f), fsplat(__builtin_inff()), e));
}
F v vexpm1(v x) {
  v c = fpick(x < fsplat(-18.0f), fsplat(-18.0f), x); c = fpick(c > fsplat(88.0f), fsplat(88.0f), c);
  v k, r; freduce(c, &k, &r);
  v p = fpoly(r), t = fpow2(k);
  return fpick(x < fsplat(-17.0f), fsplat(-1.0f), fpick(x > fsplat(88.72f), fsplat(__builtin_inff()), t * p + (t - 1.0f)));
}
"#;

/// What both lane types share, written on `v`: `NQ(nb)` vectors cover
/// blocks `0..nb` (the f32 vector of 64 bytes also the block after an odd
/// last one, still below `BLOCKS`).
const LANE_OPS: &str = r#"#define NQ(nb) (((nb) * 8 + WV - 1) / WV)
F v splat(double x) { return (v){VALL(x)}; }
F v pick(m k, v a, v b) { return (v)((k & (m)a) | (~k & (m)b)); }
/* log, sin and cos of a uniform vector (every lane alike, as in the
   instructions hoisted out of rig_rk4's loop): one call, its value in every
   lane. */
F v ulog(v a) { return splat(dlog1(a[0])); }
F v usin(v a) { return splat(dsin(dsplat(a[0]))[0]); }
F v ucos(v a) { return splat(dcos(dsplat(a[0]))[0]); }
"#;

/// One instruction as a C statement on the register locals `rN`, with the
/// helpers for vectors (`p = 'v'`) or scalars (`'s'`).
fn statement(dest: Reg, op: &Op, p: char) -> String {
    let r = |i: Id| format!("r{i}");
    let e = match *op {
        Op::Add(a, b) => format!("{} + {}", r(a), r(b)),
        Op::Sub(a, b) => format!("{} - {}", r(a), r(b)),
        Op::Mul(a, b) => format!("{} * {}", r(a), r(b)),
        Op::Div(a, b) => format!("{} / {}", r(a), r(b)),
        Op::Min(a, b) => format!("{p}min({}, {})", r(a), r(b)),
        Op::Max(a, b) => format!("{p}max({}, {})", r(a), r(b)),
        Op::Le(a, b) => format!("{p}le({}, {})", r(a), r(b)),
        Op::Eq(a, b) => format!("{p}eq({}, {})", r(a), r(b)),
        Op::Neg(a) => format!("-{}", r(a)),
        Op::Abs(a) => format!("{p}abs({})", r(a)),
        Op::Exp(a) => format!("{p}exp({})", r(a)),
        Op::Expm1(a) => format!("{p}expm1({})", r(a)),
        Op::Ln(a) => format!("{p}log({})", r(a)),
        Op::Sin(a) => format!("{p}sin({})", r(a)),
        Op::Cos(a) => format!("{p}cos({})", r(a)),
        Op::Select(c, a, b) => format!("{p}sel({}, {}, {})", r(c), r(a), r(b)),
        Op::Const(_) | Op::In(_) => unreachable!("registers filled before the list runs"),
    };
    format!("    r{dest} = {e};\n")
}

/// The registers `list` reads before it writes them (its inputs), in order.
fn inputs(list: &List) -> Vec<Reg> {
    let mut written = std::collections::HashSet::new();
    let mut read = vec![];
    for ins in &list.code {
        for o in operands(&ins.op) {
            let o = o as Reg;
            if !written.contains(&o) && !read.contains(&o) {
                read.push(o);
            }
        }
        written.insert(ins.dest);
    }
    for &root in &list.roots {
        if !written.contains(&root) && !read.contains(&root) {
            read.push(root);
        }
    }
    read
}

/// Declares every register local the code uses, of type `ty`.
fn declare(out: &mut String, code: &LaneCode, ty: &str) {
    let _ = writeln!(
        out,
        "    {ty} {};",
        (0..code.registers)
            .map(|i| format!("r{i}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    // Unread locals are fine; silence the compiler about them.
    let _ = writeln!(out, "    (void)r0;");
}

/// Loads input register `reg` of block `b`, unless it is the time or a table
/// (`time`: its C value; `tables`: register → C value).
fn load(
    out: &mut String,
    reg: Reg,
    time: &str,
    code: &LaneCode,
    tables: &dyn Fn(Reg) -> Option<String>,
) {
    let src = if reg == code.time {
        format!("splat({time})")
    } else if let Some(t) = tables(reg) {
        format!("splat({t})")
    } else if packed(code, reg) {
        format!("LDP(R, {reg})")
    } else {
        format!("LD(R, {reg})")
    };
    let _ = writeln!(out, "    r{reg} = {src};");
}

/// Whether register `reg`'s row holds its lanes packed (as f32, at the
/// row's start, in [`Arith::F32`] code; as f64 rows otherwise): a state's or
/// a per-run constant's ([`crate::compile::exec::lanes::LaneRunner`] packs
/// them so).
fn packed(code: &LaneCode, reg: Reg) -> bool {
    (reg as usize) < code.slopes.len() || code.constants.iter().any(|&(_, r)| r == reg)
}

/// Stores register `reg` into its row.
fn store(out: &mut String, code: &LaneCode, reg: Reg) {
    let st = if packed(code, reg) { "STP" } else { "ST" };
    let _ = writeln!(out, "    {st}(R, {reg}, r{reg});");
}

/// Table values per derivative in `rig_rk4`'s `tab` (one past the highest
/// table any list reads).
pub fn table_stride(code: &LaneCode) -> usize {
    [
        &code.deriv,
        &code.events,
        &code.report,
        &code.measured,
        &code.update,
    ]
    .iter()
    .flat_map(|l| l.tables.iter().map(|&(k, _)| k as usize + 1))
    .max()
    .unwrap_or(0)
}

/// Which instructions of `list` depend on time, tables and per-run
/// constants alone (not on a state or a mode), and the constant registers
/// those read.
fn time_only(code: &LaneCode, list: &List) -> (Vec<bool>, Vec<Reg>) {
    let constant: std::collections::HashSet<Reg> = code.constants.iter().map(|&(_, r)| r).collect();
    let mut tc = vec![false; code.registers];
    tc[code.time as usize] = true;
    for &(_, reg) in &list.tables {
        tc[reg as usize] = true;
    }
    for &reg in &constant {
        tc[reg as usize] = true;
    }
    let mut reads = vec![];
    let flags = list
        .code
        .iter()
        .map(|ins| {
            let ops = operands(&ins.op);
            let t = ops.iter().all(|&o| tc[o as usize]);
            if t {
                for &o in &ops {
                    let o = o as Reg;
                    if constant.contains(&o) && !reads.contains(&o) {
                        reads.push(o);
                    }
                }
            }
            tc[ins.dest as usize] = t;
            t
        })
        .collect();
    (flags, reads)
}

/// The instructions of the derivative and of the event list that depend on
/// time, tables and per-run constants alone, and the constant registers
/// those read. Where every lane holds the same value in each of those
/// constants (as when the drive's parameters are fixed), `rig_rk4` computes
/// these instructions once per call instead of once per block.
#[derive(Debug, Clone)]
pub struct Hoistable {
    /// Per derivative instruction.
    pub deriv: Vec<bool>,
    /// Per event-list instruction (the list `rig_rk4` runs at the step's
    /// end).
    pub events: Vec<bool>,
    /// The constant registers either reads.
    pub reads: Vec<Reg>,
}

/// [`Hoistable`] of `code`.
pub fn hoistable(code: &LaneCode) -> Hoistable {
    let (deriv, mut reads) = time_only(code, &code.deriv);
    let (events, more) = time_only(code, &code.events);
    for r in more {
        if !reads.contains(&r) {
            reads.push(r);
        }
    }
    Hoistable {
        deriv,
        events,
        reads,
    }
}

/// The time and table registers `list` reads (the derivative's at its
/// `stage`, 0–3; the event list's at the step's end, stage 3): `tt[stage]`
/// and that stage's row of `tab`.
fn stage_inputs(s: &mut String, code: &LaneCode, list: &List, stage: usize) {
    if list.uses_time {
        let _ = writeln!(s, "    r{} = splat(tt[{stage}]);", code.time);
    }
    for &(k, reg) in &list.tables {
        let _ = writeln!(
            s,
            "    r{reg} = splat(tab[{} + {k}]);",
            stage * table_stride(code)
        );
    }
}

/// `list`'s hoisted instructions (`hoisted[j]`) at `stage`, each result kept
/// in the vector `<keep><j>`.
fn hoist(s: &mut String, code: &LaneCode, list: &List, hoisted: &[bool], stage: usize, keep: &str) {
    stage_inputs(s, code, list, stage);
    for (j, ins) in list.code.iter().enumerate().filter(|&(j, _)| hoisted[j]) {
        // Every lane holds the same value here: the C library's functions
        // are called once, not lane by lane.
        s.push_str(&match ins.op {
            Op::Ln(a) => format!("    r{} = ulog(r{a});\n", ins.dest),
            Op::Sin(a) => format!("    r{} = usin(r{a});\n", ins.dest),
            Op::Cos(a) => format!("    r{} = ucos(r{a});\n", ins.dest),
            _ => statement(ins.dest, &ins.op, 'v'),
        });
        let _ = writeln!(s, "    v {keep}{j} = r{};", ins.dest);
    }
}

/// The stage whose hoisted values stage `stage` of `rig_rk4` reads: the
/// second and third stages are both at `t + h/2` (`tt[1] == tt[2]`, as the
/// lane runner passes them), so the third reads the second's.
fn hoisted_stage(stage: usize) -> usize {
    if stage == 2 { 1 } else { stage }
}

/// `rig_rk4`'s loop over blocks: hoisted (`Some`: which instructions were
/// computed before the loop, into `u{stage}_{index}` and `e_{index}`) or
/// not.
fn rk4_loop(s: &mut String, code: &LaneCode, hoisted: Option<&Hoistable>) {
    let n = code.slopes.len();
    s.push_str("  for (long q = 0; q < NQ(nb); q++) {\n");
    declare(s, code, "v");
    let _ = writeln!(
        s,
        "    v {};",
        (0..n)
            .map(|i| format!("y{i}, a{i}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    for reg in inputs(&code.deriv) {
        if from_rows(code, &code.deriv, reg) {
            load(s, reg, "", code, &|_| None);
        }
    }
    for i in 0..n {
        let _ = writeln!(s, "    y{i} = LDP(R, {i}); KEEP(Y, R, {i}); r{i} = y{i};");
    }
    for stage in 0..4 {
        stage_inputs(s, code, &code.deriv, stage);
        for (j, ins) in code.deriv.code.iter().enumerate() {
            if hoisted.is_some_and(|h| h.deriv[j]) {
                let _ = writeln!(s, "    r{} = u{}_{j};", ins.dest, hoisted_stage(stage));
            } else {
                s.push_str(&statement(ins.dest, &ins.op, 'v'));
            }
        }
        for &(state, copy) in &code.slope_copies {
            let _ = writeln!(s, "    r{copy} = r{state};");
        }
        for (i, &k) in code.slopes.iter().enumerate() {
            let _ = match stage {
                0 => writeln!(s, "    a{i} = r{k}; r{i} = y{i} + CH * r{k};"),
                1 => writeln!(s, "    a{i} = a{i} + TWO * r{k}; r{i} = y{i} + CH * r{k};"),
                2 => writeln!(s, "    a{i} = a{i} + TWO * r{k}; r{i} = y{i} + H * r{k};"),
                _ => writeln!(s, "    r{i} = y{i} + H6 * (a{i} + r{k});"),
            };
        }
    }
    for i in 0..n {
        let _ = writeln!(s, "    STP(R, {i}, r{i});");
    }
    step_end_events(s, code, hoisted.map(|h| &h.events[..]));
    s.push_str("  }\n");
}

/// The event list at the step's end (`tt[3]`, table row 3), run in
/// `rig_rk4`'s loop on the new state while it is still in registers, and
/// the lanes past an armed switch marked in `ks[q]` (its roots are not
/// stored: nothing after the step reads them, where the interpreter's hit
/// test reads them from the register file). `hoisted`: which instructions
/// were computed before the loop, into `e_{index}`.
fn step_end_events(s: &mut String, code: &LaneCode, hoisted: Option<&[bool]>) {
    let list = &code.events;
    if list.code.is_empty() && code.armed.is_empty() {
        return;
    }
    s.push_str("    /* the event functions at the step's end */\n");
    stage_inputs(s, code, &code.events, 3);
    let held = still_loaded(code);
    for reg in event_loads(code) {
        if from_rows(code, list, reg) && !held.contains(&reg) {
            load(s, reg, "", code, &|_| None);
        }
    }
    for (j, ins) in list.code.iter().enumerate() {
        if hoisted.is_some_and(|h| h[j]) {
            let _ = writeln!(s, "    r{} = e_{j};", ins.dest);
        } else {
            s.push_str(&statement(ins.dest, &ins.op, 'v'));
        }
    }
    hit_test(s, code);
}

/// The registers `rig_rk4`'s loop loaded at its start for the derivative
/// that still hold their rows at the step's end (no instruction or slope copy
/// of the four stages wrote them): the event list reads them from there,
/// not from the register file again (an f32 lane's load converts from f64).
fn still_loaded(code: &LaneCode) -> Vec<Reg> {
    let written: std::collections::HashSet<Reg> = code
        .deriv
        .code
        .iter()
        .map(|ins| ins.dest)
        .chain(code.slope_copies.iter().map(|&(_, copy)| copy))
        .collect();
    inputs(&code.deriv)
        .into_iter()
        .filter(|&reg| from_rows(code, &code.deriv, reg) && !written.contains(&reg))
        .collect()
}

/// Whether `list`'s input `reg` is loaded from the register file: not a
/// state (the step's own registers), the time or one of the list's tables
/// (from `tt` and `tab`).
fn from_rows(code: &LaneCode, list: &List, reg: Reg) -> bool {
    (reg as usize) >= code.slopes.len()
        && reg != code.time
        && !list.tables.iter().any(|&(_, r)| r == reg)
}

/// The registers the event list and its hit test read: its inputs, the
/// armed switches' modes and their guards' modes.
fn event_loads(code: &LaneCode) -> Vec<Reg> {
    let mut loads = inputs(&code.events);
    let guarded = code.guards.iter().flatten().map(|&(m, _)| m);
    for mode in code.armed.iter().map(|a| a.0).chain(guarded) {
        if !loads.contains(&mode) {
            loads.push(mode);
        }
    }
    loads
}

/// `LaneRunner`'s hit test on the event functions in their registers: a bit
/// per lane armed and past its switch (`Direction::past`), added to `hits`.
fn hit_test(s: &mut String, code: &LaneCode) {
    s.push_str("    m k = (m){0};\n");
    for ((&(mode, from, dir), &g), guard) in
        code.armed.iter().zip(&code.events.roots).zip(&code.guards)
    {
        let past = match dir {
            Direction::Up => ">=",
            Direction::Down => "<=",
        };
        let guard: String = guard
            .iter()
            .map(|&(m, v)| format!(" & (r{m} == splat({v:?}))"))
            .collect();
        let _ = writeln!(
            s,
            "    k |= (r{mode} == splat({from:?})) & (r{g} {past} splat(0.0)){guard};"
        );
    }
    s.push_str("    ks[q] = k; kor |= k;\n");
}

/// Stores the lanes the hit test marked in `hit`: a byte per block, a bit
/// per lane, none past block `nb`. The masks of the loop's vectors are
/// turned into bits only where one lane of them is marked (a step with no
/// switch, most of them, reduces one vector instead of one per vector).
const STORE_HITS: &str = "  if (lanebits(kor)) for (long q = 0; q < NQ(nb); q++) hits |= lanebits(ks[q]) << (q * WV);\n  if (nb < BLOCKS) hits &= (1ULL << (nb * 8)) - 1;\n  for (int i = 0; i < BLOCKS; i++) hit[i] = hits >> (8 * i);\n";

/// `a, a + 1, …, b − 1`, as a shuffle's indices.
fn indices(a: usize, b: usize) -> String {
    (a..b).map(|i| i.to_string()).collect::<Vec<_>>().join(", ")
}

/// `lanebits`: a bit per lane of mask `k` (lanes of `lanes`), with the lanes
/// OR-ed together by rotations instead of read one by one through memory
/// (which stalls on the store of the whole vector before it).
fn lane_bits(lanes: usize) -> String {
    let powers = (0..lanes)
        .map(|l| (1u64 << l).to_string())
        .collect::<Vec<_>>()
        .join(", ");
    let mut s = format!("F unsigned long long lanebits(m k) {{\n  k &= (m){{{powers}}};\n");
    let mut half = lanes / 2;
    while half > 0 {
        let rotated: Vec<String> = (0..lanes)
            .map(|l| ((l + half) % lanes).to_string())
            .collect();
        let _ = writeln!(
            s,
            "  k |= __builtin_shufflevector(k, k, {});",
            rotated.join(", ")
        );
        half /= 2;
    }
    s.push_str("  return (unsigned long long)(unsigned)k[0];\n}\n");
    s
}

/// Whether `rig_redo` is built for `code`: it has switches, and its
/// derivative and event functions read no table (whose values the caller
/// computes at each time).
pub fn redoes(code: &LaneCode) -> bool {
    !code.events.roots.is_empty() && code.deriv.tables.is_empty() && code.events.tables.is_empty()
}

/// `list` as a C function of one run or one vector of runs: `head` (its
/// signature and opening), a local of type `ty.0` per register, each input
/// from `input`, the instructions with the helpers of prefix `ty.1`
/// ([`statement`]), and the roots into `out`.
fn list_fn(
    s: &mut String,
    code: &LaneCode,
    list: &List,
    head: &str,
    ty: (&str, char),
    input: &dyn Fn(Reg) -> String,
) {
    let _ = writeln!(s, "{head}");
    declare(s, code, ty.0);
    for &reg in &inputs(list) {
        let _ = writeln!(s, "    r{reg} = {};", input(reg));
    }
    for ins in &list.code {
        s.push_str(&statement(ins.dest, &ins.op, ty.1));
    }
    for (i, &root) in list.roots.iter().enumerate() {
        let _ = writeln!(s, "    out[{i}] = r{root};");
    }
    s.push_str("}\n");
}

/// `rig_redo` ([`REDO`]) for `code`, with its switches' tables (what arms
/// each, `armedw`; which way it fires, the regime register it sets and the
/// value), and its derivative and event functions on f64 vectors (`derivw`,
/// `eventsw`: the states from `x`, every other input from its row of `R`).
fn redo(s: &mut String, code: &LaneCode) {
    use crate::compile::exec::events::{LOCATE_ITERATIONS, LOCATE_TOLERANCE, MAX_EVENTS_PER_STEP};
    let list = |v: Vec<String>| v.join(", ");
    let _ = writeln!(
        s,
        "#define NS {}\n#define NT {}\n#define MAX_EVENTS {MAX_EVENTS_PER_STEP}\n#define LOCATE_ITER {LOCATE_ITERATIONS}\n#define LOCATE_TOL {LOCATE_TOLERANCE:?}",
        code.slopes.len(),
        code.events.roots.len()
    );
    let _ = writeln!(
        s,
        "static const int DIR_UP[NT] = {{{}}};\nstatic const long MODE[NT] = {{{}}};\nstatic const double TO[NT] = {{{}}};",
        list(
            code.armed
                .iter()
                .map(|a| u8::from(a.2 == Direction::Up).to_string())
                .collect()
        ),
        list(code.armed.iter().map(|a| a.0.to_string()).collect()),
        list(code.sets.iter().map(|v| format!("{v:?}")).collect())
    );
    s.push_str("/* A row of the caller's register file: DW lanes, only 8-byte aligned. */\ntypedef double dr __attribute__((vector_size(VBYTES), aligned(8)));\n/* The lanes of R where transition i is armed: its variable at its value, its guard held. */\nstatic dm armedw(const dr *R, int i) {\n  switch (i) {\n");
    for (i, (&(mode, from, _), guard)) in code.armed.iter().zip(&code.guards).enumerate() {
        let guard: String = guard
            .iter()
            .map(|&(m, v)| format!(" & (R[{m}] == dsplat({v:?}))"))
            .collect();
        let _ = writeln!(
            s,
            "  case {i}: return (R[{mode}] == dsplat({from:?})){guard};"
        );
    }
    s.push_str("  }\n  return (dm){0};\n}\n");
    s.push_str(&vector_ops('w', "d", "dm", "dsplat", "dpick"));
    s.push_str(REDO_OPS);
    let states = code.slopes.len();
    for (name, list) in [("derivw", &code.deriv), ("eventsw", &code.events)] {
        let head = format!(
            "static __attribute__((noinline)) void {name}(const dr *restrict R, d t, const d *restrict x, d *restrict out) {{\n    (void)t; (void)x;"
        );
        list_fn(s, code, list, &head, ("d", 'w'), &|reg| {
            if reg == code.time {
                "t".to_string()
            } else if (reg as usize) < states {
                format!("x[{reg}]")
            } else {
                format!("R[{reg}]")
            }
        });
    }
    s.push_str(REDO);
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
    use crate::compile::exec::math::TRIG_REDUCED_UP_TO;
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
    let table_regs: Vec<(u32, Reg)> = [
        &code.deriv,
        &code.events,
        &code.report,
        &code.measured,
        &code.update,
    ]
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
    use crate::compile::exec::math;

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
        let built = std::process::Command::new(crate::compile::back::native::compiler())
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
