// Test kernel: evaluates exp_r and expm1_r of shared/exp.wgsl and ln_r, sin_r and
// cos_r of shared/math.wgsl at given points so tests can hold them against
// f64::exp, f64::exp_m1, f64::ln, f64::sin and f64::cos.

@group(0) @binding(0) var<storage, read> probe_x: array<real>;
// PROBE_VALUES per point: exp_r(x), expm1_r(x), ln_r(|x|), sin_r(x), cos_r(x).
@group(0) @binding(1) var<storage, read_write> probe_out: array<real>;

@compute @workgroup_size(64)
fn exp_probe_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&probe_x) {
        return;
    }
    let x = probe_x[i];
    let o = 5u * i;
    probe_out[o] = exp_r(x);
    probe_out[o + 1u] = expm1_r(x);
    probe_out[o + 2u] = ln_r(abs(x));
    probe_out[o + 3u] = sin_r(x);
    probe_out[o + 4u] = cos_r(x);
}
