// Generated from the rig description by src/compile/back/wgsl/.

const RIG_STATES: u32 = 2u;
const RIG_REGIMES: u32 = 0u;
const RIG_SWITCHES: bool = false;
const RIG_REPORT: u32 = 4u;

struct RigState {
    s0: real,
    s1: real,
}

struct RigRegime {
    r0: u32,
}

struct RunConsts {
    k8: real,
    k9: real,
    k14: real,
    k18: real,
    toff0: u32,
    tlen0: u32,
    tt00: real,
    tinv0: real,
}

struct RigReport {
    v: array<real, 4>,
}

struct RigEventValues {
    g: array<real, 1>,
}

fn rig_load(base: u32, ex: ExpInfo) -> RunConsts {
    var kc: RunConsts;
    kc.k8 = param(base, P_K8);
    kc.k9 = param(base, P_K9);
    kc.k14 = param(base, P_K14);
    kc.k18 = param(base, P_K18);
    kc.toff0 = 1u;
    kc.tlen0 = 251u;
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
    return rg;
}

fn rig_initial(base: u32, y: ptr<function, RigState>, rg: ptr<function, RigRegime>) {
}

fn rig_state_store(sb: u32, y: RigState, rg: RigRegime) {
    state[sb + 0u] = y.s0;
    state[sb + 1u] = y.s1;
}

const RIG_ACC: u32 = 2u;

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
    let v3 = y.s0;
    let v4 = y.s1;
    let v5 = ck.tab0;
    let v6 = real(0e0) - v3;
    let v7 = real(0e0) - v4;
    let v10 = kc.k9 * v6;
    let v11 = v10 * v6;
    let v12 = v11 + kc.k8;
    let v13 = v12 * v6;
    let v15 = kc.k14 * v7;
    let v16 = v13 + v15;
    let v19 = v16 * kc.k18;
    let v20 = v19 - v5;
    var r: RigState;
    r.s0 = v4;
    r.s1 = v20;
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
    let v6 = real(0e0) - v3;
    let v7 = real(0e0) - v4;
    let v10 = kc.k9 * v6;
    let v11 = v10 * v6;
    let v12 = v11 + kc.k8;
    let v13 = v12 * v6;
    let v15 = kc.k14 * v7;
    let v16 = v13 + v15;
    var r: RigReport;
    r.v[0] = v3;
    r.v[1] = v16;
    r.v[2] = v3;
    r.v[3] = v4;
    return r;
}

fn rig_deriv(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigState {
    return rig_deriv_c(kc, t, y, rg, rig_clock(kc, t));
}

fn rig_events(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigEventValues {
    return rig_events_c(kc, t, y, rg, rig_clock(kc, t));
}

