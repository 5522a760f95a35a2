// Generated from the rig description by src/compile/back/wgsl/.

const RIG_STATES: u32 = 8u;
const RIG_REGIMES: u32 = 3u;
const RIG_SWITCHES: bool = true;
const RIG_REPORT: u32 = 10u;

struct RigState {
    s0: real,
    s1: real,
    s2: real,
    s3: real,
    s4: real,
    s5: real,
    s6: real,
    s7: real,
}

struct RigRegime {
    r0: u32,
    r1: u32,
    r2: u32,
}

struct RunConsts {
    k12: real,
    k14: real,
    k15: real,
    k23: real,
    k24: real,
    k25: real,
    k26: real,
    k27: real,
    k28: real,
    k29: real,
    k30: real,
    k46: real,
    k49: real,
    k54: real,
    k56: real,
    k61: real,
    k67: real,
    k68: real,
    k69: real,
    k77: real,
    k78: real,
    k83: real,
    k94: real,
    k101: real,
    k106: real,
    k111: real,
    k116: real,
    toff0: u32,
    tlen0: u32,
    tt00: real,
    tinv0: real,
}

struct RigReport {
    v: array<real, 10>,
}

struct RigEventValues {
    g: array<real, 5>,
}

fn rig_load(base: u32, ex: ExpInfo) -> RunConsts {
    var kc: RunConsts;
    kc.k12 = param(base, P_K12);
    kc.k14 = param(base, P_K14);
    kc.k15 = param(base, P_K15);
    kc.k23 = param(base, P_K23);
    kc.k24 = param(base, P_K24);
    kc.k25 = param(base, P_K25);
    kc.k26 = param(base, P_K26);
    kc.k27 = param(base, P_K27);
    kc.k28 = param(base, P_K28);
    kc.k29 = param(base, P_K29);
    kc.k30 = param(base, P_K30);
    kc.k46 = param(base, P_K46);
    kc.k49 = param(base, P_K49);
    kc.k54 = param(base, P_K54);
    kc.k56 = param(base, P_K56);
    kc.k61 = param(base, P_K61);
    kc.k67 = param(base, P_K67);
    kc.k68 = param(base, P_K68);
    kc.k69 = param(base, P_K69);
    kc.k77 = param(base, P_K77);
    kc.k78 = param(base, P_K78);
    kc.k83 = param(base, P_K83);
    kc.k94 = param(base, P_K94);
    kc.k101 = param(base, P_K101);
    kc.k106 = param(base, P_K106);
    kc.k111 = param(base, P_K111);
    kc.k116 = param(base, P_K116);
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
    y.s3 = state[sb + 3u];
    y.s4 = state[sb + 4u];
    y.s5 = state[sb + 5u];
    y.s6 = state[sb + 6u];
    y.s7 = state[sb + 7u];
    return y;
}

fn rig_regimes_load(sb: u32) -> RigRegime {
    var rg: RigRegime;
    rg.r0 = u32(state[sb + 8u]);
    rg.r1 = u32(state[sb + 9u]);
    rg.r2 = u32(state[sb + 10u]);
    return rg;
}

fn rig_initial(base: u32, y: ptr<function, RigState>, rg: ptr<function, RigRegime>) {
}

fn rig_state_store(sb: u32, y: RigState, rg: RigRegime) {
    state[sb + 0u] = y.s0;
    state[sb + 1u] = y.s1;
    state[sb + 2u] = y.s2;
    state[sb + 3u] = y.s3;
    state[sb + 4u] = y.s4;
    state[sb + 5u] = y.s5;
    state[sb + 6u] = y.s6;
    state[sb + 7u] = y.s7;
    state[sb + 8u] = real(rg.r0);
    state[sb + 9u] = real(rg.r1);
    state[sb + 10u] = real(rg.r2);
}

const RIG_ACC: u32 = 11u;

fn st_axpy(y: RigState, a: real, k: RigState) -> RigState {
    var r: RigState;
    r.s0 = y.s0 + a * k.s0;
    r.s1 = y.s1 + a * k.s1;
    r.s2 = y.s2 + a * k.s2;
    r.s3 = y.s3 + a * k.s3;
    r.s4 = y.s4 + a * k.s4;
    r.s5 = y.s5 + a * k.s5;
    r.s6 = y.s6 + a * k.s6;
    r.s7 = y.s7 + a * k.s7;
    return r;
}

fn st_rk4(y: RigState, h6: real, k1: RigState, k2: RigState, k3: RigState, k4: RigState) -> RigState {
    var r: RigState;
    r.s0 = y.s0 + h6 * (((k1.s0 + real(2.0) * k2.s0) + real(2.0) * k3.s0) + k4.s0);
    r.s1 = y.s1 + h6 * (((k1.s1 + real(2.0) * k2.s1) + real(2.0) * k3.s1) + k4.s1);
    r.s2 = y.s2 + h6 * (((k1.s2 + real(2.0) * k2.s2) + real(2.0) * k3.s2) + k4.s2);
    r.s3 = y.s3 + h6 * (((k1.s3 + real(2.0) * k2.s3) + real(2.0) * k3.s3) + k4.s3);
    r.s4 = y.s4 + h6 * (((k1.s4 + real(2.0) * k2.s4) + real(2.0) * k3.s4) + k4.s4);
    r.s5 = y.s5 + h6 * (((k1.s5 + real(2.0) * k2.s5) + real(2.0) * k3.s5) + k4.s5);
    r.s6 = y.s6 + h6 * (((k1.s6 + real(2.0) * k2.s6) + real(2.0) * k3.s6) + k4.s6);
    r.s7 = y.s7 + h6 * (((k1.s7 + real(2.0) * k2.s7) + real(2.0) * k3.s7) + k4.s7);
    return r;
}

fn st_hermite(y0: RigState, f0: RigState, y1: RigState, f1: RigState, c00: real, c10: real, c01: real, c11: real) -> RigState {
    var r: RigState;
    r.s0 = ((c00 * y0.s0 + c10 * f0.s0) + c01 * y1.s0) + c11 * f1.s0;
    r.s1 = ((c00 * y0.s1 + c10 * f0.s1) + c01 * y1.s1) + c11 * f1.s1;
    r.s2 = ((c00 * y0.s2 + c10 * f0.s2) + c01 * y1.s2) + c11 * f1.s2;
    r.s3 = ((c00 * y0.s3 + c10 * f0.s3) + c01 * y1.s3) + c11 * f1.s3;
    r.s4 = ((c00 * y0.s4 + c10 * f0.s4) + c01 * y1.s4) + c11 * f1.s4;
    r.s5 = ((c00 * y0.s5 + c10 * f0.s5) + c01 * y1.s5) + c11 * f1.s5;
    r.s6 = ((c00 * y0.s6 + c10 * f0.s6) + c01 * y1.s6) + c11 * f1.s6;
    r.s7 = ((c00 * y0.s7 + c10 * f0.s7) + c01 * y1.s7) + c11 * f1.s7;
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
    let v4 = y.s4;
    let v5 = y.s1;
    let v6 = y.s5;
    let v7 = y.s2;
    let v8 = y.s6;
    let v9 = y.s3;
    let v10 = y.s7;
    let v11 = ck.tab0;
    let v13 = kc.k12 * v3;
    let v16 = real(rg.r0);
    let v17 = select(real(0.0), real(1.0), v16 == real(1e0));
    let v18 = select(kc.k14, kc.k15, v17 != real(0.0));
    let v19 = v18 * v4;
    let v20 = v13 + v19;
    let v21 = v5 - v3;
    let v22 = v6 - v4;
    let v31 = kc.k30 * v21;
    let v32 = v31 + kc.k29;
    let v33 = v32 * v21;
    let v34 = v33 + kc.k28;
    let v35 = v34 * v21;
    let v36 = v35 + kc.k27;
    let v37 = v36 * v21;
    let v38 = v37 + kc.k26;
    let v39 = v38 * v21;
    let v40 = v39 + kc.k25;
    let v41 = kc.k23 * v21;
    let v43 = real(rg.r1);
    let v44 = select(real(0.0), real(1.0), v43 == real(1e0));
    let v45 = select(v41, v40, v44 != real(0.0));
    let v47 = kc.k46 * v22;
    let v48 = v45 + v47;
    let v51 = select(v48, real(0e0), v17 != real(0.0));
    let v52 = v7 - v5;
    let v53 = v8 - v6;
    let v55 = kc.k54 * v52;
    let v57 = kc.k56 * v53;
    let v58 = v55 + v57;
    let v59 = v9 - v7;
    let v60 = v10 - v8;
    let v62 = v59 - kc.k61;
    let v64 = real(rg.r2);
    let v65 = select(real(0.0), real(1.0), v64 == real(1e0));
    let v84 = kc.k67 * v62;
    let v85 = expm1_r(v84);
    let v86 = kc.k78 * v85;
    let v87 = kc.k68 * v62;
    let v88 = v86 + v87;
    let v89 = v62 - kc.k77;
    let v90 = kc.k69 * v89;
    let v91 = kc.k83 + v90;
    let v92 = select(real(0.0), real(1.0), v62 <= kc.k77);
    let v93 = select(v91, v88, v92 != real(0.0));
    let v95 = kc.k94 * v60;
    let v96 = v93 + v95;
    let v97 = select(real(0e0), v96, v65 != real(0.0));
    let v99 = v51 - v20;
    let v102 = v99 * kc.k101;
    let v104 = v58 - v51;
    let v107 = v104 * kc.k106;
    let v109 = v97 - v58;
    let v112 = v109 * kc.k111;
    let v114 = v11 - v97;
    let v117 = v114 * kc.k116;
    var r: RigState;
    r.s0 = v4;
    r.s1 = v6;
    r.s2 = v8;
    r.s3 = v10;
    r.s4 = v102;
    r.s5 = v107;
    r.s6 = v112;
    r.s7 = v117;
    return r;
}

fn rig_events_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigEventValues {
    let v3 = y.s0;
    let v5 = y.s1;
    let v7 = y.s2;
    let v9 = y.s3;
    let v21 = v5 - v3;
    let v42 = v21 - kc.k24;
    let v50 = v21 - kc.k49;
    let v59 = v9 - v7;
    let v62 = v59 - kc.k61;
    var r: RigEventValues;
    r.g[0] = v42;
    r.g[1] = v42;
    r.g[2] = v50;
    r.g[3] = v62;
    r.g[4] = v62;
    return r;
}

fn rig_hits(g0: RigEventValues, g1: RigEventValues, rg: RigRegime) -> u32 {
    var hits = 0u;
    hits |= select(0u, 1u, rg.r1 == 0u && g1.g[0] >= real(0.0) && (!(g0.g[0] >= real(0.0)) || g1.g[0] > g0.g[0]));
    hits |= select(0u, 2u, rg.r1 == 1u && -(g1.g[1]) >= real(0.0) && (!(-(g0.g[1]) >= real(0.0)) || -(g1.g[1]) > -(g0.g[1])));
    hits |= select(0u, 4u, rg.r0 == 0u && g1.g[2] >= real(0.0) && (!(g0.g[2] >= real(0.0)) || g1.g[2] > g0.g[2]));
    hits |= select(0u, 8u, rg.r2 == 0u && g1.g[3] >= real(0.0) && (!(g0.g[3] >= real(0.0)) || g1.g[3] > g0.g[3]));
    hits |= select(0u, 16u, rg.r2 == 1u && -(g1.g[4]) >= real(0.0) && (!(-(g0.g[4]) >= real(0.0)) || -(g1.g[4]) > -(g0.g[4])));
    return hits;
}

struct EventBases {
    b0: real,
    b1: real,
}

fn rig_bases_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> EventBases {
    let v3 = y.s0;
    let v5 = y.s1;
    let v7 = y.s2;
    let v9 = y.s3;
    let v21 = v5 - v3;
    let v59 = v9 - v7;
    var r: EventBases;
    r.b0 = v21;
    r.b1 = v59;
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
    w.hi0 = select(w.hi0, min(w.hi0, kc.k24), rg.r1 == 0u);
    w.hi0 = select(w.hi0, min(w.hi0, kc.k49), rg.r0 == 0u);
    w.lo0 = select(w.lo0, max(w.lo0, kc.k24), rg.r1 == 1u);
    w.lo1 = -REAL_MAX;
    w.hi1 = REAL_MAX;
    w.hi1 = select(w.hi1, min(w.hi1, kc.k61), rg.r2 == 0u);
    w.lo1 = select(w.lo1, max(w.lo1, kc.k61), rg.r2 == 1u);
    return w;
}

fn rig_outside(w: EventWindows, b: EventBases) -> bool {
    return b.b0 - w.hi0 >= real(0.0)
        | b.b0 - w.lo0 <= real(0.0)
        | b.b1 - w.hi1 >= real(0.0)
        | b.b1 - w.lo1 <= real(0.0);
}

fn rig_oriented(g: RigEventValues, i: u32) -> real {
    switch i {
        case 0u: { return g.g[0]; }
        case 1u: { return -(g.g[1]); }
        case 2u: { return g.g[2]; }
        case 3u: { return g.g[3]; }
        case 4u: { return -(g.g[4]); }
        default: { return real(0.0); }
    }
}

fn rig_fire(i: u32, rg: ptr<function, RigRegime>) {
    switch i {
        case 0u: { (*rg).r1 = 1u; }
        case 1u: { (*rg).r1 = 0u; }
        case 2u: { (*rg).r0 = 1u; }
        case 3u: { (*rg).r2 = 1u; }
        case 4u: { (*rg).r2 = 0u; }
        default: {}
    }
}

fn rig_output0_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> real {
    let v3 = y.s0;
    let v4 = y.s4;
    let v13 = kc.k12 * v3;
    let v16 = real(rg.r0);
    let v17 = select(real(0.0), real(1.0), v16 == real(1e0));
    let v18 = select(kc.k14, kc.k15, v17 != real(0.0));
    let v19 = v18 * v4;
    let v20 = v13 + v19;
    return v20;
}

fn rig_report_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigReport {
    let v3 = y.s0;
    let v4 = y.s4;
    let v5 = y.s1;
    let v6 = y.s5;
    let v7 = y.s2;
    let v8 = y.s6;
    let v9 = y.s3;
    let v10 = y.s7;
    let v13 = kc.k12 * v3;
    let v16 = real(rg.r0);
    let v17 = select(real(0.0), real(1.0), v16 == real(1e0));
    let v18 = select(kc.k14, kc.k15, v17 != real(0.0));
    let v19 = v18 * v4;
    let v20 = v13 + v19;
    let v21 = v5 - v3;
    let v22 = v6 - v4;
    let v31 = kc.k30 * v21;
    let v32 = v31 + kc.k29;
    let v33 = v32 * v21;
    let v34 = v33 + kc.k28;
    let v35 = v34 * v21;
    let v36 = v35 + kc.k27;
    let v37 = v36 * v21;
    let v38 = v37 + kc.k26;
    let v39 = v38 * v21;
    let v40 = v39 + kc.k25;
    let v41 = kc.k23 * v21;
    let v43 = real(rg.r1);
    let v44 = select(real(0.0), real(1.0), v43 == real(1e0));
    let v45 = select(v41, v40, v44 != real(0.0));
    let v47 = kc.k46 * v22;
    let v48 = v45 + v47;
    let v51 = select(v48, real(0e0), v17 != real(0.0));
    var r: RigReport;
    r.v[0] = v20;
    r.v[1] = v51;
    r.v[2] = v3;
    r.v[3] = v5;
    r.v[4] = v7;
    r.v[5] = v9;
    r.v[6] = v4;
    r.v[7] = v6;
    r.v[8] = v8;
    r.v[9] = v10;
    return r;
}

fn rig_deriv(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigState {
    return rig_deriv_c(kc, t, y, rg, rig_clock(kc, t));
}

fn rig_events(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigEventValues {
    return rig_events_c(kc, t, y, rg, rig_clock(kc, t));
}

