// Linear interpolation in a table of the data buffer, for the compiled rigs'
// tables (a rig file's own and an experiment's drive column).
//
// Loops here run a fixed number of times and keep their result by selects: a
// data-dependent `while` loop was miscompiled by lavapipe (it returned a wrong
// segment at some times). Values are read through `datum` (src/gpu/shaders.rs,
// datum_fn): from a uniform copy of `data` where the fitness kernel has one.

// The header datum(off - 1) of a table: PiecewiseLinear::kernel_header, +1/Δt
// on an exactly uniform grid, −1/Δt on a roughly uniform one, 0 otherwise; a
// run reads it once (rig_load), with the first breakpoint time.
fn table_header(off: u32, n: u32) -> real {
    if n == 0u {
        return real(0.0);
    }
    return datum(off - 1u);
}

fn table_start(off: u32, n: u32) -> real {
    if n == 0u {
        return real(0.0);
    }
    return datum(off);
}

// Table value at t (PiecewiseLinear::at; 0 for t < 0): breakpoint times at
// datum(off..off + n), values after them; t0 the first breakpoint time and inv
// the table's header (table_header).
fn table_at(off: u32, n: u32, t0: real, inv: real, t: real) -> real {
    if t < real(0.0) || n == 0u {
        return real(0.0);
    }
    let vv = off + n;
    if TABLE_EXACT || inv > real(0.0) {
        // On an exactly uniform grid (a record's own samples): the value at
        // the fractional index, clamped to the table's ends, with no search
        // and no breakpoint read: two reads of the data buffer. Where every
        // table is on one (TABLE_EXACT, src/gpu/shaders.rs) the paths below
        // are compiled out: a CPU driver would run them under a mask.
        let u = min(max((t - t0) * inv, real(0.0)), real(n - 1u));
        let lo = min(u32(u), n - 2u);
        let a = datum(vv + lo);
        return a + (u - real(lo)) * (datum(vv + lo + 1u) - a);
    }
    if t <= t0 {
        return datum(vv);
    }
    if t >= datum(off + n - 1u) {
        return datum(vv + n - 1u);
    }
    // Largest i with T[i] <= t, as partition_point(x <= t) − 1.
    var lo = 0u;
    if inv < real(0.0) {
        // On a roughly uniform grid: the segment from the spacing, which the
        // host guarantees is within two breakpoints of the right one, then
        // two corrections down and two up.
        let guess = floor((t - t0) * -inv);
        lo = min(u32(max(guess, real(0.0))), n - 2u);
        for (var it = 0u; it < 2u; it += 1u) {
            lo = select(lo, lo - 1u, lo > 0u && datum(off + lo) > t);
        }
        for (var it = 0u; it < 2u; it += 1u) {
            lo = select(lo, lo + 1u, lo + 2u < n && datum(off + lo + 1u) <= t);
        }
    } else {
        // Anywhere else: a fixed number of halvings (enough for 2^32
        // breakpoints), the interval kept by selects.
        var hi = n - 1u;
        for (var it = 0u; it < 32u; it += 1u) {
            let open = hi - lo > 1u;
            let mid = (lo + hi) / 2u;
            let below = datum(off + mid) <= t;
            lo = select(lo, mid, open && below);
            hi = select(hi, mid, open && !below);
        }
    }
    let w = (t - datum(off + lo)) / (datum(off + lo + 1u) - datum(off + lo));
    return datum(vv + lo) + w * (datum(vv + lo + 1u) - datum(vv + lo));
}
