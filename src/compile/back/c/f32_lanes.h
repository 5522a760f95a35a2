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
