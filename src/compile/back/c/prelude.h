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
