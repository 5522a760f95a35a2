// Generated from the rig description by src/compile/back/wgsl/.

const RIG_STATES: u32 = 4u;
const RIG_REGIMES: u32 = 2u;
const RIG_SWITCHES: bool = true;
const RIG_REPORT: u32 = 6u;

struct RigState {
    s0: real,
    s1: real,
    s2: real,
    s3: real,
}

struct RigRegime {
    r0: u32,
    r1: u32,
}

struct RunConsts {
    k8: real,
    k9: real,
    k10: real,
    k14: real,
    k30: real,
    k39: real,
    k41: real,
    k44: real,
    k46: real,
    k51: real,
    k53: real,
    k60: real,
}

struct RigReport {
    v: array<real, 6>,
}

struct RigEventValues {
    g: array<real, 4>,
}

fn rig_load(base: u32, ex: ExpInfo) -> RunConsts {
    var kc: RunConsts;
    kc.k8 = param(base, P_K8);
    kc.k9 = param(base, P_K9);
    kc.k10 = param(base, P_K10);
    kc.k14 = param(base, P_K14);
    kc.k30 = param(base, P_K30);
    kc.k39 = param(base, P_K39);
    kc.k41 = param(base, P_K41);
    kc.k44 = param(base, P_K44);
    kc.k46 = param(base, P_K46);
    kc.k51 = param(base, P_K51);
    kc.k53 = param(base, P_K53);
    kc.k60 = param(base, P_K60);
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
    rg.r0 = u32(state[sb + 4u]);
    rg.r1 = u32(state[sb + 5u]);
    return rg;
}

fn rig_initial(base: u32, y: ptr<function, RigState>, rg: ptr<function, RigRegime>) {
}

fn rig_state_store(sb: u32, y: RigState, rg: RigRegime) {
    state[sb + 0u] = y.s0;
    state[sb + 1u] = y.s1;
    state[sb + 2u] = y.s2;
    state[sb + 3u] = y.s3;
    state[sb + 4u] = real(rg.r0);
    state[sb + 5u] = real(rg.r1);
}

const RIG_ACC: u32 = 6u;

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
    let v0 = t;
    let v3 = y.s0;
    let v4 = y.s2;
    let v5 = y.s1;
    let v6 = y.s3;
    let v11 = v0 - kc.k10;
    let v15 = kc.k14 * v11;
    let v16 = real(rg.r0);
    let v17 = select(real(0.0), real(1.0), v16 == real(1e0));
    let v18 = sin_r(v15);
    let v20 = kc.k8 * v18;
    let v27 = select(real(0e0), v20, v17 != real(0.0));
    let v31 = real(rg.r1);
    let v32 = select(real(0.0), real(1.0), v31 == real(1e0));
    let v33 = kc.k30 * v18;
    let v36 = select(real(0e0), v33, v32 != real(0.0));
    let v40 = kc.k39 * v3;
    let v42 = kc.k41 * v4;
    let v43 = v40 + v42;
    let v45 = kc.k44 * v5;
    let v47 = kc.k46 * v6;
    let v48 = v45 + v47;
    let v49 = v5 - v3;
    let v50 = v6 - v4;
    let v52 = kc.k51 * v49;
    let v54 = kc.k53 * v50;
    let v55 = v52 + v54;
    let v57 = v55 - v43;
    let v58 = v57 + v27;
    let v61 = v58 * kc.k60;
    let v62 = real(0e0) - v48;
    let v63 = v62 - v55;
    let v64 = v63 + v36;
    let v65 = v64 * kc.k60;
    var r: RigState;
    r.s0 = v4;
    r.s1 = v6;
    r.s2 = v61;
    r.s3 = v65;
    return r;
}

fn rig_events_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigEventValues {
    let v0 = t;
    let v11 = v0 - kc.k10;
    let v12 = v11 - kc.k9;
    var r: RigEventValues;
    r.g[0] = v11;
    r.g[1] = v12;
    r.g[2] = v11;
    r.g[3] = v12;
    return r;
}

fn rig_hits(g0: RigEventValues, g1: RigEventValues, rg: RigRegime) -> u32 {
    var hits = 0u;
    hits |= select(0u, 1u, rg.r0 == 0u && g1.g[0] >= real(0.0) && (!(g0.g[0] >= real(0.0)) || g1.g[0] > g0.g[0]));
    hits |= select(0u, 2u, rg.r0 == 1u && g1.g[1] >= real(0.0) && (!(g0.g[1] >= real(0.0)) || g1.g[1] > g0.g[1]));
    hits |= select(0u, 4u, rg.r1 == 0u && g1.g[2] >= real(0.0) && (!(g0.g[2] >= real(0.0)) || g1.g[2] > g0.g[2]));
    hits |= select(0u, 8u, rg.r1 == 1u && g1.g[3] >= real(0.0) && (!(g0.g[3] >= real(0.0)) || g1.g[3] > g0.g[3]));
    return hits;
}

struct EventBases {
    b0: real,
    b1: real,
}

fn rig_bases_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> EventBases {
    let v0 = t;
    let v11 = v0 - kc.k10;
    var r: EventBases;
    r.b0 = v0;
    r.b1 = v11;
    return r;
}

struct EventWindows {
    lo0: real,
    lo1: real,
    hi0: real,
    hi1: real,
}

fn rig_window(kc: RunConsts, rg: RigRegime) -> EventWindows {
    var w: EventWindows;
    w.lo0 = -REAL_MAX;
    w.hi0 = REAL_MAX;
    w.hi0 = select(w.hi0, min(w.hi0, kc.k10), rg.r0 == 0u);
    w.hi0 = select(w.hi0, min(w.hi0, kc.k10), rg.r1 == 0u);
    w.lo1 = -REAL_MAX;
    w.hi1 = REAL_MAX;
    w.hi1 = select(w.hi1, min(w.hi1, kc.k9), rg.r0 == 1u);
    w.hi1 = select(w.hi1, min(w.hi1, kc.k9), rg.r1 == 1u);
    return w;
}

fn rig_outside(w: EventWindows, b: EventBases) -> bool {
    return b.b0 - w.hi0 >= real(0.0)
        | b.b1 - w.hi1 >= real(0.0);
}

fn rig_oriented(g: RigEventValues, i: u32) -> real {
    switch i {
        case 0u: { return g.g[0]; }
        case 1u: { return g.g[1]; }
        case 2u: { return g.g[2]; }
        case 3u: { return g.g[3]; }
        default: { return real(0.0); }
    }
}

fn rig_fire(i: u32, rg: ptr<function, RigRegime>) {
    switch i {
        case 0u: { (*rg).r0 = 1u; }
        case 1u: { (*rg).r0 = 2u; }
        case 2u: { (*rg).r1 = 1u; }
        case 3u: { (*rg).r1 = 2u; }
        default: {}
    }
}

fn rig_output0_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> real {
    let v3 = y.s0;
    return v3;
}

fn rig_report_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigReport {
    let v3 = y.s0;
    let v4 = y.s2;
    let v5 = y.s1;
    let v6 = y.s3;
    var r: RigReport;
    r.v[0] = v3;
    r.v[1] = v5;
    r.v[2] = v3;
    r.v[3] = v5;
    r.v[4] = v4;
    r.v[5] = v6;
    return r;
}

fn rig_deriv(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigState {
    return rig_deriv_c(kc, t, y, rg, rig_clock(kc, t));
}

fn rig_events(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigEventValues {
    return rig_events_c(kc, t, y, rg, rig_clock(kc, t));
}

