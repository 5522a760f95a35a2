// Generated from the rig description by src/compile/back/wgsl/.

const RIG_STATES: u32 = 2u;
const RIG_REGIMES: u32 = 0u;
const RIG_SWITCHES: bool = false;
const RIG_REPORT: u32 = 6u;

struct RigState {
    s0: real,
    s1: real,
}

struct RigRegime {
    r0: u32,
    h0: real,
    h1: real,
    h2: real,
    kn: u32,
}

struct RunConsts {
    k5: real,
    k8: real,
    k10: real,
    k11: real,
    k23: real,
    k29: real,
    k33: real,
    k34: real,
    toff0: u32,
    tlen0: u32,
    tt00: real,
    tinv0: real,
}

struct RigReport {
    v: array<real, 6>,
}

struct RigEventValues {
    g: array<real, 1>,
}

fn rig_load(base: u32, ex: ExpInfo) -> RunConsts {
    var kc: RunConsts;
    kc.k5 = param(base, P_K5);
    kc.k8 = param(base, P_K8);
    kc.k10 = param(base, P_K10);
    kc.k11 = param(base, P_K11);
    kc.k23 = param(base, P_K23);
    kc.k29 = param(base, P_K29);
    kc.k33 = param(base, P_K33);
    kc.k34 = param(base, P_K34);
    kc.toff0 = ex.table_offset;
    kc.tlen0 = ex.table_len;
    kc.tt00 = table_start(kc.toff0, kc.tlen0);
    kc.tinv0 = table_header(kc.toff0, kc.tlen0);
    return kc;
}

fn rig_state_load(sb: u32) -> RigState {
    var y: RigState;
    y.s0 = state[sb + 0u];
    y.s1 = state[sb + 1u];
    return y;
}

fn rig_regimes_load(sb: u32) -> RigRegime {
    var rg: RigRegime;
    rg.h0 = state[sb + 2u];
    rg.h1 = state[sb + 3u];
    rg.h2 = state[sb + 4u];
    rg.kn = u32(state[sb + 5u]);
    return rg;
}

fn rig_initial(base: u32, y: ptr<function, RigState>, rg: ptr<function, RigRegime>) {
    (*rg).h0 = real(0e0);
    (*rg).h1 = real(0e0);
    (*rg).h2 = real(0e0);
    (*rg).kn = 0u;
}

fn rig_state_store(sb: u32, y: RigState, rg: RigRegime) {
    state[sb + 0u] = y.s0;
    state[sb + 1u] = y.s1;
    state[sb + 2u] = rg.h0;
    state[sb + 3u] = rg.h1;
    state[sb + 4u] = rg.h2;
    state[sb + 5u] = real(rg.kn);
}

const RIG_ACC: u32 = 6u;

fn st_axpy(y: RigState, a: real, k: RigState) -> RigState {
    var r: RigState;
    r.s0 = y.s0 + a * k.s0;
    r.s1 = y.s1 + a * k.s1;
    return r;
}

fn st_rk4(y: RigState, h6: real, k1: RigState, k2: RigState, k3: RigState, k4: RigState) -> RigState {
    var r: RigState;
    r.s0 = y.s0 + h6 * (((k1.s0 + real(2.0) * k2.s0) + real(2.0) * k3.s0) + k4.s0);
    r.s1 = y.s1 + h6 * (((k1.s1 + real(2.0) * k2.s1) + real(2.0) * k3.s1) + k4.s1);
    return r;
}

fn st_hermite(y0: RigState, f0: RigState, y1: RigState, f1: RigState, c00: real, c10: real, c01: real, c11: real) -> RigState {
    var r: RigState;
    r.s0 = ((c00 * y0.s0 + c10 * f0.s0) + c01 * y1.s0) + c11 * f1.s0;
    r.s1 = ((c00 * y0.s1 + c10 * f0.s1) + c01 * y1.s1) + c11 * f1.s1;
    return r;
}

struct DriveClocks {
    tab0: real,
}

fn rig_clock(kc: RunConsts, t: real) -> DriveClocks {
    var c: DriveClocks;
    c.tab0 = table_at(kc.toff0, kc.tlen0, kc.tt00, kc.tinv0, t);
    return c;
}

fn rig_clock_shift(kc: RunConsts, c: DriveClocks, q: DriveClocks, t: real) -> DriveClocks {
    var r = c;
    r.tab0 = table_at(kc.toff0, kc.tlen0, kc.tt00, kc.tinv0, t);
    return r;
}

fn rig_deriv_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigState {
    let v4 = y.s1;
    let v6 = rg.h2;
    let v7 = kc.k5 * v6;
    let v9 = kc.k8 * v4;
    let v12 = v4 / kc.k11;
    let v15 = real(2e0) * v12;
    let v16 = min(v15, real(4e1));
    let v18 = max(v16, real(-4e1));
    let v19 = expm1_r(v18);
    let v20 = v19 + real(2e0);
    let v21 = v19 / v20;
    let v22 = kc.k10 * v21;
    let v24 = real(0e0) - v9;
    let v25 = v24 - v22;
    let v26 = v25 - kc.k23;
    let v27 = v26 + v7;
    let v30 = v27 * kc.k29;
    var r: RigState;
    r.s0 = v4;
    r.s1 = v30;
    return r;
}

fn rig_events_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigEventValues {
    var r: RigEventValues;
    return r;
}

fn rig_hits(g0: RigEventValues, g1: RigEventValues, rg: RigRegime) -> u32 {
    var hits = 0u;
    return hits;
}

struct EventBases {
    b0: real,
}

fn rig_bases_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> EventBases {
    var r: EventBases;
    r.b0 = real(0.0);
    return r;
}

struct EventWindows {
    lo0: real,
    hi0: real,
}

fn rig_window(kc: RunConsts, rg: RigRegime) -> EventWindows {
    var w: EventWindows;
    w.lo0 = -REAL_MAX;
    w.hi0 = REAL_MAX;
    return w;
}

fn rig_outside(w: EventWindows, b: EventBases) -> bool {
    return false;
}

fn rig_oriented(g: RigEventValues, i: u32) -> real {
    switch i {
        default: { return real(0.0); }
    }
}

fn rig_fire(i: u32, rg: ptr<function, RigRegime>) {
    switch i {
        default: {}
    }
}

fn rig_output0_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> real {
    let v3 = y.s0;
    return v3;
}

fn rig_report_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigReport {
    let v3 = y.s0;
    let v4 = y.s1;
    let v6 = rg.h2;
    let v12 = v4 / kc.k11;
    let v15 = real(2e0) * v12;
    let v16 = min(v15, real(4e1));
    let v18 = max(v16, real(-4e1));
    let v19 = expm1_r(v18);
    let v20 = v19 + real(2e0);
    let v21 = v19 / v20;
    let v22 = kc.k10 * v21;
    var r: RigReport;
    r.v[0] = v3;
    r.v[1] = v4;
    r.v[2] = v22;
    r.v[3] = v6;
    r.v[4] = v3;
    r.v[5] = v4;
    return r;
}

fn rig_deriv(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigState {
    return rig_deriv_c(kc, t, y, rg, rig_clock(kc, t));
}

fn rig_events(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigEventValues {
    return rig_events_c(kc, t, y, rg, rig_clock(kc, t));
}

const RIG_SAMPLED: bool = true;
const SAMPLE_PERIOD: real = real(1e-3);
const SAMPLE_PHASE: real = real(0e0);

fn rig_instant(rg: RigRegime) -> real {
    return SAMPLE_PHASE + real(rg.kn) * SAMPLE_PERIOD;
}

fn rig_sample_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigRegime {
    let v3 = y.s0;
    let v31 = rg.h0;
    let v32 = rg.h1;
    let v35 = ck.tab0;
    let v36 = v35 - v3;
    let v37 = kc.k34 * v36;
    let v38 = v3 - v32;
    let v41 = v38 / real(2e-3);
    let v42 = v37 - v41;
    let v43 = kc.k33 * v42;
    var r = rg;
    r.h0 = v3;
    r.h1 = v31;
    r.h2 = v43;
    r.kn = rg.kn + 1u;
    return r;
}

fn rig_sample(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigRegime {
    return rig_sample_c(kc, t, y, rg, rig_clock(kc, t));
}

