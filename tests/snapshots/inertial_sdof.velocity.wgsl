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
    k6: real,
    k7: real,
    k8: real,
    k32: real,
    k33: real,
    k38: real,
    k41: real,
    k42: real,
    k54: real,
    k55: real,
    k68: real,
    k77: real,
}

struct RigReport {
    v: array<real, 6>,
}

struct RigEventValues {
    g: array<real, 1>,
}

fn rig_load(base: u32, ex: ExpInfo) -> RunConsts {
    var kc: RunConsts;
    kc.k6 = param(base, P_K6);
    kc.k7 = param(base, P_K7);
    kc.k8 = param(base, P_K8);
    kc.k32 = param(base, P_K32);
    kc.k33 = param(base, P_K33);
    kc.k38 = param(base, P_K38);
    kc.k41 = param(base, P_K41);
    kc.k42 = param(base, P_K42);
    kc.k54 = param(base, P_K54);
    kc.k55 = param(base, P_K55);
    kc.k68 = param(base, P_K68);
    kc.k77 = param(base, P_K77);
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
    let v0 = t;
    let v3 = y.s0;
    let v4 = y.s1;
    let v10 = kc.k8 * v0;
    let v11 = real(5e-1) * v10;
    let v12 = kc.k7 + v11;
    let v13 = v12 * v0;
    let v14 = real(6.283185307179586e0) * v13;
    let v18 = select(real(0.0), real(1.0), real(0e0) <= v0);
    let v19 = sin_r(v14);
    let v21 = kc.k6 * v19;
    let v29 = select(real(0e0), v21, v18 != real(0.0));
    let v34 = kc.k33 * v3;
    let v35 = v34 * v3;
    let v36 = v35 + kc.k32;
    let v37 = v36 * v3;
    let v39 = kc.k38 * v4;
    let v40 = v37 + v39;
    let v43 = abs(v3);
    let v44 = select(real(0.0), real(1.0), v43 <= real(0e0));
    let v45 = select(v43, real(1e0), v44 != real(0.0));
    let v46 = ln_r(v45);
    let v47 = kc.k42 * v46;
    let v48 = exp_r(v47);
    let v49 = select(v48, real(0e0), v44 != real(0.0));
    let v50 = select(real(0.0), real(1.0), v3 <= real(0e0));
    let v51 = -v49;
    let v52 = select(v49, v51, v50 != real(0.0));
    let v53 = kc.k41 * v52;
    let v56 = abs(v4);
    let v57 = select(real(0.0), real(1.0), v56 <= real(0e0));
    let v58 = select(v56, real(1e0), v57 != real(0.0));
    let v59 = ln_r(v58);
    let v60 = kc.k55 * v59;
    let v61 = exp_r(v60);
    let v62 = select(v61, real(0e0), v57 != real(0.0));
    let v63 = select(real(0.0), real(1.0), v4 <= real(0e0));
    let v64 = -v62;
    let v65 = select(v62, v64, v63 != real(0.0));
    let v66 = kc.k54 * v65;
    let v67 = v53 + v66;
    let v70 = v4 * v56;
    let v71 = v70 * v56;
    let v72 = kc.k68 * v71;
    let v73 = real(0e0) - v40;
    let v74 = v73 - v67;
    let v75 = v74 - v72;
    let v78 = v75 * kc.k77;
    let v79 = v78 - v29;
    var r: RigState;
    r.s0 = v4;
    r.s1 = v79;
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
    let v0 = t;
    let v3 = y.s0;
    let v4 = y.s1;
    let v10 = kc.k8 * v0;
    let v11 = real(5e-1) * v10;
    let v12 = kc.k7 + v11;
    let v13 = v12 * v0;
    let v14 = real(6.283185307179586e0) * v13;
    let v18 = select(real(0.0), real(1.0), real(0e0) <= v0);
    let v19 = sin_r(v14);
    let v21 = kc.k6 * v19;
    let v29 = select(real(0e0), v21, v18 != real(0.0));
    let v34 = kc.k33 * v3;
    let v35 = v34 * v3;
    let v36 = v35 + kc.k32;
    let v37 = v36 * v3;
    let v39 = kc.k38 * v4;
    let v40 = v37 + v39;
    let v43 = abs(v3);
    let v44 = select(real(0.0), real(1.0), v43 <= real(0e0));
    let v45 = select(v43, real(1e0), v44 != real(0.0));
    let v46 = ln_r(v45);
    let v47 = kc.k42 * v46;
    let v48 = exp_r(v47);
    let v49 = select(v48, real(0e0), v44 != real(0.0));
    let v50 = select(real(0.0), real(1.0), v3 <= real(0e0));
    let v51 = -v49;
    let v52 = select(v49, v51, v50 != real(0.0));
    let v53 = kc.k41 * v52;
    let v56 = abs(v4);
    let v57 = select(real(0.0), real(1.0), v56 <= real(0e0));
    let v58 = select(v56, real(1e0), v57 != real(0.0));
    let v59 = ln_r(v58);
    let v60 = kc.k55 * v59;
    let v61 = exp_r(v60);
    let v62 = select(v61, real(0e0), v57 != real(0.0));
    let v63 = select(real(0.0), real(1.0), v4 <= real(0e0));
    let v64 = -v62;
    let v65 = select(v62, v64, v63 != real(0.0));
    let v66 = kc.k54 * v65;
    let v67 = v53 + v66;
    let v70 = v4 * v56;
    let v71 = v70 * v56;
    let v72 = kc.k68 * v71;
    let v73 = real(0e0) - v40;
    let v74 = v73 - v67;
    let v75 = v74 - v72;
    let v78 = v75 * kc.k77;
    let v79 = v78 - v29;
    let v80 = v40 + v67;
    let v81 = v80 + v72;
    var r: RigReport;
    r.v[0] = v3;
    r.v[1] = v81;
    r.v[2] = v4;
    r.v[3] = v79;
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

