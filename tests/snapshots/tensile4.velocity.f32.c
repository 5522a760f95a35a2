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
  if (hoist) {
  const long q = 0;
    v r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17, r18, r19, r20, r21, r22, r23, r24, r25, r26, r27, r28, r29, r30, r31, r32, r33, r34, r35, r36, r37, r38, r39, r40, r41, r42, r43, r44, r45, r46, r47, r48, r49, r50, r51;
    (void)r0;
    r12 = LDP(R, 12);
    r13 = LDP(R, 13);
    r14 = LDP(R, 14);
    r15 = LDP(R, 15);
    r16 = LDP(R, 16);
    r8 = splat(tt[0]);
    r44 = vle(r8, r12);
    v u0_0 = r44;
    r45 = r13 * r8;
    v u0_1 = r45;
    r45 = -r45;
    v u0_2 = r45;
    r45 = vexpm1(r45);
    v u0_3 = r45;
    r46 = r14 * r8;
    v u0_4 = r46;
    r47 = r15 * r45;
    v u0_5 = r47;
    r47 = r46 + r47;
    v u0_6 = r47;
    r45 = r14 * r45;
    v u0_7 = r45;
    r45 = -r45;
    v u0_8 = r45;
    r47 = vsel(r16, r46, r47);
    v u0_9 = r47;
    r45 = vsel(r16, r14, r45);
    v u0_10 = r45;
    r47 = vsel(r44, r12, r47);
    v u0_11 = r47;
    r45 = vsel(r44, r12, r45);
    v u0_12 = r45;
    r8 = splat(tt[1]);
    r44 = vle(r8, r12);
    v u1_0 = r44;
    r45 = r13 * r8;
    v u1_1 = r45;
    r45 = -r45;
    v u1_2 = r45;
    r45 = vexpm1(r45);
    v u1_3 = r45;
    r46 = r14 * r8;
    v u1_4 = r46;
    r47 = r15 * r45;
    v u1_5 = r47;
    r47 = r46 + r47;
    v u1_6 = r47;
    r45 = r14 * r45;
    v u1_7 = r45;
    r45 = -r45;
    v u1_8 = r45;
    r47 = vsel(r16, r46, r47);
    v u1_9 = r47;
    r45 = vsel(r16, r14, r45);
    v u1_10 = r45;
    r47 = vsel(r44, r12, r47);
    v u1_11 = r47;
    r45 = vsel(r44, r12, r45);
    v u1_12 = r45;
    r8 = splat(tt[3]);
    r44 = vle(r8, r12);
    v u3_0 = r44;
    r45 = r13 * r8;
    v u3_1 = r45;
    r45 = -r45;
    v u3_2 = r45;
    r45 = vexpm1(r45);
    v u3_3 = r45;
    r46 = r14 * r8;
    v u3_4 = r46;
    r47 = r15 * r45;
    v u3_5 = r47;
    r47 = r46 + r47;
    v u3_6 = r47;
    r45 = r14 * r45;
    v u3_7 = r45;
    r45 = -r45;
    v u3_8 = r45;
    r47 = vsel(r16, r46, r47);
    v u3_9 = r47;
    r45 = vsel(r16, r14, r45);
    v u3_10 = r45;
    r47 = vsel(r44, r12, r47);
    v u3_11 = r47;
    r45 = vsel(r44, r12, r45);
    v u3_12 = r45;
    r8 = splat(tt[3]);
    r44 = vle(r8, r12);
    v e_0 = r44;
    r45 = r13 * r8;
    v e_1 = r45;
    r45 = -r45;
    v e_2 = r45;
    r45 = vexpm1(r45);
    v e_3 = r45;
    r46 = r14 * r8;
    v e_4 = r46;
    r45 = r15 * r45;
    v e_5 = r45;
    r45 = r46 + r45;
    v e_6 = r45;
    r45 = vsel(r16, r46, r45);
    v e_7 = r45;
    r45 = vsel(r44, r12, r45);
    v e_8 = r45;
  for (long q = 0; q < NQ(nb); q++) {
    v r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17, r18, r19, r20, r21, r22, r23, r24, r25, r26, r27, r28, r29, r30, r31, r32, r33, r34, r35, r36, r37, r38, r39, r40, r41, r42, r43, r44, r45, r46, r47, r48, r49, r50, r51;
    (void)r0;
    v y0, a0, y1, a1, y2, a2, y3, a3, y4, a4, y5, a5, y6, a6, y7, a7;
    r12 = LDP(R, 12);
    r13 = LDP(R, 13);
    r14 = LDP(R, 14);
    r15 = LDP(R, 15);
    r16 = LDP(R, 16);
    r17 = LDP(R, 17);
    r9 = LD(R, 9);
    r18 = LDP(R, 18);
    r19 = LDP(R, 19);
    r20 = LDP(R, 20);
    r21 = LDP(R, 21);
    r22 = LDP(R, 22);
    r23 = LDP(R, 23);
    r24 = LDP(R, 24);
    r25 = LDP(R, 25);
    r26 = LDP(R, 26);
    r27 = LDP(R, 27);
    r10 = LD(R, 10);
    r28 = LDP(R, 28);
    r29 = LDP(R, 29);
    r30 = LDP(R, 30);
    r31 = LDP(R, 31);
    r11 = LD(R, 11);
    r32 = LDP(R, 32);
    r33 = LDP(R, 33);
    r34 = LDP(R, 34);
    r35 = LDP(R, 35);
    r36 = LDP(R, 36);
    r37 = LDP(R, 37);
    r38 = LDP(R, 38);
    r39 = LDP(R, 39);
    r40 = LDP(R, 40);
    r41 = LDP(R, 41);
    y0 = LDP(R, 0); KEEP(Y, R, 0); r0 = y0;
    y1 = LDP(R, 1); KEEP(Y, R, 1); r1 = y1;
    y2 = LDP(R, 2); KEEP(Y, R, 2); r2 = y2;
    y3 = LDP(R, 3); KEEP(Y, R, 3); r3 = y3;
    y4 = LDP(R, 4); KEEP(Y, R, 4); r4 = y4;
    y5 = LDP(R, 5); KEEP(Y, R, 5); r5 = y5;
    y6 = LDP(R, 6); KEEP(Y, R, 6); r6 = y6;
    y7 = LDP(R, 7); KEEP(Y, R, 7); r7 = y7;
    r8 = splat(tt[0]);
    r44 = u0_0;
    r45 = u0_1;
    r45 = u0_2;
    r45 = u0_3;
    r46 = u0_4;
    r47 = u0_5;
    r47 = u0_6;
    r45 = u0_7;
    r45 = u0_8;
    r47 = u0_9;
    r45 = u0_10;
    r47 = u0_11;
    r45 = u0_12;
    r44 = r17 * r0;
    r46 = veq(r9, r18);
    r48 = vsel(r46, r19, r20);
    r48 = r48 * r4;
    r48 = r44 + r48;
    r44 = r1 - r0;
    r49 = r5 - r4;
    r50 = r21 * r44;
    r50 = r50 + r22;
    r50 = r50 * r44;
    r50 = r50 + r23;
    r50 = r50 * r44;
    r50 = r50 + r24;
    r50 = r50 * r44;
    r50 = r50 + r25;
    r50 = r50 * r44;
    r50 = r50 + r26;
    r44 = r27 * r44;
    r51 = veq(r10, r18);
    r51 = vsel(r51, r50, r44);
    r49 = r28 * r49;
    r49 = r51 + r49;
    r49 = vsel(r46, r12, r49);
    r46 = r2 - r1;
    r51 = r6 - r5;
    r46 = r29 * r46;
    r51 = r30 * r51;
    r51 = r46 + r51;
    r47 = r47 - r2;
    r45 = r45 - r6;
    r47 = r47 - r31;
    r46 = veq(r11, r18);
    r44 = r32 * r47;
    r44 = vexpm1(r44);
    r44 = r33 * r44;
    r50 = r34 * r47;
    r50 = r44 + r50;
    r44 = r47 - r35;
    r44 = r36 * r44;
    r44 = r37 + r44;
    r47 = vle(r47, r35);
    r47 = vsel(r47, r50, r44);
    r45 = r38 * r45;
    r45 = r47 + r45;
    r45 = vsel(r46, r45, r12);
    r48 = r49 - r48;
    r48 = r48 * r39;
    r49 = r51 - r49;
    r49 = r49 * r40;
    r45 = r45 - r51;
    r45 = r45 * r41;
    a0 = r4; r0 = y0 + CH * r4;
    a1 = r5; r1 = y1 + CH * r5;
    a2 = r6; r2 = y2 + CH * r6;
    a3 = r12; r3 = y3 + CH * r12;
    a4 = r48; r4 = y4 + CH * r48;
    a5 = r49; r5 = y5 + CH * r49;
    a6 = r45; r6 = y6 + CH * r45;
    a7 = r12; r7 = y7 + CH * r12;
    r8 = splat(tt[1]);
    r44 = u1_0;
    r45 = u1_1;
    r45 = u1_2;
    r45 = u1_3;
    r46 = u1_4;
    r47 = u1_5;
    r47 = u1_6;
    r45 = u1_7;
    r45 = u1_8;
    r47 = u1_9;
    r45 = u1_10;
    r47 = u1_11;
    r45 = u1_12;
    r44 = r17 * r0;
    r46 = veq(r9, r18);
    r48 = vsel(r46, r19, r20);
    r48 = r48 * r4;
    r48 = r44 + r48;
    r44 = r1 - r0;
    r49 = r5 - r4;
    r50 = r21 * r44;
    r50 = r50 + r22;
    r50 = r50 * r44;
    r50 = r50 + r23;
    r50 = r50 * r44;
    r50 = r50 + r24;
    r50 = r50 * r44;
    r50 = r50 + r25;
    r50 = r50 * r44;
    r50 = r50 + r26;
    r44 = r27 * r44;
    r51 = veq(r10, r18);
    r51 = vsel(r51, r50, r44);
    r49 = r28 * r49;
    r49 = r51 + r49;
    r49 = vsel(r46, r12, r49);
    r46 = r2 - r1;
    r51 = r6 - r5;
    r46 = r29 * r46;
    r51 = r30 * r51;
    r51 = r46 + r51;
    r47 = r47 - r2;
    r45 = r45 - r6;
    r47 = r47 - r31;
    r46 = veq(r11, r18);
    r44 = r32 * r47;
    r44 = vexpm1(r44);
    r44 = r33 * r44;
    r50 = r34 * r47;
    r50 = r44 + r50;
    r44 = r47 - r35;
    r44 = r36 * r44;
    r44 = r37 + r44;
    r47 = vle(r47, r35);
    r47 = vsel(r47, r50, r44);
    r45 = r38 * r45;
    r45 = r47 + r45;
    r45 = vsel(r46, r45, r12);
    r48 = r49 - r48;
    r48 = r48 * r39;
    r49 = r51 - r49;
    r49 = r49 * r40;
    r45 = r45 - r51;
    r45 = r45 * r41;
    a0 = a0 + TWO * r4; r0 = y0 + CH * r4;
    a1 = a1 + TWO * r5; r1 = y1 + CH * r5;
    a2 = a2 + TWO * r6; r2 = y2 + CH * r6;
    a3 = a3 + TWO * r12; r3 = y3 + CH * r12;
    a4 = a4 + TWO * r48; r4 = y4 + CH * r48;
    a5 = a5 + TWO * r49; r5 = y5 + CH * r49;
    a6 = a6 + TWO * r45; r6 = y6 + CH * r45;
    a7 = a7 + TWO * r12; r7 = y7 + CH * r12;
    r8 = splat(tt[2]);
    r44 = u1_0;
    r45 = u1_1;
    r45 = u1_2;
    r45 = u1_3;
    r46 = u1_4;
    r47 = u1_5;
    r47 = u1_6;
    r45 = u1_7;
    r45 = u1_8;
    r47 = u1_9;
    r45 = u1_10;
    r47 = u1_11;
    r45 = u1_12;
    r44 = r17 * r0;
    r46 = veq(r9, r18);
    r48 = vsel(r46, r19, r20);
    r48 = r48 * r4;
    r48 = r44 + r48;
    r44 = r1 - r0;
    r49 = r5 - r4;
    r50 = r21 * r44;
    r50 = r50 + r22;
    r50 = r50 * r44;
    r50 = r50 + r23;
    r50 = r50 * r44;
    r50 = r50 + r24;
    r50 = r50 * r44;
    r50 = r50 + r25;
    r50 = r50 * r44;
    r50 = r50 + r26;
    r44 = r27 * r44;
    r51 = veq(r10, r18);
    r51 = vsel(r51, r50, r44);
    r49 = r28 * r49;
    r49 = r51 + r49;
    r49 = vsel(r46, r12, r49);
    r46 = r2 - r1;
    r51 = r6 - r5;
    r46 = r29 * r46;
    r51 = r30 * r51;
    r51 = r46 + r51;
    r47 = r47 - r2;
    r45 = r45 - r6;
    r47 = r47 - r31;
    r46 = veq(r11, r18);
    r44 = r32 * r47;
    r44 = vexpm1(r44);
    r44 = r33 * r44;
    r50 = r34 * r47;
    r50 = r44 + r50;
    r44 = r47 - r35;
    r44 = r36 * r44;
    r44 = r37 + r44;
    r47 = vle(r47, r35);
    r47 = vsel(r47, r50, r44);
    r45 = r38 * r45;
    r45 = r47 + r45;
    r45 = vsel(r46, r45, r12);
    r48 = r49 - r48;
    r48 = r48 * r39;
    r49 = r51 - r49;
    r49 = r49 * r40;
    r45 = r45 - r51;
    r45 = r45 * r41;
    a0 = a0 + TWO * r4; r0 = y0 + H * r4;
    a1 = a1 + TWO * r5; r1 = y1 + H * r5;
    a2 = a2 + TWO * r6; r2 = y2 + H * r6;
    a3 = a3 + TWO * r12; r3 = y3 + H * r12;
    a4 = a4 + TWO * r48; r4 = y4 + H * r48;
    a5 = a5 + TWO * r49; r5 = y5 + H * r49;
    a6 = a6 + TWO * r45; r6 = y6 + H * r45;
    a7 = a7 + TWO * r12; r7 = y7 + H * r12;
    r8 = splat(tt[3]);
    r44 = u3_0;
    r45 = u3_1;
    r45 = u3_2;
    r45 = u3_3;
    r46 = u3_4;
    r47 = u3_5;
    r47 = u3_6;
    r45 = u3_7;
    r45 = u3_8;
    r47 = u3_9;
    r45 = u3_10;
    r47 = u3_11;
    r45 = u3_12;
    r44 = r17 * r0;
    r46 = veq(r9, r18);
    r48 = vsel(r46, r19, r20);
    r48 = r48 * r4;
    r48 = r44 + r48;
    r44 = r1 - r0;
    r49 = r5 - r4;
    r50 = r21 * r44;
    r50 = r50 + r22;
    r50 = r50 * r44;
    r50 = r50 + r23;
    r50 = r50 * r44;
    r50 = r50 + r24;
    r50 = r50 * r44;
    r50 = r50 + r25;
    r50 = r50 * r44;
    r50 = r50 + r26;
    r44 = r27 * r44;
    r51 = veq(r10, r18);
    r51 = vsel(r51, r50, r44);
    r49 = r28 * r49;
    r49 = r51 + r49;
    r49 = vsel(r46, r12, r49);
    r46 = r2 - r1;
    r51 = r6 - r5;
    r46 = r29 * r46;
    r51 = r30 * r51;
    r51 = r46 + r51;
    r47 = r47 - r2;
    r45 = r45 - r6;
    r47 = r47 - r31;
    r46 = veq(r11, r18);
    r44 = r32 * r47;
    r44 = vexpm1(r44);
    r44 = r33 * r44;
    r50 = r34 * r47;
    r50 = r44 + r50;
    r44 = r47 - r35;
    r44 = r36 * r44;
    r44 = r37 + r44;
    r47 = vle(r47, r35);
    r47 = vsel(r47, r50, r44);
    r45 = r38 * r45;
    r45 = r47 + r45;
    r45 = vsel(r46, r45, r12);
    r48 = r49 - r48;
    r48 = r48 * r39;
    r49 = r51 - r49;
    r49 = r49 * r40;
    r45 = r45 - r51;
    r45 = r45 * r41;
    r0 = y0 + H6 * (a0 + r4);
    r1 = y1 + H6 * (a1 + r5);
    r2 = y2 + H6 * (a2 + r6);
    r3 = y3 + H6 * (a3 + r12);
    r4 = y4 + H6 * (a4 + r48);
    r5 = y5 + H6 * (a5 + r49);
    r6 = y6 + H6 * (a6 + r45);
    r7 = y7 + H6 * (a7 + r12);
    STP(R, 0, r0);
    STP(R, 1, r1);
    STP(R, 2, r2);
    STP(R, 3, r3);
    STP(R, 4, r4);
    STP(R, 5, r5);
    STP(R, 6, r6);
    STP(R, 7, r7);
    /* the event functions at the step's end */
    r8 = splat(tt[3]);
    r42 = LDP(R, 42);
    r43 = LDP(R, 43);
    r44 = e_0;
    r45 = e_1;
    r45 = e_2;
    r45 = e_3;
    r46 = e_4;
    r45 = e_5;
    r45 = e_6;
    r45 = e_7;
    r45 = e_8;
    r44 = r1 - r0;
    r46 = r44 - r42;
    r44 = r44 - r43;
    r45 = r45 - r2;
    r45 = r45 - r31;
    m k = (m){0};
    k |= (r10 == splat(0.0)) & (r46 >= splat(0.0));
    k |= (r10 == splat(1.0)) & (r46 <= splat(0.0));
    k |= (r9 == splat(0.0)) & (r44 >= splat(0.0));
    k |= (r11 == splat(0.0)) & (r45 >= splat(0.0));
    k |= (r11 == splat(1.0)) & (r45 <= splat(0.0));
    ks[q] = k; kor |= k;
  }
  if (lanebits(kor)) for (long q = 0; q < NQ(nb); q++) hits |= lanebits(ks[q]) << (q * WV);
  if (nb < BLOCKS) hits &= (1ULL << (nb * 8)) - 1;
  for (int i = 0; i < BLOCKS; i++) hit[i] = hits >> (8 * i);
  return;
  }
  for (long q = 0; q < NQ(nb); q++) {
    v r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17, r18, r19, r20, r21, r22, r23, r24, r25, r26, r27, r28, r29, r30, r31, r32, r33, r34, r35, r36, r37, r38, r39, r40, r41, r42, r43, r44, r45, r46, r47, r48, r49, r50, r51;
    (void)r0;
    v y0, a0, y1, a1, y2, a2, y3, a3, y4, a4, y5, a5, y6, a6, y7, a7;
    r12 = LDP(R, 12);
    r13 = LDP(R, 13);
    r14 = LDP(R, 14);
    r15 = LDP(R, 15);
    r16 = LDP(R, 16);
    r17 = LDP(R, 17);
    r9 = LD(R, 9);
    r18 = LDP(R, 18);
    r19 = LDP(R, 19);
    r20 = LDP(R, 20);
    r21 = LDP(R, 21);
    r22 = LDP(R, 22);
    r23 = LDP(R, 23);
    r24 = LDP(R, 24);
    r25 = LDP(R, 25);
    r26 = LDP(R, 26);
    r27 = LDP(R, 27);
    r10 = LD(R, 10);
    r28 = LDP(R, 28);
    r29 = LDP(R, 29);
    r30 = LDP(R, 30);
    r31 = LDP(R, 31);
    r11 = LD(R, 11);
    r32 = LDP(R, 32);
    r33 = LDP(R, 33);
    r34 = LDP(R, 34);
    r35 = LDP(R, 35);
    r36 = LDP(R, 36);
    r37 = LDP(R, 37);
    r38 = LDP(R, 38);
    r39 = LDP(R, 39);
    r40 = LDP(R, 40);
    r41 = LDP(R, 41);
    y0 = LDP(R, 0); KEEP(Y, R, 0); r0 = y0;
    y1 = LDP(R, 1); KEEP(Y, R, 1); r1 = y1;
    y2 = LDP(R, 2); KEEP(Y, R, 2); r2 = y2;
    y3 = LDP(R, 3); KEEP(Y, R, 3); r3 = y3;
    y4 = LDP(R, 4); KEEP(Y, R, 4); r4 = y4;
    y5 = LDP(R, 5); KEEP(Y, R, 5); r5 = y5;
    y6 = LDP(R, 6); KEEP(Y, R, 6); r6 = y6;
    y7 = LDP(R, 7); KEEP(Y, R, 7); r7 = y7;
    r8 = splat(tt[0]);
    r44 = vle(r8, r12);
    r45 = r13 * r8;
    r45 = -r45;
    r45 = vexpm1(r45);
    r46 = r14 * r8;
    r47 = r15 * r45;
    r47 = r46 + r47;
    r45 = r14 * r45;
    r45 = -r45;
    r47 = vsel(r16, r46, r47);
    r45 = vsel(r16, r14, r45);
    r47 = vsel(r44, r12, r47);
    r45 = vsel(r44, r12, r45);
    r44 = r17 * r0;
    r46 = veq(r9, r18);
    r48 = vsel(r46, r19, r20);
    r48 = r48 * r4;
    r48 = r44 + r48;
    r44 = r1 - r0;
    r49 = r5 - r4;
    r50 = r21 * r44;
    r50 = r50 + r22;
    r50 = r50 * r44;
    r50 = r50 + r23;
    r50 = r50 * r44;
    r50 = r50 + r24;
    r50 = r50 * r44;
    r50 = r50 + r25;
    r50 = r50 * r44;
    r50 = r50 + r26;
    r44 = r27 * r44;
    r51 = veq(r10, r18);
    r51 = vsel(r51, r50, r44);
    r49 = r28 * r49;
    r49 = r51 + r49;
    r49 = vsel(r46, r12, r49);
    r46 = r2 - r1;
    r51 = r6 - r5;
    r46 = r29 * r46;
    r51 = r30 * r51;
    r51 = r46 + r51;
    r47 = r47 - r2;
    r45 = r45 - r6;
    r47 = r47 - r31;
    r46 = veq(r11, r18);
    r44 = r32 * r47;
    r44 = vexpm1(r44);
    r44 = r33 * r44;
    r50 = r34 * r47;
    r50 = r44 + r50;
    r44 = r47 - r35;
    r44 = r36 * r44;
    r44 = r37 + r44;
    r47 = vle(r47, r35);
    r47 = vsel(r47, r50, r44);
    r45 = r38 * r45;
    r45 = r47 + r45;
    r45 = vsel(r46, r45, r12);
    r48 = r49 - r48;
    r48 = r48 * r39;
    r49 = r51 - r49;
    r49 = r49 * r40;
    r45 = r45 - r51;
    r45 = r45 * r41;
    a0 = r4; r0 = y0 + CH * r4;
    a1 = r5; r1 = y1 + CH * r5;
    a2 = r6; r2 = y2 + CH * r6;
    a3 = r12; r3 = y3 + CH * r12;
    a4 = r48; r4 = y4 + CH * r48;
    a5 = r49; r5 = y5 + CH * r49;
    a6 = r45; r6 = y6 + CH * r45;
    a7 = r12; r7 = y7 + CH * r12;
    r8 = splat(tt[1]);
    r44 = vle(r8, r12);
    r45 = r13 * r8;
    r45 = -r45;
    r45 = vexpm1(r45);
    r46 = r14 * r8;
    r47 = r15 * r45;
    r47 = r46 + r47;
    r45 = r14 * r45;
    r45 = -r45;
    r47 = vsel(r16, r46, r47);
    r45 = vsel(r16, r14, r45);
    r47 = vsel(r44, r12, r47);
    r45 = vsel(r44, r12, r45);
    r44 = r17 * r0;
    r46 = veq(r9, r18);
    r48 = vsel(r46, r19, r20);
    r48 = r48 * r4;
    r48 = r44 + r48;
    r44 = r1 - r0;
    r49 = r5 - r4;
    r50 = r21 * r44;
    r50 = r50 + r22;
    r50 = r50 * r44;
    r50 = r50 + r23;
    r50 = r50 * r44;
    r50 = r50 + r24;
    r50 = r50 * r44;
    r50 = r50 + r25;
    r50 = r50 * r44;
    r50 = r50 + r26;
    r44 = r27 * r44;
    r51 = veq(r10, r18);
    r51 = vsel(r51, r50, r44);
    r49 = r28 * r49;
    r49 = r51 + r49;
    r49 = vsel(r46, r12, r49);
    r46 = r2 - r1;
    r51 = r6 - r5;
    r46 = r29 * r46;
    r51 = r30 * r51;
    r51 = r46 + r51;
    r47 = r47 - r2;
    r45 = r45 - r6;
    r47 = r47 - r31;
    r46 = veq(r11, r18);
    r44 = r32 * r47;
    r44 = vexpm1(r44);
    r44 = r33 * r44;
    r50 = r34 * r47;
    r50 = r44 + r50;
    r44 = r47 - r35;
    r44 = r36 * r44;
    r44 = r37 + r44;
    r47 = vle(r47, r35);
    r47 = vsel(r47, r50, r44);
    r45 = r38 * r45;
    r45 = r47 + r45;
    r45 = vsel(r46, r45, r12);
    r48 = r49 - r48;
    r48 = r48 * r39;
    r49 = r51 - r49;
    r49 = r49 * r40;
    r45 = r45 - r51;
    r45 = r45 * r41;
    a0 = a0 + TWO * r4; r0 = y0 + CH * r4;
    a1 = a1 + TWO * r5; r1 = y1 + CH * r5;
    a2 = a2 + TWO * r6; r2 = y2 + CH * r6;
    a3 = a3 + TWO * r12; r3 = y3 + CH * r12;
    a4 = a4 + TWO * r48; r4 = y4 + CH * r48;
    a5 = a5 + TWO * r49; r5 = y5 + CH * r49;
    a6 = a6 + TWO * r45; r6 = y6 + CH * r45;
    a7 = a7 + TWO * r12; r7 = y7 + CH * r12;
    r8 = splat(tt[2]);
    r44 = vle(r8, r12);
    r45 = r13 * r8;
    r45 = -r45;
    r45 = vexpm1(r45);
    r46 = r14 * r8;
    r47 = r15 * r45;
    r47 = r46 + r47;
    r45 = r14 * r45;
    r45 = -r45;
    r47 = vsel(r16, r46, r47);
    r45 = vsel(r16, r14, r45);
    r47 = vsel(r44, r12, r47);
    r45 = vsel(r44, r12, r45);
    r44 = r17 * r0;
    r46 = veq(r9, r18);
    r48 = vsel(r46, r19, r20);
    r48 = r48 * r4;
    r48 = r44 + r48;
    r44 = r1 - r0;
    r49 = r5 - r4;
    r50 = r21 * r44;
    r50 = r50 + r22;
    r50 = r50 * r44;
    r50 = r50 + r23;
    r50 = r50 * r44;
    r50 = r50 + r24;
    r50 = r50 * r44;
    r50 = r50 + r25;
    r50 = r50 * r44;
    r50 = r50 + r26;
    r44 = r27 * r44;
    r51 = veq(r10, r18);
    r51 = vsel(r51, r50, r44);
    r49 = r28 * r49;
    r49 = r51 + r49;
    r49 = vsel(r46, r12, r49);
    r46 = r2 - r1;
    r51 = r6 - r5;
    r46 = r29 * r46;
    r51 = r30 * r51;
    r51 = r46 + r51;
    r47 = r47 - r2;
    r45 = r45 - r6;
    r47 = r47 - r31;
    r46 = veq(r11, r18);
    r44 = r32 * r47;
    r44 = vexpm1(r44);
    r44 = r33 * r44;
    r50 = r34 * r47;
    r50 = r44 + r50;
    r44 = r47 - r35;
    r44 = r36 * r44;
    r44 = r37 + r44;
    r47 = vle(r47, r35);
    r47 = vsel(r47, r50, r44);
    r45 = r38 * r45;
    r45 = r47 + r45;
    r45 = vsel(r46, r45, r12);
    r48 = r49 - r48;
    r48 = r48 * r39;
    r49 = r51 - r49;
    r49 = r49 * r40;
    r45 = r45 - r51;
    r45 = r45 * r41;
    a0 = a0 + TWO * r4; r0 = y0 + H * r4;
    a1 = a1 + TWO * r5; r1 = y1 + H * r5;
    a2 = a2 + TWO * r6; r2 = y2 + H * r6;
    a3 = a3 + TWO * r12; r3 = y3 + H * r12;
    a4 = a4 + TWO * r48; r4 = y4 + H * r48;
    a5 = a5 + TWO * r49; r5 = y5 + H * r49;
    a6 = a6 + TWO * r45; r6 = y6 + H * r45;
    a7 = a7 + TWO * r12; r7 = y7 + H * r12;
    r8 = splat(tt[3]);
    r44 = vle(r8, r12);
    r45 = r13 * r8;
    r45 = -r45;
    r45 = vexpm1(r45);
    r46 = r14 * r8;
    r47 = r15 * r45;
    r47 = r46 + r47;
    r45 = r14 * r45;
    r45 = -r45;
    r47 = vsel(r16, r46, r47);
    r45 = vsel(r16, r14, r45);
    r47 = vsel(r44, r12, r47);
    r45 = vsel(r44, r12, r45);
    r44 = r17 * r0;
    r46 = veq(r9, r18);
    r48 = vsel(r46, r19, r20);
    r48 = r48 * r4;
    r48 = r44 + r48;
    r44 = r1 - r0;
    r49 = r5 - r4;
    r50 = r21 * r44;
    r50 = r50 + r22;
    r50 = r50 * r44;
    r50 = r50 + r23;
    r50 = r50 * r44;
    r50 = r50 + r24;
    r50 = r50 * r44;
    r50 = r50 + r25;
    r50 = r50 * r44;
    r50 = r50 + r26;
    r44 = r27 * r44;
    r51 = veq(r10, r18);
    r51 = vsel(r51, r50, r44);
    r49 = r28 * r49;
    r49 = r51 + r49;
    r49 = vsel(r46, r12, r49);
    r46 = r2 - r1;
    r51 = r6 - r5;
    r46 = r29 * r46;
    r51 = r30 * r51;
    r51 = r46 + r51;
    r47 = r47 - r2;
    r45 = r45 - r6;
    r47 = r47 - r31;
    r46 = veq(r11, r18);
    r44 = r32 * r47;
    r44 = vexpm1(r44);
    r44 = r33 * r44;
    r50 = r34 * r47;
    r50 = r44 + r50;
    r44 = r47 - r35;
    r44 = r36 * r44;
    r44 = r37 + r44;
    r47 = vle(r47, r35);
    r47 = vsel(r47, r50, r44);
    r45 = r38 * r45;
    r45 = r47 + r45;
    r45 = vsel(r46, r45, r12);
    r48 = r49 - r48;
    r48 = r48 * r39;
    r49 = r51 - r49;
    r49 = r49 * r40;
    r45 = r45 - r51;
    r45 = r45 * r41;
    r0 = y0 + H6 * (a0 + r4);
    r1 = y1 + H6 * (a1 + r5);
    r2 = y2 + H6 * (a2 + r6);
    r3 = y3 + H6 * (a3 + r12);
    r4 = y4 + H6 * (a4 + r48);
    r5 = y5 + H6 * (a5 + r49);
    r6 = y6 + H6 * (a6 + r45);
    r7 = y7 + H6 * (a7 + r12);
    STP(R, 0, r0);
    STP(R, 1, r1);
    STP(R, 2, r2);
    STP(R, 3, r3);
    STP(R, 4, r4);
    STP(R, 5, r5);
    STP(R, 6, r6);
    STP(R, 7, r7);
    /* the event functions at the step's end */
    r8 = splat(tt[3]);
    r42 = LDP(R, 42);
    r43 = LDP(R, 43);
    r44 = vle(r8, r12);
    r45 = r13 * r8;
    r45 = -r45;
    r45 = vexpm1(r45);
    r46 = r14 * r8;
    r45 = r15 * r45;
    r45 = r46 + r45;
    r45 = vsel(r16, r46, r45);
    r45 = vsel(r44, r12, r45);
    r44 = r1 - r0;
    r46 = r44 - r42;
    r44 = r44 - r43;
    r45 = r45 - r2;
    r45 = r45 - r31;
    m k = (m){0};
    k |= (r10 == splat(0.0)) & (r46 >= splat(0.0));
    k |= (r10 == splat(1.0)) & (r46 <= splat(0.0));
    k |= (r9 == splat(0.0)) & (r44 >= splat(0.0));
    k |= (r11 == splat(0.0)) & (r45 >= splat(0.0));
    k |= (r11 == splat(1.0)) & (r45 <= splat(0.0));
    ks[q] = k; kor |= k;
  }
  if (lanebits(kor)) for (long q = 0; q < NQ(nb); q++) hits |= lanebits(ks[q]) << (q * WV);
  if (nb < BLOCKS) hits &= (1ULL << (nb * 8)) - 1;
  for (int i = 0; i < BLOCKS; i++) hit[i] = hits >> (8 * i);
}
#define NS 8
#define NT 5
#define MAX_EVENTS 16
#define LOCATE_ITER 200
#define LOCATE_TOL 1e-12
static const int DIR_UP[NT] = {1, 0, 1, 1, 0};
static const long MODE[NT] = {10, 10, 9, 11, 11};
static const double TO[NT] = {1.0, 0.0, 1.0, 1.0, 0.0};
/* A row of the caller's register file: DW lanes, only 8-byte aligned. */
typedef double dr __attribute__((vector_size(VBYTES), aligned(8)));
/* The lanes of R where transition i is armed: its variable at its value, its guard held. */
static dm armedw(const dr *R, int i) {
  switch (i) {
  case 0: return (R[10] == dsplat(0.0));
  case 1: return (R[10] == dsplat(1.0));
  case 2: return (R[9] == dsplat(0.0));
  case 3: return (R[11] == dsplat(0.0));
  case 4: return (R[11] == dsplat(1.0));
  }
  return (dm){0};
}
F d wsel(d c, d a, d b) { return dpick(c != dsplat(0.0), a, b); }
F d wle(d a, d b) { return (d)((a <= b) & (dm)dsplat(1.0)); }
F d weq(d a, d b) { return (d)((a == b) & (dm)dsplat(1.0)); }
/* Rust's f64::min / f64::max: a NaN operand gives the other. */
F d wmin(d a, d b) { d r = dpick(a < b, a, b); r = dpick(a != a, b, r); return dpick(b != b, a, r); }
F d wmax(d a, d b) { d r = dpick(a > b, a, b); r = dpick(a != a, b, r); return dpick(b != b, a, r); }
#define FIRED (MAX_EVENTS + 1)
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
static __attribute__((noinline)) void derivw(const dr *restrict R, d t, const d *restrict x, d *restrict out) {
    (void)t; (void)x;
    d r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17, r18, r19, r20, r21, r22, r23, r24, r25, r26, r27, r28, r29, r30, r31, r32, r33, r34, r35, r36, r37, r38, r39, r40, r41, r42, r43, r44, r45, r46, r47, r48, r49, r50, r51;
    (void)r0;
    r8 = t;
    r12 = R[12];
    r13 = R[13];
    r14 = R[14];
    r15 = R[15];
    r16 = R[16];
    r17 = R[17];
    r0 = x[0];
    r9 = R[9];
    r18 = R[18];
    r19 = R[19];
    r20 = R[20];
    r4 = x[4];
    r1 = x[1];
    r5 = x[5];
    r21 = R[21];
    r22 = R[22];
    r23 = R[23];
    r24 = R[24];
    r25 = R[25];
    r26 = R[26];
    r27 = R[27];
    r10 = R[10];
    r28 = R[28];
    r2 = x[2];
    r6 = x[6];
    r29 = R[29];
    r30 = R[30];
    r31 = R[31];
    r11 = R[11];
    r32 = R[32];
    r33 = R[33];
    r34 = R[34];
    r35 = R[35];
    r36 = R[36];
    r37 = R[37];
    r38 = R[38];
    r39 = R[39];
    r40 = R[40];
    r41 = R[41];
    r44 = wle(r8, r12);
    r45 = r13 * r8;
    r45 = -r45;
    r45 = wexpm1(r45);
    r46 = r14 * r8;
    r47 = r15 * r45;
    r47 = r46 + r47;
    r45 = r14 * r45;
    r45 = -r45;
    r47 = wsel(r16, r46, r47);
    r45 = wsel(r16, r14, r45);
    r47 = wsel(r44, r12, r47);
    r45 = wsel(r44, r12, r45);
    r44 = r17 * r0;
    r46 = weq(r9, r18);
    r48 = wsel(r46, r19, r20);
    r48 = r48 * r4;
    r48 = r44 + r48;
    r44 = r1 - r0;
    r49 = r5 - r4;
    r50 = r21 * r44;
    r50 = r50 + r22;
    r50 = r50 * r44;
    r50 = r50 + r23;
    r50 = r50 * r44;
    r50 = r50 + r24;
    r50 = r50 * r44;
    r50 = r50 + r25;
    r50 = r50 * r44;
    r50 = r50 + r26;
    r44 = r27 * r44;
    r51 = weq(r10, r18);
    r51 = wsel(r51, r50, r44);
    r49 = r28 * r49;
    r49 = r51 + r49;
    r49 = wsel(r46, r12, r49);
    r46 = r2 - r1;
    r51 = r6 - r5;
    r46 = r29 * r46;
    r51 = r30 * r51;
    r51 = r46 + r51;
    r47 = r47 - r2;
    r45 = r45 - r6;
    r47 = r47 - r31;
    r46 = weq(r11, r18);
    r44 = r32 * r47;
    r44 = wexpm1(r44);
    r44 = r33 * r44;
    r50 = r34 * r47;
    r50 = r44 + r50;
    r44 = r47 - r35;
    r44 = r36 * r44;
    r44 = r37 + r44;
    r47 = wle(r47, r35);
    r47 = wsel(r47, r50, r44);
    r45 = r38 * r45;
    r45 = r47 + r45;
    r45 = wsel(r46, r45, r12);
    r48 = r49 - r48;
    r48 = r48 * r39;
    r49 = r51 - r49;
    r49 = r49 * r40;
    r45 = r45 - r51;
    r45 = r45 * r41;
    out[0] = r4;
    out[1] = r5;
    out[2] = r6;
    out[3] = r12;
    out[4] = r48;
    out[5] = r49;
    out[6] = r45;
    out[7] = r12;
}
static __attribute__((noinline)) void eventsw(const dr *restrict R, d t, const d *restrict x, d *restrict out) {
    (void)t; (void)x;
    d r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17, r18, r19, r20, r21, r22, r23, r24, r25, r26, r27, r28, r29, r30, r31, r32, r33, r34, r35, r36, r37, r38, r39, r40, r41, r42, r43, r44, r45, r46, r47, r48, r49, r50, r51;
    (void)r0;
    r8 = t;
    r12 = R[12];
    r13 = R[13];
    r14 = R[14];
    r15 = R[15];
    r16 = R[16];
    r1 = x[1];
    r0 = x[0];
    r42 = R[42];
    r43 = R[43];
    r2 = x[2];
    r31 = R[31];
    r44 = wle(r8, r12);
    r45 = r13 * r8;
    r45 = -r45;
    r45 = wexpm1(r45);
    r46 = r14 * r8;
    r45 = r15 * r45;
    r45 = r46 + r45;
    r45 = wsel(r16, r46, r45);
    r45 = wsel(r44, r12, r45);
    r44 = r1 - r0;
    r46 = r44 - r42;
    r44 = r44 - r43;
    r45 = r45 - r2;
    r45 = r45 - r31;
    out[0] = r46;
    out[1] = r46;
    out[2] = r44;
    out[3] = r45;
    out[4] = r45;
}
/* rig_redo: the steps of the lanes in `act` (a bit per lane of a d vector)
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
void rig_report(blk *restrict R, long nb, double t, const double *tab) {
  for (long q = 0; q < NQ(nb); q++) {
    v r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17, r18, r19, r20, r21, r22, r23, r24, r25, r26, r27, r28, r29, r30, r31, r32, r33, r34, r35, r36, r37, r38, r39, r40, r41, r42, r43, r44, r45, r46, r47, r48, r49, r50, r51;
    (void)r0;
    r8 = splat(t);
    r12 = LDP(R, 12);
    r13 = LDP(R, 13);
    r14 = LDP(R, 14);
    r15 = LDP(R, 15);
    r16 = LDP(R, 16);
    r17 = LDP(R, 17);
    r0 = LDP(R, 0);
    r9 = LD(R, 9);
    r18 = LDP(R, 18);
    r19 = LDP(R, 19);
    r20 = LDP(R, 20);
    r4 = LDP(R, 4);
    r1 = LDP(R, 1);
    r5 = LDP(R, 5);
    r21 = LDP(R, 21);
    r22 = LDP(R, 22);
    r23 = LDP(R, 23);
    r24 = LDP(R, 24);
    r25 = LDP(R, 25);
    r26 = LDP(R, 26);
    r27 = LDP(R, 27);
    r10 = LD(R, 10);
    r28 = LDP(R, 28);
    r2 = LDP(R, 2);
    r6 = LDP(R, 6);
    r44 = vle(r8, r12);
    r45 = r13 * r8;
    r45 = -r45;
    r45 = vexpm1(r45);
    r46 = r14 * r8;
    r47 = r15 * r45;
    r47 = r46 + r47;
    r45 = r14 * r45;
    r45 = -r45;
    r47 = vsel(r16, r46, r47);
    r45 = vsel(r16, r14, r45);
    r47 = vsel(r44, r12, r47);
    r45 = vsel(r44, r12, r45);
    r44 = r17 * r0;
    r46 = veq(r9, r18);
    r48 = vsel(r46, r19, r20);
    r48 = r48 * r4;
    r48 = r44 + r48;
    r44 = r1 - r0;
    r49 = r5 - r4;
    r50 = r21 * r44;
    r50 = r50 + r22;
    r50 = r50 * r44;
    r50 = r50 + r23;
    r50 = r50 * r44;
    r50 = r50 + r24;
    r50 = r50 * r44;
    r50 = r50 + r25;
    r50 = r50 * r44;
    r50 = r50 + r26;
    r44 = r27 * r44;
    r51 = veq(r10, r18);
    r51 = vsel(r51, r50, r44);
    r49 = r28 * r49;
    r49 = r51 + r49;
    r49 = vsel(r46, r12, r49);
    ST(R, 48, r48);
    ST(R, 49, r49);
    STP(R, 0, r0);
    STP(R, 1, r1);
    STP(R, 2, r2);
    ST(R, 47, r47);
    STP(R, 4, r4);
    STP(R, 5, r5);
    STP(R, 6, r6);
    ST(R, 45, r45);
  }
}
void rig_measured(blk *restrict R, long nb, double t, const double *tab) {
  for (long q = 0; q < NQ(nb); q++) {
    v r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17, r18, r19, r20, r21, r22, r23, r24, r25, r26, r27, r28, r29, r30, r31, r32, r33, r34, r35, r36, r37, r38, r39, r40, r41, r42, r43, r44, r45, r46, r47, r48, r49, r50, r51;
    (void)r0;
    r17 = LDP(R, 17);
    r0 = LDP(R, 0);
    r9 = LD(R, 9);
    r18 = LDP(R, 18);
    r19 = LDP(R, 19);
    r20 = LDP(R, 20);
    r4 = LDP(R, 4);
    r44 = r17 * r0;
    r45 = veq(r9, r18);
    r45 = vsel(r45, r19, r20);
    r45 = r45 * r4;
    r45 = r44 + r45;
    ST(R, 45, r45);
  }
}
void rig_update(blk *restrict R, long nb, double t, const double *tab) {
  for (long q = 0; q < NQ(nb); q++) {
    v r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12, r13, r14, r15, r16, r17, r18, r19, r20, r21, r22, r23, r24, r25, r26, r27, r28, r29, r30, r31, r32, r33, r34, r35, r36, r37, r38, r39, r40, r41, r42, r43, r44, r45, r46, r47, r48, r49, r50, r51;
    (void)r0;
  }
}
