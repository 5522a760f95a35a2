// Generated from the rig description by src/compile/back/wgsl/.

const RIG_STATES: u32 = 3u;
const RIG_REGIMES: u32 = 1u;
const RIG_SWITCHES: bool = true;
const RIG_REPORT: u32 = 5u;

struct RigState {
    s0: real,
    s1: real,
    s2: real,
}

struct RigRegime {
    r0: u32,
}

struct RunConsts {
    k8: real,
    k9: real,
    k17: real,
    k22: real,
    toff0: u32,
    tlen0: u32,
    tt00: real,
    tinv0: real,
}

struct RigReport {
    v: array<real, 5>,
}

struct RigEventValues {
    g: array<real, 4>,
}

fn rig_load(base: u32, ex: ExpInfo) -> RunConsts {
    var kc: RunConsts;
    kc.k8 = param(base, P_K8);
    kc.k9 = param(base, P_K9);
    kc.k17 = param(base, P_K17);
    kc.k22 = param(base, P_K22);
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
    y.s2 = state[sb + 2u];
    return y;
}

fn rig_regimes_load(sb: u32) -> RigRegime {
    var rg: RigRegime;
    rg.r0 = u32(state[sb + 3u]);
    return rg;
}

fn rig_initial(base: u32, y: ptr<function, RigState>, rg: ptr<function, RigRegime>) {
}

fn rig_state_store(sb: u32, y: RigState, rg: RigRegime) {
    state[sb + 0u] = y.s0;
    state[sb + 1u] = y.s1;
    state[sb + 2u] = y.s2;
    state[sb + 3u] = real(rg.r0);
}

const RIG_ACC: u32 = 4u;

fn st_axpy(y: RigState, a: real, k: RigState) -> RigState {
    var r: RigState;
    r.s0 = y.s0 + a * k.s0;
    r.s1 = y.s1 + a * k.s1;
    r.s2 = y.s2 + a * k.s2;
    return r;
}

fn st_rk4(y: RigState, h6: real, k1: RigState, k2: RigState, k3: RigState, k4: RigState) -> RigState {
    var r: RigState;
    r.s0 = y.s0 + h6 * (((k1.s0 + real(2.0) * k2.s0) + real(2.0) * k3.s0) + k4.s0);
    r.s1 = y.s1 + h6 * (((k1.s1 + real(2.0) * k2.s1) + real(2.0) * k3.s1) + k4.s1);
    r.s2 = y.s2 + h6 * (((k1.s2 + real(2.0) * k2.s2) + real(2.0) * k3.s2) + k4.s2);
    return r;
}

fn st_hermite(y0: RigState, f0: RigState, y1: RigState, f1: RigState, c00: real, c10: real, c01: real, c11: real) -> RigState {
    var r: RigState;
    r.s0 = ((c00 * y0.s0 + c10 * f0.s0) + c01 * y1.s0) + c11 * f1.s0;
    r.s1 = ((c00 * y0.s1 + c10 * f0.s1) + c01 * y1.s1) + c11 * f1.s1;
    r.s2 = ((c00 * y0.s2 + c10 * f0.s2) + c01 * y1.s2) + c11 * f1.s2;
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
    let v5 = ck.tab0;
    let v7 = real(0e0) - v4;
    let v10 = y.s2;
    let v11 = kc.k9 * v10;
    let v14 = real(rg.r0);
    let v15 = select(real(0.0), real(1.0), v14 == real(0e0));
    let v16 = select(real(0e0), v7, v15 != real(0.0));
    let v18 = kc.k17 * v7;
    let v19 = v11 + v18;
    let v20 = v19 + v5;
    let v23 = v20 * kc.k22;
    var r: RigState;
    r.s0 = v4;
    r.s1 = v23;
    r.s2 = v16;
    return r;
}

fn rig_events_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigEventValues {
    let v4 = y.s1;
    let v7 = real(0e0) - v4;
    let v10 = y.s2;
    let v11 = kc.k9 * v10;
    let v12 = v11 - kc.k8;
    let v13 = v11 + kc.k8;
    var r: RigEventValues;
    r.g[0] = v12;
    r.g[1] = v13;
    r.g[2] = v7;
    r.g[3] = v7;
    return r;
}

fn rig_hits(g0: RigEventValues, g1: RigEventValues, rg: RigRegime) -> u32 {
    var hits = 0u;
    hits |= select(0u, 1u, rg.r0 == 0u && g1.g[0] >= real(0.0) && (!(g0.g[0] >= real(0.0)) || g1.g[0] > g0.g[0]));
    hits |= select(0u, 2u, rg.r0 == 0u && -(g1.g[1]) >= real(0.0) && (!(-(g0.g[1]) >= real(0.0)) || -(g1.g[1]) > -(g0.g[1])));
    hits |= select(0u, 4u, rg.r0 == 1u && -(g1.g[2]) >= real(0.0) && (!(-(g0.g[2]) >= real(0.0)) || -(g1.g[2]) > -(g0.g[2])));
    hits |= select(0u, 8u, rg.r0 == 2u && g1.g[3] >= real(0.0) && (!(g0.g[3] >= real(0.0)) || g1.g[3] > g0.g[3]));
    return hits;
}

struct EventBases {
    b0: real,
    b1: real,
    b2: real,
}

fn rig_bases_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> EventBases {
    let v4 = y.s1;
    let v7 = real(0e0) - v4;
    let v10 = y.s2;
    let v11 = kc.k9 * v10;
    let v13 = v11 + kc.k8;
    var r: EventBases;
    r.b0 = v11;
    r.b1 = v13;
    r.b2 = v7;
    return r;
}

struct EventWindows {
    lo0: real,
    lo1: real,
    lo2: real,
    hi0: real,
    hi1: real,
    hi2: real,
}

fn rig_window(kc: RunConsts, rg: RigRegime) -> EventWindows {
    var w: EventWindows;
    w.lo0 = -REAL_MAX;
    w.hi0 = REAL_MAX;
    w.hi0 = select(w.hi0, min(w.hi0, kc.k8), rg.r0 == 0u);
    w.lo1 = -REAL_MAX;
    w.hi1 = REAL_MAX;
    w.lo1 = select(w.lo1, max(w.lo1, real(0.0)), rg.r0 == 0u);
    w.lo2 = -REAL_MAX;
    w.hi2 = REAL_MAX;
    w.hi2 = select(w.hi2, min(w.hi2, real(0.0)), rg.r0 == 2u);
    w.lo2 = select(w.lo2, max(w.lo2, real(0.0)), rg.r0 == 1u);
    return w;
}

fn rig_outside(w: EventWindows, b: EventBases) -> bool {
    return b.b0 - w.hi0 >= real(0.0)
        | b.b1 - w.lo1 <= real(0.0)
        | b.b2 - w.hi2 >= real(0.0)
        | b.b2 - w.lo2 <= real(0.0);
}

fn rig_oriented(g: RigEventValues, i: u32) -> real {
    switch i {
        case 0u: { return g.g[0]; }
        case 1u: { return -(g.g[1]); }
        case 2u: { return -(g.g[2]); }
        case 3u: { return g.g[3]; }
        default: { return real(0.0); }
    }
}

fn rig_fire(i: u32, rg: ptr<function, RigRegime>) {
    switch i {
        case 0u: { (*rg).r0 = 1u; }
        case 1u: { (*rg).r0 = 2u; }
        case 2u: { (*rg).r0 = 0u; }
        case 3u: { (*rg).r0 = 0u; }
        default: {}
    }
}

fn rig_output0_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> real {
    let v10 = y.s2;
    let v11 = kc.k9 * v10;
    return v11;
}

fn rig_report_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigReport {
    let v3 = y.s0;
    let v4 = y.s1;
    let v10 = y.s2;
    let v11 = kc.k9 * v10;
    var r: RigReport;
    r.v[0] = v11;
    r.v[1] = v3;
    r.v[2] = v3;
    r.v[3] = v4;
    r.v[4] = v10;
    return r;
}

fn rig_deriv(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigState {
    return rig_deriv_c(kc, t, y, rg, rig_clock(kc, t));
}

fn rig_events(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigEventValues {
    return rig_events_c(kc, t, y, rg, rig_clock(kc, t));
}

