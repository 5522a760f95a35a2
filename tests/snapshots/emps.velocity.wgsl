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
}

struct RunConsts {
    k5: real,
    k7: real,
    k8: real,
    k20: real,
    k25: real,
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
    kc.k7 = param(base, P_K7);
    kc.k8 = param(base, P_K8);
    kc.k20 = param(base, P_K20);
    kc.k25 = param(base, P_K25);
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
    let v4 = y.s1;
    let v6 = kc.k5 * v4;
    let v9 = v4 / kc.k8;
    let v12 = real(2e0) * v9;
    let v13 = min(v12, real(4e1));
    let v15 = max(v13, real(-4e1));
    let v16 = expm1_r(v15);
    let v17 = v16 + real(2e0);
    let v18 = v16 / v17;
    let v19 = kc.k7 * v18;
    let v21 = real(0e0) - v6;
    let v22 = v21 - v19;
    let v23 = v22 - kc.k20;
    let v26 = v23 * kc.k25;
    var r: RigState;
    r.s0 = v4;
    r.s1 = v26;
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
    let v9 = v4 / kc.k8;
    let v12 = real(2e0) * v9;
    let v13 = min(v12, real(4e1));
    let v15 = max(v13, real(-4e1));
    let v16 = expm1_r(v15);
    let v17 = v16 + real(2e0);
    let v18 = v16 / v17;
    let v19 = kc.k7 * v18;
    var r: RigReport;
    r.v[0] = v3;
    r.v[1] = v4;
    r.v[2] = v19;
    r.v[3] = real(0e0);
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

