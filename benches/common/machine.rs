//! The machine a bench table was measured on, printed above every table: the
//! processor, its cores and the vector extensions the CPU lanes can use.

/// One line: processor, cores, AVX2 / AVX-512, the instruction set the lanes
/// run (and its override), and how the native lanes are built.
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
    format!(
        "Machine: {}, {cores} cores, {isa}; lanes: {picked:?} (RIGFIT_LANES_ISA={lanes}), \
         native lanes: -march=native {}in {}-byte vectors",
        rigfit::job::backend::processor(),
        picked
            .narrowing_flags()
            .iter()
            .map(|f| format!("{f} "))
            .collect::<String>(),
        picked.vector_bytes()
    )
}
