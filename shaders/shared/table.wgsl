// Linear interpolation in a table of the data buffer, shared by the
// hand-written model's force drive and the compiled rigs' tables.
//
// The search halves a fixed 32 times and keeps the interval by selects: a
// data-dependent `while` loop here was miscompiled by lavapipe (it returned a
// wrong segment at some times).

// Table value at t (PiecewiseLinear::at; 0 for t < 0): breakpoint times at
// data[off..off + n], values after them.
fn table_at(off: u32, n: u32, t: real) -> real {
    if t < real(0.0) || n == 0u {
        return real(0.0);
    }
    let vv = off + n;
    if t <= data[off] {
        return data[vv];
    }
    if t >= data[off + n - 1u] {
        return data[vv + n - 1u];
    }
    // Largest i with T[i] <= t, as partition_point(x <= t) − 1: a fixed number
    // of halvings (enough for 2^32 breakpoints), the interval kept by selects.
    var lo = 0u;
    var hi = n - 1u;
    for (var it = 0u; it < 32u; it += 1u) {
        let open = hi - lo > 1u;
        let mid = (lo + hi) / 2u;
        let below = data[off + mid] <= t;
        lo = select(lo, mid, open && below);
        hi = select(hi, mid, open && !below);
    }
    let w = (t - data[off + lo]) / (data[off + lo + 1u] - data[off + lo]);
    return data[vv + lo] + w * (data[vv + lo + 1u] - data[vv + lo]);
}
