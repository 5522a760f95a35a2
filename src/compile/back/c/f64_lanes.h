typedef d v; typedef dm m; typedef du u;
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
