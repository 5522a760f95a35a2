//! The machine a bench table was measured on, printed above every table: the
//! processor, its cores and the vector extensions the CPU lanes can use (and
//! lavapipe's, where `GALLIUM_OVERRIDE_CPU_CAPS` narrows them).

/// One line: processor, cores, AVX2 / AVX-512, the instruction set the lanes
/// run (and its override), how the native lanes are built, and Mesa's
/// `GALLIUM_OVERRIDE_CPU_CAPS` where set (`avx` keeps lavapipe's JIT off
/// AVX-512 and its 32 registers: with `RIGFIT_LANES_ISA=avx2`, both paths as
/// a processor with AVX2 alone runs them).
pub fn machine_line() -> String {
    let flags = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("flags"))
                .map(|l| l.to_string())
        })
        .unwrap_or_default();
    let has = |f: &str| flags.split_whitespace().any(|x| x == f);
    let isa = match (has("avx512f"), has("avx2")) {
        (true, _) => "AVX-512 (avx512f) and AVX2",
        (false, true) => "AVX2, no AVX-512",
        _ => "neither AVX2 nor AVX-512",
    };
    let cores = rigfit::eval::all_cores();
    let lanes = std::env::var("RIGFIT_LANES_ISA").unwrap_or_else(|_| "widest".into());
    let picked = rigfit::compile::exec::lanes::Isa::detect();
    let lavapipe = std::env::var("GALLIUM_OVERRIDE_CPU_CAPS")
        .map(|caps| format!("; lavapipe: GALLIUM_OVERRIDE_CPU_CAPS={caps}"))
        .unwrap_or_default();
    format!(
        "Machine: {}, {cores} cores, {isa}; lanes: {picked:?} (RIGFIT_LANES_ISA={lanes}), \
         native lanes: -march=native {}in {}-byte vectors{lavapipe}",
        rigfit::job::backend::processor(),
        picked
            .narrowing_flags()
            .iter()
            .map(|f| format!("{f} "))
            .collect::<String>(),
        picked.vector_bytes()
    )
}
