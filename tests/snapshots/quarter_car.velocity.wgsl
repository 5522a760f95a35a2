// Generated from the rig description by src/compile/back/wgsl/.

const RIG_STATES: u32 = 6u;
const RIG_REGIMES: u32 = 1u;
const RIG_SWITCHES: bool = true;
const RIG_REPORT: u32 = 12u;

struct RigState {
    s0: real,
    s1: real,
    s2: real,
    s3: real,
    s4: real,
    s5: real,
}

struct RigRegime {
    r0: u32,
}

struct RunConsts {
    k10: real,
    k11: real,
    k12: real,
    k21: real,
    k38: real,
    k40: real,
    k45: real,
    k47: real,
    k48: real,
    k49: real,
    k53: real,
    k62: real,
    k69: real,
    k78: real,
    k83: real,
}

struct RigReport {
    v: array<real, 12>,
}

struct RigEventValues {
    g: array<real, 4>,
}

fn rig_load(base: u32, ex: ExpInfo) -> RunConsts {
    var kc: RunConsts;
    kc.k10 = param(base, P_K10);
    kc.k11 = param(base, P_K11);
    kc.k12 = param(base, P_K12);
    kc.k21 = param(base, P_K21);
    kc.k38 = param(base, P_K38);
    kc.k40 = param(base, P_K40);
    kc.k45 = param(base, P_K45);
    kc.k47 = param(base, P_K47);
    kc.k48 = param(base, P_K48);
    kc.k49 = param(base, P_K49);
    kc.k53 = param(base, P_K53);
    kc.k62 = param(base, P_K62);
    kc.k69 = param(base, P_K69);
    kc.k78 = param(base, P_K78);
    kc.k83 = param(base, P_K83);
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
    return y;
}

fn rig_regimes_load(sb: u32) -> RigRegime {
    var rg: RigRegime;
    rg.r0 = u32(state[sb + 6u]);
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
    state[sb + 6u] = real(rg.r0);
}

const RIG_ACC: u32 = 7u;

fn st_axpy(y: RigState, a: real, k: RigState) -> RigState {
    var r: RigState;
    r.s0 = y.s0 + a * k.s0;
    r.s1 = y.s1 + a * k.s1;
    r.s2 = y.s2 + a * k.s2;
    r.s3 = y.s3 + a * k.s3;
    r.s4 = y.s4 + a * k.s4;
    r.s5 = y.s5 + a * k.s5;
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
    let v22 = select(real(0.0), real(1.0), real(0e0) <= v0);
    let v23 = sin_r(v18);
    let v24 = cos_r(v18);
    let v25 = kc.k10 * v23;
    let v26 = v24 * v20;
    let v27 = kc.k10 * v26;
    let v33 = select(real(0e0), v25, v22 != real(0.0));
    let v34 = select(real(0e0), v27, v22 != real(0.0));
    let v36 = v5 - v33;
    let v37 = v6 - v34;
    let v39 = kc.k38 * v36;
    let v41 = kc.k40 * v37;
    let v42 = v39 + v41;
    let v43 = v7 - v5;
    let v44 = v8 - v6;
    let v46 = kc.k45 * v43;
    let v50 = abs(v44);
    let v51 = select(real(0.0), real(1.0), v50 <= kc.k49);
    let v52 = kc.k47 * v44;
    let v54 = v50 - kc.k49;
    let v55 = kc.k48 * v54;
    let v56 = kc.k53 + v55;
    let v57 = select(real(0.0), real(1.0), v44 <= real(0e0));
    let v58 = -v56;
    let v59 = select(v56, v58, v57 != real(0.0));
    let v60 = select(v59, v52, v51 != real(0.0));
    let v61 = v46 + v60;
    let v63 = v43 - kc.k62;
    let v64 = v43 + kc.k62;
    let v65 = real(rg.r0);
    let v66 = select(real(0.0), real(1.0), v65 == real(1e0));
    let v68 = select(real(0.0), real(1.0), v65 == real(2e0));
    let v70 = kc.k69 * v63;
    let v71 = kc.k69 * v64;
    let v72 = select(real(0e0), v71, v68 != real(0.0));
    let v73 = select(v72, v70, v66 != real(0.0));
    let v75 = v61 - v42;
    let v76 = v75 + v73;
    let v79 = v76 * kc.k78;
    let v80 = real(0e0) - v61;
    let v81 = v80 - v73;
    let v84 = v81 * kc.k83;
    var r: RigState;
    r.s0 = real(0e0);
    r.s1 = v6;
    r.s2 = v8;
    r.s3 = real(0e0);
    r.s4 = v79;
    r.s5 = v84;
    return r;
}

fn rig_events_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigEventValues {
    let v5 = y.s1;
    let v7 = y.s2;
    let v43 = v7 - v5;
    let v63 = v43 - kc.k62;
    let v64 = v43 + kc.k62;
    var r: RigEventValues;
    r.g[0] = v63;
    r.g[1] = v63;
    r.g[2] = v64;
    r.g[3] = v64;
    return r;
}

fn rig_hits(g0: RigEventValues, g1: RigEventValues, rg: RigRegime) -> u32 {
    var hits = 0u;
    hits |= select(0u, 1u, rg.r0 == 0u && g1.g[0] >= real(0.0) && (!(g0.g[0] >= real(0.0)) || g1.g[0] > g0.g[0]));
    hits |= select(0u, 2u, rg.r0 == 1u && -(g1.g[1]) >= real(0.0) && (!(-(g0.g[1]) >= real(0.0)) || -(g1.g[1]) > -(g0.g[1])));
    hits |= select(0u, 4u, rg.r0 == 0u && -(g1.g[2]) >= real(0.0) && (!(-(g0.g[2]) >= real(0.0)) || -(g1.g[2]) > -(g0.g[2])));
    hits |= select(0u, 8u, rg.r0 == 2u && g1.g[3] >= real(0.0) && (!(g0.g[3] >= real(0.0)) || g1.g[3] > g0.g[3]));
    return hits;
}

struct EventBases {
    b0: real,
    b1: real,
}

fn rig_bases_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> EventBases {
    let v5 = y.s1;
    let v7 = y.s2;
    let v43 = v7 - v5;
    let v64 = v43 + kc.k62;
    var r: EventBases;
    r.b0 = v43;
    r.b1 = v64;
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
    w.hi0 = select(w.hi0, min(w.hi0, kc.k62), rg.r0 == 0u);
    w.lo0 = select(w.lo0, max(w.lo0, kc.k62), rg.r0 == 1u);
    w.lo1 = -REAL_MAX;
    w.hi1 = REAL_MAX;
    w.hi1 = select(w.hi1, min(w.hi1, real(0.0)), rg.r0 == 2u);
    w.lo1 = select(w.lo1, max(w.lo1, real(0.0)), rg.r0 == 0u);
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
        case 2u: { return -(g.g[2]); }
        case 3u: { return g.g[3]; }
        default: { return real(0.0); }
    }
}

fn rig_fire(i: u32, rg: ptr<function, RigRegime>) {
    switch i {
        case 0u: { (*rg).r0 = 1u; }
        case 1u: { (*rg).r0 = 0u; }
        case 2u: { (*rg).r0 = 2u; }
        case 3u: { (*rg).r0 = 0u; }
        default: {}
    }
}

fn rig_output0_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> real {
    let v5 = y.s1;
    let v6 = y.s4;
    let v7 = y.s2;
    let v8 = y.s5;
    let v43 = v7 - v5;
    let v44 = v8 - v6;
    let v46 = kc.k45 * v43;
    let v50 = abs(v44);
    let v51 = select(real(0.0), real(1.0), v50 <= kc.k49);
    let v52 = kc.k47 * v44;
    let v54 = v50 - kc.k49;
    let v55 = kc.k48 * v54;
    let v56 = kc.k53 + v55;
    let v57 = select(real(0.0), real(1.0), v44 <= real(0e0));
    let v58 = -v56;
    let v59 = select(v56, v58, v57 != real(0.0));
    let v60 = select(v59, v52, v51 != real(0.0));
    let v61 = v46 + v60;
    let v63 = v43 - kc.k62;
    let v64 = v43 + kc.k62;
    let v65 = real(rg.r0);
    let v66 = select(real(0.0), real(1.0), v65 == real(1e0));
    let v68 = select(real(0.0), real(1.0), v65 == real(2e0));
    let v70 = kc.k69 * v63;
    let v71 = kc.k69 * v64;
    let v72 = select(real(0e0), v71, v68 != real(0.0));
    let v73 = select(v72, v70, v66 != real(0.0));
    let v80 = real(0e0) - v61;
    let v81 = v80 - v73;
    let v84 = v81 * kc.k83;
    return v84;
}

fn rig_report_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigReport {
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
    let v22 = select(real(0.0), real(1.0), real(0e0) <= v0);
    let v23 = sin_r(v18);
    let v24 = cos_r(v18);
    let v25 = kc.k10 * v23;
    let v26 = v24 * v20;
    let v27 = kc.k10 * v26;
    let v28 = v20 * v20;
    let v29 = v23 * v28;
    let v30 = v24 * kc.k21;
    let v31 = v30 - v29;
    let v32 = kc.k10 * v31;
    let v33 = select(real(0e0), v25, v22 != real(0.0));
    let v34 = select(real(0e0), v27, v22 != real(0.0));
    let v35 = select(real(0e0), v32, v22 != real(0.0));
    let v36 = v5 - v33;
    let v37 = v6 - v34;
    let v39 = kc.k38 * v36;
    let v41 = kc.k40 * v37;
    let v42 = v39 + v41;
    let v43 = v7 - v5;
    let v44 = v8 - v6;
    let v46 = kc.k45 * v43;
    let v50 = abs(v44);
    let v51 = select(real(0.0), real(1.0), v50 <= kc.k49);
    let v52 = kc.k47 * v44;
    let v54 = v50 - kc.k49;
    let v55 = kc.k48 * v54;
    let v56 = kc.k53 + v55;
    let v57 = select(real(0.0), real(1.0), v44 <= real(0e0));
    let v58 = -v56;
    let v59 = select(v56, v58, v57 != real(0.0));
    let v60 = select(v59, v52, v51 != real(0.0));
    let v61 = v46 + v60;
    let v63 = v43 - kc.k62;
    let v64 = v43 + kc.k62;
    let v65 = real(rg.r0);
    let v66 = select(real(0.0), real(1.0), v65 == real(1e0));
    let v68 = select(real(0.0), real(1.0), v65 == real(2e0));
    let v70 = kc.k69 * v63;
    let v71 = kc.k69 * v64;
    let v72 = select(real(0e0), v71, v68 != real(0.0));
    let v73 = select(v72, v70, v66 != real(0.0));
    let v75 = v61 - v42;
    let v76 = v75 + v73;
    let v79 = v76 * kc.k78;
    let v80 = real(0e0) - v61;
    let v81 = v80 - v73;
    let v84 = v81 * kc.k83;
    let v85 = v61 + v73;
    let v87 = real(-1e0) * v5;
    let v88 = v7 + v87;
    let v89 = real(-1e0) * v6;
    let v90 = v8 + v89;
    var r: RigReport;
    r.v[0] = v84;
    r.v[1] = v79;
    r.v[2] = v35;
    r.v[3] = v85;
    r.v[4] = v88;
    r.v[5] = v90;
    r.v[6] = v33;
    r.v[7] = v5;
    r.v[8] = v7;
    r.v[9] = v34;
    r.v[10] = v6;
    r.v[11] = v8;
    return r;
}

fn rig_deriv(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigState {
    return rig_deriv_c(kc, t, y, rg, rig_clock(kc, t));
}

fn rig_events(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigEventValues {
    return rig_events_c(kc, t, y, rg, rig_clock(kc, t));
}

