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
    k11: real,
    k12: real,
    k14: real,
    k16: real,
    k34: real,
    k36: real,
    k37: real,
    k45: real,
    k46: real,
    k47: real,
    k48: real,
    k49: real,
    k50: real,
    k51: real,
    k52: real,
    k68: real,
    k71: real,
    k76: real,
    k78: real,
    k83: real,
    k89: real,
    k90: real,
    k91: real,
    k99: real,
    k100: real,
    k105: real,
    k116: real,
    k123: real,
    k128: real,
    k133: real,
}

struct RigReport {
    v: array<real, 10>,
}

struct RigEventValues {
    g: array<real, 5>,
}

fn rig_load(base: u32, ex: ExpInfo) -> RunConsts {
    var kc: RunConsts;
    kc.k11 = param(base, P_K11);
    kc.k12 = param(base, P_K12);
    kc.k14 = param(base, P_K14);
    kc.k16 = param(base, P_K16);
    kc.k34 = param(base, P_K34);
    kc.k36 = param(base, P_K36);
    kc.k37 = param(base, P_K37);
    kc.k45 = param(base, P_K45);
    kc.k46 = param(base, P_K46);
    kc.k47 = param(base, P_K47);
    kc.k48 = param(base, P_K48);
    kc.k49 = param(base, P_K49);
    kc.k50 = param(base, P_K50);
    kc.k51 = param(base, P_K51);
    kc.k52 = param(base, P_K52);
    kc.k68 = param(base, P_K68);
    kc.k71 = param(base, P_K71);
    kc.k76 = param(base, P_K76);
    kc.k78 = param(base, P_K78);
    kc.k83 = param(base, P_K83);
    kc.k89 = param(base, P_K89);
    kc.k90 = param(base, P_K90);
    kc.k91 = param(base, P_K91);
    kc.k99 = param(base, P_K99);
    kc.k100 = param(base, P_K100);
    kc.k105 = param(base, P_K105);
    kc.k116 = param(base, P_K116);
    kc.k123 = param(base, P_K123);
    kc.k128 = param(base, P_K128);
    kc.k133 = param(base, P_K133);
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
    m0: real,
}

fn rig_clock(kc: RunConsts, t: real) -> DriveClocks {
    var c: DriveClocks;
    c.m0 = expm1_r((-(kc.k16 * (real(1.0)))) * t);
    return c;
}

fn rig_clock_shift(kc: RunConsts, c: DriveClocks, q: DriveClocks, t: real) -> DriveClocks {
    var r = c;
    r.m0 = (c.m0 + q.m0) + c.m0 * q.m0;
    return r;
}

fn rig_deriv_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigState {
    let v0 = t;
    let v3 = y.s0;
    let v4 = y.s4;
    let v5 = y.s1;
    let v6 = y.s5;
    let v7 = y.s2;
    let v8 = y.s6;
    let v13 = select(real(0.0), real(1.0), v0 <= real(0e0));
    let v17 = kc.k16 * v0;
    let v18 = -v17;
    let v19 = ck.m0;
    let v20 = kc.k11 * v0;
    let v21 = kc.k12 * v19;
    let v22 = v20 + v21;
    let v23 = kc.k11 * v19;
    let v24 = -v23;
    let v28 = select(v22, v20, kc.k14 != real(0.0));
    let v29 = select(v24, kc.k11, kc.k14 != real(0.0));
    let v31 = select(v28, real(0e0), v13 != real(0.0));
    let v32 = select(v29, real(0e0), v13 != real(0.0));
    let v35 = kc.k34 * v3;
    let v38 = real(rg.r0);
    let v39 = select(real(0.0), real(1.0), v38 == real(1e0));
    let v40 = select(kc.k36, kc.k37, v39 != real(0.0));
    let v41 = v40 * v4;
    let v42 = v35 + v41;
    let v43 = v5 - v3;
    let v44 = v6 - v4;
    let v53 = kc.k52 * v43;
    let v54 = v53 + kc.k51;
    let v55 = v54 * v43;
    let v56 = v55 + kc.k50;
    let v57 = v56 * v43;
    let v58 = v57 + kc.k49;
    let v59 = v58 * v43;
    let v60 = v59 + kc.k48;
    let v61 = v60 * v43;
    let v62 = v61 + kc.k47;
    let v63 = kc.k45 * v43;
    let v65 = real(rg.r1);
    let v66 = select(real(0.0), real(1.0), v65 == real(1e0));
    let v67 = select(v63, v62, v66 != real(0.0));
    let v69 = kc.k68 * v44;
    let v70 = v67 + v69;
    let v73 = select(v70, real(0e0), v39 != real(0.0));
    let v74 = v7 - v5;
    let v75 = v8 - v6;
    let v77 = kc.k76 * v74;
    let v79 = kc.k78 * v75;
    let v80 = v77 + v79;
    let v81 = v31 - v7;
    let v82 = v32 - v8;
    let v84 = v81 - kc.k83;
    let v86 = real(rg.r2);
    let v87 = select(real(0.0), real(1.0), v86 == real(1e0));
    let v106 = kc.k89 * v84;
    let v107 = expm1_r(v106);
    let v108 = kc.k100 * v107;
    let v109 = kc.k90 * v84;
    let v110 = v108 + v109;
    let v111 = v84 - kc.k99;
    let v112 = kc.k91 * v111;
    let v113 = kc.k105 + v112;
    let v114 = select(real(0.0), real(1.0), v84 <= kc.k99);
    let v115 = select(v113, v110, v114 != real(0.0));
    let v117 = kc.k116 * v82;
    let v118 = v115 + v117;
    let v119 = select(real(0e0), v118, v87 != real(0.0));
    let v121 = v73 - v42;
    let v124 = v121 * kc.k123;
    let v126 = v80 - v73;
    let v129 = v126 * kc.k128;
    let v131 = v119 - v80;
    let v134 = v131 * kc.k133;
    var r: RigState;
    r.s0 = v4;
    r.s1 = v6;
    r.s2 = v8;
    r.s3 = real(0e0);
    r.s4 = v124;
    r.s5 = v129;
    r.s6 = v134;
    r.s7 = real(0e0);
    return r;
}

fn rig_events_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigEventValues {
    let v0 = t;
    let v3 = y.s0;
    let v5 = y.s1;
    let v7 = y.s2;
    let v13 = select(real(0.0), real(1.0), v0 <= real(0e0));
    let v17 = kc.k16 * v0;
    let v18 = -v17;
    let v19 = ck.m0;
    let v20 = kc.k11 * v0;
    let v21 = kc.k12 * v19;
    let v22 = v20 + v21;
    let v28 = select(v22, v20, kc.k14 != real(0.0));
    let v31 = select(v28, real(0e0), v13 != real(0.0));
    let v43 = v5 - v3;
    let v64 = v43 - kc.k46;
    let v72 = v43 - kc.k71;
    let v81 = v31 - v7;
    let v84 = v81 - kc.k83;
    var r: RigEventValues;
    r.g[0] = v64;
    r.g[1] = v64;
    r.g[2] = v72;
    r.g[3] = v84;
    r.g[4] = v84;
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
    let v0 = t;
    let v3 = y.s0;
    let v5 = y.s1;
    let v7 = y.s2;
    let v13 = select(real(0.0), real(1.0), v0 <= real(0e0));
    let v17 = kc.k16 * v0;
    let v18 = -v17;
    let v19 = ck.m0;
    let v20 = kc.k11 * v0;
    let v21 = kc.k12 * v19;
    let v22 = v20 + v21;
    let v28 = select(v22, v20, kc.k14 != real(0.0));
    let v31 = select(v28, real(0e0), v13 != real(0.0));
    let v43 = v5 - v3;
    let v81 = v31 - v7;
    var r: EventBases;
    r.b0 = v43;
    r.b1 = v81;
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
    w.hi0 = select(w.hi0, min(w.hi0, kc.k46), rg.r1 == 0u);
    w.hi0 = select(w.hi0, min(w.hi0, kc.k71), rg.r0 == 0u);
    w.lo0 = select(w.lo0, max(w.lo0, kc.k46), rg.r1 == 1u);
    w.lo1 = -REAL_MAX;
    w.hi1 = REAL_MAX;
    w.hi1 = select(w.hi1, min(w.hi1, kc.k83), rg.r2 == 0u);
    w.lo1 = select(w.lo1, max(w.lo1, kc.k83), rg.r2 == 1u);
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
    let v35 = kc.k34 * v3;
    let v38 = real(rg.r0);
    let v39 = select(real(0.0), real(1.0), v38 == real(1e0));
    let v40 = select(kc.k36, kc.k37, v39 != real(0.0));
    let v41 = v40 * v4;
    let v42 = v35 + v41;
    return v42;
}

fn rig_report_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigReport {
    let v0 = t;
    let v3 = y.s0;
    let v4 = y.s4;
    let v5 = y.s1;
    let v6 = y.s5;
    let v7 = y.s2;
    let v8 = y.s6;
    let v13 = select(real(0.0), real(1.0), v0 <= real(0e0));
    let v17 = kc.k16 * v0;
    let v18 = -v17;
    let v19 = ck.m0;
    let v20 = kc.k11 * v0;
    let v21 = kc.k12 * v19;
    let v22 = v20 + v21;
    let v23 = kc.k11 * v19;
    let v24 = -v23;
    let v28 = select(v22, v20, kc.k14 != real(0.0));
    let v29 = select(v24, kc.k11, kc.k14 != real(0.0));
    let v31 = select(v28, real(0e0), v13 != real(0.0));
    let v32 = select(v29, real(0e0), v13 != real(0.0));
    let v35 = kc.k34 * v3;
    let v38 = real(rg.r0);
    let v39 = select(real(0.0), real(1.0), v38 == real(1e0));
    let v40 = select(kc.k36, kc.k37, v39 != real(0.0));
    let v41 = v40 * v4;
    let v42 = v35 + v41;
    let v43 = v5 - v3;
    let v44 = v6 - v4;
    let v53 = kc.k52 * v43;
    let v54 = v53 + kc.k51;
    let v55 = v54 * v43;
    let v56 = v55 + kc.k50;
    let v57 = v56 * v43;
    let v58 = v57 + kc.k49;
    let v59 = v58 * v43;
    let v60 = v59 + kc.k48;
    let v61 = v60 * v43;
    let v62 = v61 + kc.k47;
    let v63 = kc.k45 * v43;
    let v65 = real(rg.r1);
    let v66 = select(real(0.0), real(1.0), v65 == real(1e0));
    let v67 = select(v63, v62, v66 != real(0.0));
    let v69 = kc.k68 * v44;
    let v70 = v67 + v69;
    let v73 = select(v70, real(0e0), v39 != real(0.0));
    var r: RigReport;
    r.v[0] = v42;
    r.v[1] = v73;
    r.v[2] = v3;
    r.v[3] = v5;
    r.v[4] = v7;
    r.v[5] = v31;
    r.v[6] = v4;
    r.v[7] = v6;
    r.v[8] = v8;
    r.v[9] = v32;
    return r;
}

fn rig_deriv(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigState {
    return rig_deriv_c(kc, t, y, rg, rig_clock(kc, t));
}

fn rig_events(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigEventValues {
    return rig_events_c(kc, t, y, rg, rig_clock(kc, t));
}

