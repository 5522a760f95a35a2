// Test kernel: evaluates exp_r and expm1_r of shared/exp.wgsl at given points so
// tests can hold them against f64::exp and f64::exp_m1.

@group(0) @binding(0) var<storage, read> probe_x: array<real>;
// (exp_r(x), expm1_r(x)) per point.
@group(0) @binding(1) var<storage, read_write> probe_out: array<real>;

@compute @workgroup_size(64)
fn exp_probe_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&probe_x) {
        return;
    }
    probe_out[2u * i] = exp_r(probe_x[i]);
    probe_out[2u * i + 1u] = expm1_r(probe_x[i]);
}
