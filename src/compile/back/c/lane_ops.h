#define NQ(nb) (((nb) * 8 + WV - 1) / WV)
F v splat(double x) { return (v){VALL(x)}; }
F v pick(m k, v a, v b) { return (v)((k & (m)a) | (~k & (m)b)); }
/* log, sin and cos of a uniform vector (every lane alike, as in the
   instructions hoisted out of rig_rk4's loop): one call, its value in every
   lane. */
F v ulog(v a) { return splat(dlog1(a[0])); }
F v usin(v a) { return splat(dsin(dsplat(a[0]))[0]); }
F v ucos(v a) { return splat(dcos(dsplat(a[0]))[0]); }
