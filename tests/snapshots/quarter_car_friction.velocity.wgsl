// Generated from the rig description by src/compile/back/wgsl/.

const RIG_STATES: u32 = 7u;
const RIG_MODES: u32 = 2u;
const RIG_REPORT: u32 = 14u;

struct RigState {
    s0: real,
    s1: real,
    s2: real,
    s3: real,
    s4: real,
    s5: real,
    s6: real,
}

struct RigRegime {
    m0: u32,
    m1: u32,
}

struct RunConsts {
    k10: real,
    k11: real,
    k12: real,
    k21: real,
    k39: real,
    k41: real,
    k46: real,
    k48: real,
    k49: real,
    k50: real,
    k54: real,
    k63: real,
    k70: real,
    k75: real,
    k76: real,
    k89: real,
    k95: real,
}

struct RigReport {
    v: array<real, 14>,
}

struct RigEventValues {
    g: array<real, 8>,
}

fn rig_load(base: u32, ex: ExpInfo) -> RunConsts {
    var kc: RunConsts;
    kc.k10 = param(base, P_K10);
    kc.k11 = param(base, P_K11);
    kc.k12 = param(base, P_K12);
    kc.k21 = param(base, P_K21);
    kc.k39 = param(base, P_K39);
    kc.k41 = param(base, P_K41);
    kc.k46 = param(base, P_K46);
    kc.k48 = param(base, P_K48);
    kc.k49 = param(base, P_K49);
    kc.k50 = param(base, P_K50);
    kc.k54 = param(base, P_K54);
    kc.k63 = param(base, P_K63);
    kc.k70 = param(base, P_K70);
    kc.k75 = param(base, P_K75);
    kc.k76 = param(base, P_K76);
    kc.k89 = param(base, P_K89);
    kc.k95 = param(base, P_K95);
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
    return y;
}

fn rig_regimes_load(sb: u32) -> RigRegime {
    var md: RigRegime;
    md.m0 = u32(state[sb + 7u]);
    md.m1 = u32(state[sb + 8u]);
    return md;
}

fn rig_initial(base: u32, y: ptr<function, RigState>, md: ptr<function, RigRegime>) {
}

fn rig_state_store(sb: u32, y: RigState, md: RigRegime) {
    state[sb + 0u] = y.s0;
    state[sb + 1u] = y.s1;
    state[sb + 2u] = y.s2;
    state[sb + 3u] = y.s3;
    state[sb + 4u] = y.s4;
    state[sb + 5u] = y.s5;
    state[sb + 6u] = y.s6;
    state[sb + 7u] = real(md.m0);
    state[sb + 8u] = real(md.m1);
}

const RIG_ACC: u32 = 9u;

fn st_axpy(y: RigState, a: real, k: RigState) -> RigState {
    var r: RigState;
    r.s0 = y.s0 + a * k.s0;
    r.s1 = y.s1 + a * k.s1;
    r.s2 = y.s2 + a * k.s2;
    r.s3 = y.s3 + a * k.s3;
    r.s4 = y.s4 + a * k.s4;
    r.s5 = y.s5 + a * k.s5;
    r.s6 = y.s6 + a * k.s6;
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

fn rig_clock_shift(c: DriveClocks, q: DriveClocks) -> DriveClocks {
    var r = c;
    return r;
}

fn rig_deriv_c(kc: RunConsts, t: real, y: RigState, md: RigRegime, ck: DriveClocks) -> RigState {
    let v0 = t;
    let v5 = y.s1;
    let v6 = y.s4;
    let v7 = y.s2;
    let v8 = y.s5;
    let v14 = kc.k12 * v0;
    let v15 = real(5e-1) * v14;
    let v16 = kc.k11 + v15;
    let v17 = v16 * v0;
    let v18 = real(6.283185307179586e0) * v17;
    let v19 = kc.k11 + v14;
    let v20 = real(6.283185307179586e0) * v19;
    let v22 = select(real(0.0), real(1.0), v0 <= real(0e0));
    let v23 = select(real(1e0), real(0e0), v22 != real(0.0));
    let v24 = sin_r(v18);
    let v25 = cos_r(v18);
    let v26 = kc.k10 * v24;
    let v27 = v25 * v20;
    let v28 = kc.k10 * v27;
    let v34 = select(real(0e0), v26, v23 != real(0.0));
    let v35 = select(real(0e0), v28, v23 != real(0.0));
    let v37 = v5 - v34;
    let v38 = v6 - v35;
    let v40 = kc.k39 * v37;
    let v42 = kc.k41 * v38;
    let v43 = v40 + v42;
    let v44 = v7 - v5;
    let v45 = v8 - v6;
    let v47 = kc.k46 * v44;
    let v51 = abs(v45);
    let v52 = select(real(0.0), real(1.0), v51 <= kc.k50);
    let v53 = kc.k48 * v45;
    let v55 = v51 - kc.k50;
    let v56 = kc.k49 * v55;
    let v57 = kc.k54 + v56;
    let v58 = select(real(0.0), real(1.0), v45 <= real(0e0));
    let v59 = -v57;
    let v60 = select(v57, v59, v58 != real(0.0));
    let v61 = select(v60, v53, v52 != real(0.0));
    let v62 = v47 + v61;
    let v64 = v44 - kc.k63;
    let v65 = v44 + kc.k63;
    let v66 = real(md.m0);
    let v67 = select(real(0.0), real(1.0), v66 == real(1e0));
    let v69 = select(real(0.0), real(1.0), v66 == real(2e0));
    let v71 = kc.k70 * v64;
    let v72 = kc.k70 * v65;
    let v73 = select(real(0e0), v72, v69 != real(0.0));
    let v74 = select(v73, v71, v67 != real(0.0));
    let v77 = y.s6;
    let v78 = kc.k76 * v77;
    let v81 = real(md.m1);
    let v82 = select(real(0.0), real(1.0), v81 == real(0e0));
    let v83 = select(real(0e0), v45, v82 != real(0.0));
    let v85 = v62 - v43;
    let v86 = v85 + v74;
    let v87 = v86 + v78;
    let v90 = v87 * kc.k89;
    let v91 = real(0e0) - v62;
    let v92 = v91 - v74;
    let v93 = v92 - v78;
    let v96 = v93 * kc.k95;
    var r: RigState;
    r.s0 = real(0e0);
    r.s1 = v6;
    r.s2 = v8;
    r.s3 = real(0e0);
    r.s4 = v90;
    r.s5 = v96;
    r.s6 = v83;
    return r;
}

fn rig_events_c(kc: RunConsts, t: real, y: RigState, md: RigRegime, ck: DriveClocks) -> RigEventValues {
    let v5 = y.s1;
    let v6 = y.s4;
    let v7 = y.s2;
    let v8 = y.s5;
    let v44 = v7 - v5;
    let v45 = v8 - v6;
    let v64 = v44 - kc.k63;
    let v65 = v44 + kc.k63;
    let v77 = y.s6;
    let v78 = kc.k76 * v77;
    let v79 = v78 - kc.k75;
    let v80 = v78 + kc.k75;
    var r: RigEventValues;
    r.g[0] = v64;
    r.g[1] = v64;
    r.g[2] = v65;
    r.g[3] = v65;
    r.g[4] = v79;
    r.g[5] = v80;
    r.g[6] = v45;
    r.g[7] = v45;
    return r;
}

fn rig_hits(g0: RigEventValues, g1: RigEventValues, md: RigRegime) -> u32 {
    var hits = 0u;
    hits |= select(0u, 1u, md.m0 == 0u && g1.g[0] >= real(0.0) && (!(g0.g[0] >= real(0.0)) || g1.g[0] > g0.g[0]));
    hits |= select(0u, 2u, md.m0 == 1u && -(g1.g[1]) >= real(0.0) && (!(-(g0.g[1]) >= real(0.0)) || -(g1.g[1]) > -(g0.g[1])));
    hits |= select(0u, 4u, md.m0 == 0u && -(g1.g[2]) >= real(0.0) && (!(-(g0.g[2]) >= real(0.0)) || -(g1.g[2]) > -(g0.g[2])));
    hits |= select(0u, 8u, md.m0 == 2u && g1.g[3] >= real(0.0) && (!(g0.g[3] >= real(0.0)) || g1.g[3] > g0.g[3]));
    hits |= select(0u, 16u, md.m1 == 0u && g1.g[4] >= real(0.0) && (!(g0.g[4] >= real(0.0)) || g1.g[4] > g0.g[4]));
    hits |= select(0u, 32u, md.m1 == 0u && -(g1.g[5]) >= real(0.0) && (!(-(g0.g[5]) >= real(0.0)) || -(g1.g[5]) > -(g0.g[5])));
    hits |= select(0u, 64u, md.m1 == 1u && -(g1.g[6]) >= real(0.0) && (!(-(g0.g[6]) >= real(0.0)) || -(g1.g[6]) > -(g0.g[6])));
    hits |= select(0u, 128u, md.m1 == 2u && g1.g[7] >= real(0.0) && (!(g0.g[7] >= real(0.0)) || g1.g[7] > g0.g[7]));
    return hits;
}

struct EventBases {
    b0: real,
    b1: real,
    b2: real,
    b3: real,
    b4: real,
}

fn rig_bases_c(kc: RunConsts, t: real, y: RigState, md: RigRegime, ck: DriveClocks) -> EventBases {
    let v5 = y.s1;
    let v6 = y.s4;
    let v7 = y.s2;
    let v8 = y.s5;
    let v44 = v7 - v5;
    let v45 = v8 - v6;
    let v65 = v44 + kc.k63;
    let v77 = y.s6;
    let v78 = kc.k76 * v77;
    let v80 = v78 + kc.k75;
    var r: EventBases;
    r.b0 = v44;
    r.b1 = v65;
    r.b2 = v78;
    r.b3 = v80;
    r.b4 = v45;
    return r;
}

struct EventWindows {
    lo0: real,
    lo1: real,
    lo2: real,
    lo3: real,
    lo4: real,
    hi0: real,
    hi1: real,
    hi2: real,
    hi3: real,
    hi4: real,
}

fn rig_window(kc: RunConsts, md: RigRegime) -> EventWindows {
    var w: EventWindows;
    w.lo0 = -REAL_MAX;
    w.hi0 = REAL_MAX;
    w.hi0 = select(w.hi0, min(w.hi0, kc.k63), md.m0 == 0u);
    w.lo0 = select(w.lo0, max(w.lo0, kc.k63), md.m0 == 1u);
    w.lo1 = -REAL_MAX;
    w.hi1 = REAL_MAX;
    w.hi1 = select(w.hi1, min(w.hi1, real(0.0)), md.m0 == 2u);
    w.lo1 = select(w.lo1, max(w.lo1, real(0.0)), md.m0 == 0u);
    w.lo2 = -REAL_MAX;
    w.hi2 = REAL_MAX;
    w.hi2 = select(w.hi2, min(w.hi2, kc.k75), md.m1 == 0u);
    w.lo3 = -REAL_MAX;
    w.hi3 = REAL_MAX;
    w.lo3 = select(w.lo3, max(w.lo3, real(0.0)), md.m1 == 0u);
    w.lo4 = -REAL_MAX;
    w.hi4 = REAL_MAX;
    w.hi4 = select(w.hi4, min(w.hi4, real(0.0)), md.m1 == 2u);
    w.lo4 = select(w.lo4, max(w.lo4, real(0.0)), md.m1 == 1u);
    return w;
}

fn rig_outside(w: EventWindows, b: EventBases) -> bool {
    return b.b0 - w.hi0 >= real(0.0)
        | b.b0 - w.lo0 <= real(0.0)
        | b.b1 - w.hi1 >= real(0.0)
        | b.b1 - w.lo1 <= real(0.0)
        | b.b2 - w.hi2 >= real(0.0)
        | b.b3 - w.lo3 <= real(0.0)
        | b.b4 - w.hi4 >= real(0.0)
        | b.b4 - w.lo4 <= real(0.0);
}

fn rig_oriented(g: RigEventValues, i: u32) -> real {
    switch i {
        case 0u: { return g.g[0]; }
        case 1u: { return -(g.g[1]); }
        case 2u: { return -(g.g[2]); }
        case 3u: { return g.g[3]; }
        case 4u: { return g.g[4]; }
        case 5u: { return -(g.g[5]); }
        case 6u: { return -(g.g[6]); }
        case 7u: { return g.g[7]; }
        default: { return real(0.0); }
    }
}

fn rig_fire(i: u32, md: ptr<function, RigRegime>) {
    switch i {
        case 0u: { (*md).m0 = 1u; }
        case 1u: { (*md).m0 = 0u; }
        case 2u: { (*md).m0 = 2u; }
        case 3u: { (*md).m0 = 0u; }
        case 4u: { (*md).m1 = 1u; }
        case 5u: { (*md).m1 = 2u; }
        case 6u: { (*md).m1 = 0u; }
        case 7u: { (*md).m1 = 0u; }
        default: {}
    }
}

fn rig_output0_c(kc: RunConsts, t: real, y: RigState, md: RigRegime, ck: DriveClocks) -> real {
    let v5 = y.s1;
    let v6 = y.s4;
    let v7 = y.s2;
    let v8 = y.s5;
    let v44 = v7 - v5;
    let v45 = v8 - v6;
    let v47 = kc.k46 * v44;
    let v51 = abs(v45);
    let v52 = select(real(0.0), real(1.0), v51 <= kc.k50);
    let v53 = kc.k48 * v45;
    let v55 = v51 - kc.k50;
    let v56 = kc.k49 * v55;
    let v57 = kc.k54 + v56;
    let v58 = select(real(0.0), real(1.0), v45 <= real(0e0));
    let v59 = -v57;
    let v60 = select(v57, v59, v58 != real(0.0));
    let v61 = select(v60, v53, v52 != real(0.0));
    let v62 = v47 + v61;
    let v64 = v44 - kc.k63;
    let v65 = v44 + kc.k63;
    let v66 = real(md.m0);
    let v67 = select(real(0.0), real(1.0), v66 == real(1e0));
    let v69 = select(real(0.0), real(1.0), v66 == real(2e0));
    let v71 = kc.k70 * v64;
    let v72 = kc.k70 * v65;
    let v73 = select(real(0e0), v72, v69 != real(0.0));
    let v74 = select(v73, v71, v67 != real(0.0));
    let v77 = y.s6;
    let v78 = kc.k76 * v77;
    let v91 = real(0e0) - v62;
    let v92 = v91 - v74;
    let v93 = v92 - v78;
    let v96 = v93 * kc.k95;
    return v96;
}

fn rig_report_c(kc: RunConsts, t: real, y: RigState, md: RigRegime, ck: DriveClocks) -> RigReport {
    let v0 = t;
    let v5 = y.s1;
    let v6 = y.s4;
    let v7 = y.s2;
    let v8 = y.s5;
    let v14 = kc.k12 * v0;
    let v15 = real(5e-1) * v14;
    let v16 = kc.k11 + v15;
    let v17 = v16 * v0;
    let v18 = real(6.283185307179586e0) * v17;
    let v19 = kc.k11 + v14;
    let v20 = real(6.283185307179586e0) * v19;
    let v22 = select(real(0.0), real(1.0), v0 <= real(0e0));
    let v23 = select(real(1e0), real(0e0), v22 != real(0.0));
    let v24 = sin_r(v18);
    let v25 = cos_r(v18);
    let v26 = kc.k10 * v24;
    let v27 = v25 * v20;
    let v28 = kc.k10 * v27;
    let v29 = v20 * v20;
    let v30 = v24 * v29;
    let v31 = v25 * kc.k21;
    let v32 = v31 - v30;
    let v33 = kc.k10 * v32;
    let v34 = select(real(0e0), v26, v23 != real(0.0));
    let v35 = select(real(0e0), v28, v23 != real(0.0));
    let v36 = select(real(0e0), v33, v23 != real(0.0));
    let v37 = v5 - v34;
    let v38 = v6 - v35;
    let v40 = kc.k39 * v37;
    let v42 = kc.k41 * v38;
    let v43 = v40 + v42;
    let v44 = v7 - v5;
    let v45 = v8 - v6;
    let v47 = kc.k46 * v44;
    let v51 = abs(v45);
    let v52 = select(real(0.0), real(1.0), v51 <= kc.k50);
    let v53 = kc.k48 * v45;
    let v55 = v51 - kc.k50;
    let v56 = kc.k49 * v55;
    let v57 = kc.k54 + v56;
    let v58 = select(real(0.0), real(1.0), v45 <= real(0e0));
    let v59 = -v57;
    let v60 = select(v57, v59, v58 != real(0.0));
    let v61 = select(v60, v53, v52 != real(0.0));
    let v62 = v47 + v61;
    let v64 = v44 - kc.k63;
    let v65 = v44 + kc.k63;
    let v66 = real(md.m0);
    let v67 = select(real(0.0), real(1.0), v66 == real(1e0));
    let v69 = select(real(0.0), real(1.0), v66 == real(2e0));
    let v71 = kc.k70 * v64;
    let v72 = kc.k70 * v65;
    let v73 = select(real(0e0), v72, v69 != real(0.0));
    let v74 = select(v73, v71, v67 != real(0.0));
    let v77 = y.s6;
    let v78 = kc.k76 * v77;
    let v85 = v62 - v43;
    let v86 = v85 + v74;
    let v87 = v86 + v78;
    let v90 = v87 * kc.k89;
    let v91 = real(0e0) - v62;
    let v92 = v91 - v74;
    let v93 = v92 - v78;
    let v96 = v93 * kc.k95;
    let v97 = v62 + v74;
    let v98 = v97 + v78;
    let v100 = real(-1e0) * v5;
    let v101 = v7 + v100;
    let v102 = real(-1e0) * v6;
    let v103 = v8 + v102;
    var r: RigReport;
    r.v[0] = v96;
    r.v[1] = v90;
    r.v[2] = v36;
    r.v[3] = v98;
    r.v[4] = v78;
    r.v[5] = v101;
    r.v[6] = v103;
    r.v[7] = v34;
    r.v[8] = v5;
    r.v[9] = v7;
    r.v[10] = v35;
    r.v[11] = v6;
    r.v[12] = v8;
    r.v[13] = v77;
    return r;
}

fn rig_deriv(kc: RunConsts, t: real, y: RigState, md: RigRegime) -> RigState {
    return rig_deriv_c(kc, t, y, md, rig_clock(kc, t));
}

fn rig_events(kc: RunConsts, t: real, y: RigState, md: RigRegime) -> RigEventValues {
    return rig_events_c(kc, t, y, md, rig_clock(kc, t));
}

