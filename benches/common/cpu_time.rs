//! CPU time of the benchmark process, for rates per CPU-second on a shared
//! machine.

/// CPU seconds used so far by this process, all threads (lavapipe's included):
/// the process CPU-time clock (nanoseconds) on Unix, else `None`. (The tick
/// counts of `/proc/self/stat` step by 10 ms, a tenth of a short evaluation.)
pub fn process_cpu_seconds() -> Option<f64> {
    #[cfg(unix)]
    {
        let t = rustix::time::clock_gettime(rustix::time::ClockId::ProcessCPUTime);
        Some(t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9)
    }
    #[cfg(not(unix))]
    {
        None
    }
}
