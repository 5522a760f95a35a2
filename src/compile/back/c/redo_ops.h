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
