// The tensile4 rig for the ensemble kernels. Keep in sync with
// src/model/tensile.rs (equations, written there in f64) and
// src/model/tensile_gpu.rs (the packed P_* slots, derived constants).
//
// Differences from the CPU text, all within the parity tolerance: divisions by
// masses are multiplications by 1/m packed on the host; a/b of the slack law
// and v/r of the drive are packed as one value each; the drive's exponential at
// t + h/2 and t + h is e(t)·e^{−v·h/2r}, and e(t) itself is carried from step to
// step by the run loop (see rig_clock); piecewise laws are selects (CPU drivers
// run both sides of a branch anyway).

// The actuator at the stage times t, t + h/2 and t + h of one RK4 step.
struct Actuation {
    a0: vec3<real>,
    am: vec3<real>,
    a1: vec3<real>,
}

struct Rig {
    k1: real,
    // c1 before fracture, c1_post after.
    c1_now: real,
    c1_post: real,
    inv_m1: real,
    inv_m2: real,
    inv_m3: real,
    inv_m4: real,
    k_lin: real,
    e_yield: real,
    a0: real,
    a1: real,
    a2: real,
    a3: real,
    a4: real,
    a5: real,
    e_fracture: real,
    c2: real,
    k3: real,
    c3: real,
    slack_a_over_b: real,
    slack_b: real,
    slack_c: real,
    k4_lin: real,
    c4: real,
    gap: real,
    d_star: real,
    g_star: real,
    velocity: real,
    ramp: real,
    // v/r (0 without a ramp), so the drive exponent needs no division.
    v_over_r: real,
    // v²/r, the same f64 the CPU computes.
    v2_over_r: real,
    broken: bool,
    drive_kind: u32,
    table_offset: u32,
    table_len: u32,
}

fn rig_load(base: u32, ex: ExpInfo) -> Rig {
    return Rig(
        param(base, P_K1),
        param(base, P_C1),
        param(base, P_C1_POST),
        param(base, P_INV_M1),
        param(base, P_INV_M2),
        param(base, P_INV_M3),
        param(base, P_INV_M4),
        param(base, P_K_LIN),
        param(base, P_E_YIELD),
        param(base, P_A0),
        param(base, P_A1),
        param(base, P_A2),
        param(base, P_A3),
        param(base, P_A4),
        param(base, P_A5),
        param(base, P_E_FRACTURE),
        param(base, P_C2),
        param(base, P_K3),
        param(base, P_C3),
        param(base, P_SLACK_A_OVER_B),
        param(base, P_SLACK_B),
        param(base, P_SLACK_C),
        param(base, P_K4_LIN),
        param(base, P_C4),
        param(base, P_GAP),
        param(base, P_D_STAR),
        param(base, P_G_STAR),
        param(base, P_VELOCITY),
        param(base, P_RAMP),
        param(base, P_V_OVER_R),
        param(base, P_V2_OVER_R),
        false,
        ex.drive_kind,
        ex.table_offset,
        ex.table_len,
    );
}

fn rig_is_broken(rig: Rig) -> bool {
    return rig.broken;
}

// The specimen breaks: it carries no force and the load cell damping changes.
fn rig_fire(rig: ptr<function, Rig>) {
    (*rig).broken = true;
    (*rig).c1_now = (*rig).c1_post;
}

// Switching function g = e − e_fracture and dg/dt.
fn rig_switch(rig: Rig, y: State) -> vec2<real> {
    return vec2<real>(y.q.y - y.q.x - rig.e_fracture, y.v.y - y.v.x);
}

// Force-drive table value at t (PiecewiseLinear::at; 0 for t < 0).
fn drive_table(rig: Rig, t: real) -> real {
    return table_at(rig.table_offset, rig.table_len, t);
}

// Velocity drive (y4, v4, a4) at tt > 0 from e = e^{−v·tt/r}: y4 = v·tt + r·(e − 1),
// v4 = v·(1 − e), a4 = (v²/r)·e; a linear drive when there is no ramp, and
// (0, 0, 0) for tt ≤ 0. Selects, not branches: CPU drivers run both sides anyway.
fn velocity_drive(rig: Rig, tt: real, e: real) -> vec3<real> {
    let v = rig.velocity;
    let ramped = vec3<real>(v * tt + rig.ramp * (e - real(1.0)), v * (real(1.0) - e), rig.v2_over_r * e);
    let linear = vec3<real>(v * tt, v, real(0.0));
    let a = select(ramped, linear, rig.ramp <= real(0.0));
    return select(a, vec3<real>(real(0.0)), tt <= real(0.0));
}

// Velocity drive: prescribed (y4, v4, a4) at t. Force drive: (F_drive, 0, 0).
fn rig_actuator(rig: Rig, t: real) -> vec3<real> {
    if FORCE_DRIVE && rig.drive_kind == DRIVE_FORCE {
        return vec3<real>(drive_table(rig, t), real(0.0), real(0.0));
    }
    return velocity_drive(rig, t, exp_n(-rig.v_over_r * t));
}

// The drive's clock, carried from step to step by the run loop: c = e^{−v·t/r}
// at a step's start, and its factor over half a step of length h. A block of
// plain steps starts from rig_clock and advances it with rig_clock_next, so the
// hot loop evaluates no exponential for the drive (a few ulp from the CPU's
// direct expm1 per step, restarted every block).
fn rig_clock(rig: Rig, t: real) -> real {
    return exp_n(-rig.v_over_r * t);
}

fn rig_clock_half(rig: Rig, h: real) -> real {
    return exp_n(-rig.v_over_r * (real(0.5) * h));
}

// The clock at the end of a step that started at clock c.
fn rig_clock_next(c: real, half: real) -> real {
    return c * half * half;
}

// The actuator at the three stage times of an RK4 step (t, t + h/2, t + h) from
// the clock c at t: e(t + h/2) = c·half and e(t + h) = c·half·half.
fn rig_actuators_clocked(rig: Rig, t: real, h: real, c: real, half: real) -> Actuation {
    let hh = real(0.5) * h;
    if FORCE_DRIVE && rig.drive_kind == DRIVE_FORCE {
        return Actuation(
            vec3<real>(drive_table(rig, t), real(0.0), real(0.0)),
            vec3<real>(drive_table(rig, t + hh), real(0.0), real(0.0)),
            vec3<real>(drive_table(rig, t + h), real(0.0), real(0.0)),
        );
    }
    let em = c * half;
    return Actuation(
        velocity_drive(rig, t, c),
        velocity_drive(rig, t + hh, em),
        velocity_drive(rig, t + h, em * half),
    );
}

// The actuator at the three stage times of a step from t, with a fresh clock.
fn rig_actuators(rig: Rig, t: real, h: real) -> Actuation {
    return rig_actuators_clocked(rig, t, h, rig_clock(rig, t), rig_clock_half(rig, h));
}

// Specimen law S(e).
fn specimen_law(rig: Rig, e: real) -> real {
    var s = rig.a5;
    s = s * e + rig.a4;
    s = s * e + rig.a3;
    s = s * e + rig.a2;
    s = s * e + rig.a1;
    s = s * e + rig.a0;
    return select(s, rig.k_lin * e, e <= rig.e_yield);
}

// Slack-adapter spring law G(d) for d > 0.
fn slack_law(rig: Rig, d: real) -> real {
    let curved = rig.slack_a_over_b * expm1_r(rig.slack_b * d) + rig.slack_c * d;
    let straight = rig.g_star + rig.k4_lin * (d - rig.d_star);
    return select(straight, curved, d <= rig.d_star);
}

// Actuator displacement and velocity seen by the slack adapter.
fn actuator_motion(rig: Rig, act: vec3<real>, y: State) -> vec2<real> {
    if FORCE_DRIVE && rig.drive_kind == DRIVE_FORCE {
        return vec2<real>(y.q.w, y.v.w);
    }
    return act.xy;
}

// Element forces (F1, F2, F3, F4).
fn rig_forces(rig: Rig, act: vec3<real>, y: State) -> vec4<real> {
    let f1 = rig.k1 * y.q.x + rig.c1_now * y.v.x;
    let f2 = select(
        specimen_law(rig, y.q.y - y.q.x) + rig.c2 * (y.v.y - y.v.x),
        real(0.0),
        rig.broken,
    );
    let f3 = rig.k3 * (y.q.z - y.q.y) + rig.c3 * (y.v.z - y.v.y);
    let a = actuator_motion(rig, act, y);
    let d = a.x - y.q.z - rig.gap;
    let f4 = select(slack_law(rig, d) + rig.c4 * (a.y - y.v.z), real(0.0), d <= real(0.0));
    return vec4<real>(f1, f2, f3, f4);
}

// Under a velocity drive the actuator's slots (q.w, v.w) are not integrated:
// its motion is prescribed (act), and rig_full_state fills them for outputs.
// Their derivatives are 0, which the driver's compiler folds away.
fn rig_deriv(rig: Rig, act: vec3<real>, y: State) -> State {
    let f = rig_forces(rig, act, y);
    var q4 = real(0.0);
    var a4 = real(0.0);
    if FORCE_DRIVE && rig.drive_kind == DRIVE_FORCE {
        q4 = y.v.w;
        a4 = (act.x - f.w) * rig.inv_m4;
    }
    return State(
        vec4<real>(y.v.x, y.v.y, y.v.z, q4),
        vec4<real>((f.y - f.x) * rig.inv_m1, (f.z - f.y) * rig.inv_m2, (f.w - f.z) * rig.inv_m3, a4),
    );
}

// Outputs (load-cell force F1, specimen force F2) at (t, y).
fn rig_outputs(rig: Rig, t: real, y: State) -> vec2<real> {
    let f = rig_forces(rig, rig_actuator(rig, t), y);
    return f.xy;
}

// The state with the actuator slots filled from the prescribed motion.
fn rig_full_state(rig: Rig, t: real, y: State) -> State {
    let a = actuator_motion(rig, rig_actuator(rig, t), y);
    return State(vec4<real>(y.q.xyz, a.x), vec4<real>(y.v.xyz, a.y));
}
