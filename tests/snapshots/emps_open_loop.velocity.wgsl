// Generated from the rig description by src/compile/back/wgsl/.

const RIG_STATES: u32 = 4u;
const RIG_REGIMES: u32 = 0u;
const RIG_SWITCHES: bool = false;
const RIG_REPORT: u32 = 7u;

struct RigState {
    s0: real,
    s1: real,
    s2: real,
    s3: real,
}

struct RigRegime {
    r0: u32,
}

struct RunConsts {
    k9: real,
    k11: real,
    k12: real,
    k24: real,
    k29: real,
}

struct RigReport {
    v: array<real, 7>,
}

struct RigEventValues {
    g: array<real, 1>,
}

fn rig_load(base: u32, ex: ExpInfo) -> RunConsts {
    var kc: RunConsts;
    kc.k9 = param(base, P_K9);
    kc.k11 = param(base, P_K11);
    kc.k12 = param(base, P_K12);
    kc.k24 = param(base, P_K24);
    kc.k29 = param(base, P_K29);
    return kc;
}

fn rig_state_load(sb: u32) -> RigState {
    var y: RigState;
    y.s0 = state[sb + 0u];
    y.s1 = state[sb + 1u];
    y.s2 = state[sb + 2u];
    y.s3 = state[sb + 3u];
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
    state[sb + 2u] = y.s2;
    state[sb + 3u] = y.s3;
}

const RIG_ACC: u32 = 4u;

fn st_axpy(y: RigState, a: real, k: RigState) -> RigState {
    var r: RigState;
    r.s0 = y.s0 + a * k.s0;
    r.s1 = y.s1 + a * k.s1;
    r.s2 = y.s2 + a * k.s2;
    r.s3 = y.s3 + a * k.s3;
    return r;
}

fn st_rk4(y: RigState, h6: real, k1: RigState, k2: RigState, k3: RigState, k4: RigState) -> RigState {
    var r: RigState;
    r.s0 = y.s0 + h6 * (((k1.s0 + real(2.0) * k2.s0) + real(2.0) * k3.s0) + k4.s0);
    r.s1 = y.s1 + h6 * (((k1.s1 + real(2.0) * k2.s1) + real(2.0) * k3.s1) + k4.s1);
    r.s2 = y.s2 + h6 * (((k1.s2 + real(2.0) * k2.s2) + real(2.0) * k3.s2) + k4.s2);
    r.s3 = y.s3 + h6 * (((k1.s3 + real(2.0) * k2.s3) + real(2.0) * k3.s3) + k4.s3);
    return r;
}

fn st_hermite(y0: RigState, f0: RigState, y1: RigState, f1: RigState, c00: real, c10: real, c01: real, c11: real) -> RigState {
    var r: RigState;
    r.s0 = ((c00 * y0.s0 + c10 * f0.s0) + c01 * y1.s0) + c11 * f1.s0;
    r.s1 = ((c00 * y0.s1 + c10 * f0.s1) + c01 * y1.s1) + c11 * f1.s1;
    r.s2 = ((c00 * y0.s2 + c10 * f0.s2) + c01 * y1.s2) + c11 * f1.s2;
    r.s3 = ((c00 * y0.s3 + c10 * f0.s3) + c01 * y1.s3) + c11 * f1.s3;
    return r;
}

struct DriveClocks {
    unused: real,
}

fn rig_clock(kc: RunConsts, t: real) -> DriveClocks {
    var c: DriveClocks;
    c.unused = t;
    return c;
}

fn rig_clock_shift(kc: RunConsts, c: DriveClocks, q: DriveClocks, t: real) -> DriveClocks {
    var r = c;
    return r;
}

fn rig_deriv_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigState {
    let v4 = y.s2;
    let v6 = y.s3;
    let v8 = v4 - v6;
    let v10 = kc.k9 * v8;
    let v13 = v8 / kc.k12;
    let v16 = real(2e0) * v13;
    let v17 = min(v16, real(4e1));
    let v19 = max(v17, real(-4e1));
    let v20 = expm1_r(v19);
    let v21 = v20 + real(2e0);
    let v22 = v20 / v21;
    let v23 = kc.k11 * v22;
    let v25 = real(0e0) - v10;
    let v26 = v25 - v23;
    let v27 = v26 - kc.k24;
    let v30 = v27 * kc.k29;
    let v31 = v10 + v23;
    let v32 = v31 + kc.k24;
    var r: RigState;
    r.s0 = v4;
    r.s1 = v6;
    r.s2 = v30;
    r.s3 = v32;
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
    let v5 = y.s1;
    let v34 = real(-1e0) * v5;
    let v35 = v3 + v34;
    return v35;
}

fn rig_report_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigReport {
    let v3 = y.s0;
    let v4 = y.s2;
    let v5 = y.s1;
    let v6 = y.s3;
    let v8 = v4 - v6;
    let v13 = v8 / kc.k12;
    let v16 = real(2e0) * v13;
    let v17 = min(v16, real(4e1));
    let v19 = max(v17, real(-4e1));
    let v20 = expm1_r(v19);
    let v21 = v20 + real(2e0);
    let v22 = v20 / v21;
    let v23 = kc.k11 * v22;
    let v34 = real(-1e0) * v5;
    let v35 = v3 + v34;
    let v36 = real(-1e0) * v6;
    let v37 = v4 + v36;
    var r: RigReport;
    r.v[0] = v35;
    r.v[1] = v37;
    r.v[2] = v23;
    r.v[3] = v3;
    r.v[4] = v5;
    r.v[5] = v4;
    r.v[6] = v6;
    return r;
}

fn rig_deriv(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigState {
    return rig_deriv_c(kc, t, y, rg, rig_clock(kc, t));
}

fn rig_events(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigEventValues {
    return rig_events_c(kc, t, y, rg, rig_clock(kc, t));
}

