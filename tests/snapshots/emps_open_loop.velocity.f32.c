#define BLOCKS 8
#define VBYTES 64
#define DALL(x) x, x, x, x, x, x, x, x
#define TRIG_MAX 1000000.0
#include <math.h>
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
#define VALL(x) x, x, x, x, x, x, x, x, x, x, x, x, x, x, x, x
#define JOIN 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15
#define LO 0, 1, 2, 3, 4, 5, 6, 7
#define HI 8, 9, 10, 11, 12, 13, 14, 15
typedef float v __attribute__((vector_size(VBYTES)));
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
#define NQ(nb) (((nb) * 8 + WV - 1) / WV)
F v splat(double x) { return (v){VALL(x)}; }
F v pick(m k, v a, v b) { return (v)((k & (m)a) | (~k & (m)b)); }
/* log, sin and cos of a uniform vector (every lane alike, as in the
   instructions hoisted out of rig_rk4's loop): one call, its value in every
   lane. */
F v ulog(v a) { return splat(dlog1(a[0])); }
F v usin(v a) { return splat(dsin(dsplat(a[0]))[0]); }
F v ucos(v a) { return splat(dcos(dsplat(a[0]))[0]); }
F v vsel(v c, v a, v b) { return pick(c != splat(0.0), a, b); }
F v vle(v a, v b) { return (v)((a <= b) & (m)splat(1.0)); }
F v veq(v a, v b) { return (v)((a == b) & (m)splat(1.0)); }
/* Rust's f64::min / f64::max: a NaN operand gives the other. */
F v vmin(v a, v b) { v r = pick(a < b, a, b); r = pick(a != a, b, r); return pick(b != b, a, r); }
F v vmax(v a, v b) { v r = pick(a > b, a, b); r = pick(a != a, b, r); return pick(b != b, a, r); }
F unsigned long long lanebits(m k) {
  k &= (m){1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384, 32768};
  k |= __builtin_shufflevector(k, k, 8, 9, 10, 11, 12, 13, 14, 15, 0, 1, 2, 3, 4, 5, 6, 7);
  k |= __builtin_shufflevector(k, k, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 0, 1, 2, 3);
  k |= __builtin_shufflevector(k, k, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 0, 1);
  k |= __builtin_shufflevector(k, k, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 0);
  return (unsigned long long)(unsigned)k[0];
}
void rig_rk4(blk *restrict R, blk *restrict Y, long nb, const double *tt, const double *tab, double ch, double h, double h6, long hoist, unsigned char *hit) {
  const v CH = splat(ch), H = splat(h), H6 = splat(h6), TWO = splat(2.0);
  unsigned long long hits = 0;
  m kor = (m){0}, ks[(BLOCKS * 8 + WV - 1) / WV];
  for (long q = 0; q < NQ(nb); q++) {
    v r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17;
    (void)r0;
    v y0, a0, y1, a1, y2, a2, y3, a3;
    r5 = LDP(R, 5);
    r6 = LDP(R, 6);
    r7 = LDP(R, 7);
    r8 = LDP(R, 8);
    r9 = LDP(R, 9);
    r10 = LDP(R, 10);
    r11 = LDP(R, 11);
    r12 = LDP(R, 12);
    r13 = LDP(R, 13);
    y0 = LDP(R, 0); KEEP(Y, R, 0); r0 = y0;
    y1 = LDP(R, 1); KEEP(Y, R, 1); r1 = y1;
    y2 = LDP(R, 2); KEEP(Y, R, 2); r2 = y2;
    y3 = LDP(R, 3); KEEP(Y, R, 3); r3 = y3;
    r15 = r2 - r3;
    r16 = r5 * r15;
    r15 = r15 / r6;
    r15 = r7 * r15;
    r15 = vmin(r15, r8);
    r15 = vmax(r15, r9);
    r15 = vexpm1(r15);
    r17 = r15 + r7;
    r17 = r15 / r17;
    r17 = r10 * r17;
    r15 = r11 - r16;
    r15 = r15 - r17;
    r15 = r15 - r12;
    r15 = r15 * r13;
    r17 = r16 + r17;
    r17 = r17 + r12;
    a0 = r2; r0 = y0 + CH * r2;
    a1 = r3; r1 = y1 + CH * r3;
    a2 = r15; r2 = y2 + CH * r15;
    a3 = r17; r3 = y3 + CH * r17;
    r15 = r2 - r3;
    r16 = r5 * r15;
    r15 = r15 / r6;
    r15 = r7 * r15;
    r15 = vmin(r15, r8);
    r15 = vmax(r15, r9);
    r15 = vexpm1(r15);
    r17 = r15 + r7;
    r17 = r15 / r17;
    r17 = r10 * r17;
    r15 = r11 - r16;
    r15 = r15 - r17;
    r15 = r15 - r12;
    r15 = r15 * r13;
    r17 = r16 + r17;
    r17 = r17 + r12;
    a0 = a0 + TWO * r2; r0 = y0 + CH * r2;
    a1 = a1 + TWO * r3; r1 = y1 + CH * r3;
    a2 = a2 + TWO * r15; r2 = y2 + CH * r15;
    a3 = a3 + TWO * r17; r3 = y3 + CH * r17;
    r15 = r2 - r3;
    r16 = r5 * r15;
    r15 = r15 / r6;
    r15 = r7 * r15;
    r15 = vmin(r15, r8);
    r15 = vmax(r15, r9);
    r15 = vexpm1(r15);
    r17 = r15 + r7;
    r17 = r15 / r17;
    r17 = r10 * r17;
    r15 = r11 - r16;
    r15 = r15 - r17;
    r15 = r15 - r12;
    r15 = r15 * r13;
    r17 = r16 + r17;
    r17 = r17 + r12;
    a0 = a0 + TWO * r2; r0 = y0 + H * r2;
    a1 = a1 + TWO * r3; r1 = y1 + H * r3;
    a2 = a2 + TWO * r15; r2 = y2 + H * r15;
    a3 = a3 + TWO * r17; r3 = y3 + H * r17;
    r15 = r2 - r3;
    r16 = r5 * r15;
    r15 = r15 / r6;
    r15 = r7 * r15;
    r15 = vmin(r15, r8);
    r15 = vmax(r15, r9);
    r15 = vexpm1(r15);
    r17 = r15 + r7;
    r17 = r15 / r17;
    r17 = r10 * r17;
    r15 = r11 - r16;
    r15 = r15 - r17;
    r15 = r15 - r12;
    r15 = r15 * r13;
    r17 = r16 + r17;
    r17 = r17 + r12;
    r0 = y0 + H6 * (a0 + r2);
    r1 = y1 + H6 * (a1 + r3);
    r2 = y2 + H6 * (a2 + r15);
    r3 = y3 + H6 * (a3 + r17);
    STP(R, 0, r0);
    STP(R, 1, r1);
    STP(R, 2, r2);
    STP(R, 3, r3);
  }
  if (lanebits(kor)) for (long q = 0; q < NQ(nb); q++) hits |= lanebits(ks[q]) << (q * WV);
  if (nb < BLOCKS) hits &= (1ULL << (nb * 8)) - 1;
  for (int i = 0; i < BLOCKS; i++) hit[i] = hits >> (8 * i);
}
/* e^x and e^x - 1 of one value: lane 0 of the vector forms (as cheap as
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
static __attribute__((noinline)) void deriv1_(const double *restrict R, double t, const double *tab, double *restrict out) {
    (void)t; (void)tab;
    double r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17;
    (void)r0;
    r2 = R[2];
    r3 = R[3];
    r5 = R[5];
    r6 = R[6];
    r7 = R[7];
    r8 = R[8];
    r9 = R[9];
    r10 = R[10];
    r11 = R[11];
    r12 = R[12];
    r13 = R[13];
    r15 = r2 - r3;
    r16 = r5 * r15;
    r15 = r15 / r6;
    r15 = r7 * r15;
    r15 = smin(r15, r8);
    r15 = smax(r15, r9);
    r15 = sexpm1(r15);
    r17 = r15 + r7;
    r17 = r15 / r17;
    r17 = r10 * r17;
    r15 = r11 - r16;
    r15 = r15 - r17;
    r15 = r15 - r12;
    r15 = r15 * r13;
    r17 = r16 + r17;
    r17 = r17 + r12;
    out[0] = r2;
    out[1] = r3;
    out[2] = r15;
    out[3] = r17;
}
static __attribute__((noinline)) void events1_(const double *restrict R, double t, const double *tab, double *restrict out) {
    (void)t; (void)tab;
    double r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17;
    (void)r0;
}
void rig_deriv1(const double *restrict R, double t, const double *tab, double *restrict out) { deriv1_(R, t, tab, out); }
void rig_events1(const double *restrict R, double t, const double *tab, double *restrict out) { events1_(R, t, tab, out); }
void rig_report(blk *restrict R, long nb, double t, const double *tab) {
  for (long q = 0; q < NQ(nb); q++) {
    v r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17;
    (void)r0;
    r2 = LDP(R, 2);
    r3 = LDP(R, 3);
    r6 = LDP(R, 6);
    r7 = LDP(R, 7);
    r8 = LDP(R, 8);
    r9 = LDP(R, 9);
    r10 = LDP(R, 10);
    r14 = LDP(R, 14);
    r1 = LDP(R, 1);
    r0 = LDP(R, 0);
    r15 = r2 - r3;
    r15 = r15 / r6;
    r15 = r7 * r15;
    r15 = vmin(r15, r8);
    r15 = vmax(r15, r9);
    r15 = vexpm1(r15);
    r16 = r15 + r7;
    r16 = r15 / r16;
    r16 = r10 * r16;
    r15 = r14 * r1;
    r15 = r0 + r15;
    r17 = r14 * r3;
    r17 = r2 + r17;
    ST(R, 15, r15);
    ST(R, 17, r17);
    ST(R, 16, r16);
    STP(R, 0, r0);
    STP(R, 1, r1);
    STP(R, 2, r2);
    STP(R, 3, r3);
  }
}
void rig_measured(blk *restrict R, long nb, double t, const double *tab) {
  for (long q = 0; q < NQ(nb); q++) {
    v r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17;
    (void)r0;
    r14 = LDP(R, 14);
    r1 = LDP(R, 1);
    r0 = LDP(R, 0);
    r15 = r14 * r1;
    r15 = r0 + r15;
    ST(R, 15, r15);
  }
}
void rig_update(blk *restrict R, long nb, double t, const double *tab) {
  for (long q = 0; q < NQ(nb); q++) {
    v r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17;
    (void)r0;
  }
}
