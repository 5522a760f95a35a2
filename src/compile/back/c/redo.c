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
