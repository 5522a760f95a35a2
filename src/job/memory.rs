//! A job's memory, estimated before any work, and the chunk size that keeps
//! it bounded.
//!
//! The search must hold its population (population × genes); nothing else
//! grows with it. The evaluation (per-experiment parameter vectors, scores,
//! the GPU's run buffers) goes through the evaluator in chunks of at most
//! [`chunk_candidates`] candidates, and the polish's histories in chunks of at
//! most [`history_chunk`] runs, so a population of 10⁶ costs its genomes and
//! no more. A job whose estimate exceeds the limit (the memory available now,
//! or `--max-memory`) is refused before anything is written.

use std::fmt;

use serde::Serialize;

use crate::campaign::Campaign;
use crate::eval::{Backend, ExperimentData, PrecisionChoice};

/// Memory one evaluation chunk may take (bytes). A constant, not a share of
/// the memory available, so that the chunks (and with them the GPU kernels'
/// batches) are the same on every machine.
pub const CHUNK_BYTES: f64 = 64.0 * MIB;

/// Memory the polish's histories may take at once (bytes).
pub const HISTORY_CHUNK_BYTES: f64 = 64.0 * MIB;

/// One mebibyte.
pub const MIB: f64 = 1024.0 * 1024.0;

/// The program, its threads and buffers before any candidate (measured: a
/// population of 16 on the shipped example peaks at 16 MiB on the CPU path).
const BASE_CPU: f64 = 40.0 * MIB;

/// The GPU driver on top (measured: lavapipe with the compiled kernels peaks
/// at about 220 MiB with a population of 16).
const BASE_GPU: f64 = 320.0 * MIB;

/// Bytes per record sample held beyond the record itself: the best
/// candidate's history, the result CSV and the plots' text.
const PER_SAMPLE: f64 = 400.0;

/// What a job will hold at its peak, in bytes, by part.
#[derive(Debug, Clone, Serialize)]
pub struct MemoryEstimate {
    /// Population of the search.
    pub population: usize,
    /// Genes per genome.
    pub genes: usize,
    /// The search's genomes and costs: the population, the children bred
    /// from it, their values, and a checkpoint being written.
    pub search: f64,
    /// Candidates per evaluation chunk.
    pub chunk: usize,
    /// One evaluation chunk (batch, scores, GPU run buffers).
    pub evaluation: f64,
    /// The same evaluation unchunked: the whole population at once.
    pub unchunked_evaluation: f64,
    /// The polish's residuals and one chunk of histories.
    pub histories: f64,
    /// The program, the driver, the records and the outputs.
    pub base: f64,
    /// The sum.
    pub total: f64,
}

impl MemoryEstimate {
    /// A job's estimate as `rigfit run` and `rigfit.fit` check it before any
    /// work: with the GPU's buffers in `precision` where `backend` may run
    /// the rig there (not on the CPU, nor where the kernels cannot hold it).
    pub fn of_job(campaign: &Campaign, backend: Backend, precision: PrecisionChoice) -> Self {
        let gpu_real = match (backend, precision) {
            (Backend::Cpu, _) => None,
            _ if crate::gpu::kernel_groups(&campaign.problem).is_err() => None,
            (_, PrecisionChoice::F32) => Some(4),
            _ => Some(8),
        };
        Self::of(campaign, gpu_real)
    }

    /// Why a job this size is refused under `limit` bytes (`source` says
    /// whence the limit): `whom` is what to change (the population, as the
    /// caller spells it), `limit_flag` how the caller spells the limit
    /// (`--max-memory`, `max_memory`), `given` whether the user gave it.
    pub fn refusal(
        &self,
        whom: &str,
        limit: f64,
        source: &str,
        limit_flag: &str,
        given: bool,
    ) -> String {
        let hint = if given {
            format!("lower the population or raise {limit_flag}")
        } else {
            format!(
                "lower the population, free memory, or set {limit_flag} to the memory the job \
                 may use"
            )
        };
        format!(
            "{whom}: expected a job that fits in {} ({source}), found {self}; {hint}",
            human_bytes(limit)
        )
    }

    /// The estimate of `campaign` on the GPU path (`gpu_real`: 4 or 8 bytes per
    /// real) or, with `None`, on the CPU path.
    pub fn of(campaign: &Campaign, gpu_real: Option<usize>) -> Self {
        // The largest batch the search asks for: the population, or the
        // last restart's of CMA-ES.
        let n = campaign.search.method.largest_batch(&campaign.search);
        let g = campaign.genes.len();
        let search = n as f64 * search_bytes_per_candidate(g);
        let per_candidate = evaluation_bytes_per_candidate(campaign, gpu_real);
        let chunk = chunk_candidates(campaign).min(n.max(1));
        let evaluation = chunk as f64 * per_candidate;
        let unchunked_evaluation = n as f64 * per_candidate;
        let histories = histories_bytes(campaign, gpu_real);
        let samples = summed(campaign, |x| x.measured.len());
        let base = if gpu_real.is_some() {
            BASE_CPU + BASE_GPU
        } else {
            BASE_CPU
        } + samples as f64 * PER_SAMPLE;
        Self {
            population: n,
            genes: g,
            search,
            chunk,
            evaluation,
            unchunked_evaluation,
            histories,
            base,
            total: search + evaluation + histories + base,
        }
    }
}

impl fmt::Display for MemoryEstimate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "about {} (the search's {} genomes of {} genes: {}; evaluation in chunks of {} \
             candidates: {}; histories: {}; program, driver and records: {})",
            human_bytes(self.total),
            self.population,
            self.genes,
            human_bytes(self.search),
            self.chunk,
            human_bytes(self.evaluation),
            human_bytes(self.histories),
            human_bytes(self.base)
        )
    }
}

/// `count` summed over the campaign's experiments (their samples, their fit
/// windows' samples).
fn summed(campaign: &Campaign, count: impl Fn(&ExperimentData) -> usize) -> usize {
    campaign.problem.experiments.iter().map(count).sum()
}

/// Heap bytes of a `Vec<f64>` of `n` values: the vector itself and its block
/// as the system allocator rounds it.
fn vec_bytes(n: usize, each: usize) -> f64 {
    let block = (n * each + 8).div_ceil(16) * 16;
    (24 + block.max(32)) as f64
}

/// The search's bytes per candidate with `g` genes: the population, the
/// children and their values (three genomes), costs and ranks, and a
/// checkpoint in flight (a JSON tree of the genome and its text).
fn search_bytes_per_candidate(g: usize) -> f64 {
    let genome = vec_bytes(g, 8);
    let checkpoint = 32.0 + vec_bytes(g, 32) + 32.0 + 28.0 * (g + 1) as f64;
    3.0 * genome + 48.0 + checkpoint
}

/// The evaluation's bytes per candidate: per experiment, the model's
/// parameters and the offset, the scores and their bookkeeping; on the GPU
/// path also the packed run (host and device), its state, progress, fitness and
/// read-back, with the buffers rounded up to a power of two runs.
fn evaluation_bytes_per_candidate(campaign: &Campaign, gpu_real: Option<usize>) -> f64 {
    let ne = campaign.problem.experiments.len();
    let p = campaign.model.params().len();
    let cpu = (p * 8 + 8 + 8 + 16 + 16 + 8) as f64;
    let gpu = gpu_real.map_or(0.0, |real| {
        let run = |slots: usize, state: usize| -> f64 {
            let stride = crate::gpu::layout::run_stride(slots) as usize;
            let host = stride * 8 + stride * real;
            let device = stride * real + state * real + 16;
            (host + 2 * (device + 2 * real)) as f64
        };
        // Each experiment's runs are as wide as the kernels that score it
        // (a job mixing drive modes has one pipeline per mode).
        match crate::gpu::kernel_groups(&campaign.problem) {
            Ok(groups) => groups
                .iter()
                .map(|g| {
                    g.experiments.len() as f64
                        * run(g.model.slot_names().len(), g.model.state_stride() as usize)
                })
                .sum(),
            // No kernels for this rig: the job runs on the CPU.
            Err(_) => 0.0,
        }
    });
    ne as f64 * cpu + gpu + 8.0
}

/// Candidates per evaluation chunk: as many as fit in [`CHUNK_BYTES`] on the
/// GPU path (the larger), a power of two, at least 1 024.
pub fn chunk_candidates(campaign: &Campaign) -> usize {
    let per = evaluation_bytes_per_candidate(campaign, Some(8));
    let n = (CHUNK_BYTES / per).max(1024.0) as usize;
    1 << n.ilog2()
}

/// Bytes of one candidate's records for the polish's residuals, in every
/// experiment: the scored output alone
/// ([`crate::eval::Evaluator::scored_outputs`]) in f64 on the host, and on
/// the GPU path (`gpu_real`: its bytes per value) in the history buffer and
/// its read-back as well.
fn history_bytes_per_candidate(campaign: &Campaign, gpu_real: Option<usize>) -> f64 {
    let per_sample = 8 + gpu_real.map_or(0, |real| 2 * real);
    (summed(campaign, |x| x.window.end) * per_sample) as f64
}

/// Candidates per chunk of the polish's records on the path that runs them
/// (`gpu_real`: the GPU's bytes per value, `None` on the CPU): as many as fit
/// in [`HISTORY_CHUNK_BYTES`], at least one. With the scored output alone,
/// every candidate of a polish iteration on the EMPS closed loop's
/// 24 841-sample records fits one chunk, on either path.
pub fn history_chunk(campaign: &Campaign, gpu_real: Option<usize>) -> usize {
    let per = history_bytes_per_candidate(campaign, gpu_real);
    ((HISTORY_CHUNK_BYTES / per) as usize).max(1)
}

/// Bytes of one candidate's whole history in every experiment (the best
/// candidate's, which the job's outputs are written from): time, outputs and
/// states per sample; on the GPU path also the raw history buffer, its
/// read-back and its host copy.
fn full_history_bytes(campaign: &Campaign, gpu_real: Option<usize>) -> f64 {
    let m = &campaign.model;
    let values = 1 + m.output_names().len() + m.state_names().len();
    let samples = summed(campaign, |x| x.window.end);
    let gpu = gpu_real.map_or(0, |real| {
        let values = crate::gpu::kernel_groups(&campaign.problem)
            .ok()
            .and_then(|g| g.iter().map(|k| k.model.hist_values()).max())
            .unwrap_or(0);
        values as usize * (2 * real + 8)
    });
    (samples * (values * 8 + gpu)) as f64
}

/// The polish's residuals (every point and stencil of one iteration, over
/// every fit window) plus one chunk of their records, or the best
/// candidate's whole history where that is larger (the outputs are written
/// from it once the polish has let its records go).
fn histories_bytes(campaign: &Campaign, gpu_real: Option<usize>) -> f64 {
    let polish = &campaign.search.polish;
    let g = campaign.genes.len();
    let batch = if polish.enabled {
        polish.starts.max(1) * (2 * g + 1)
    } else {
        1
    };
    let window = summed(campaign, |x| x.window.len());
    let residuals = if polish.enabled {
        (batch * window * 8) as f64
    } else {
        0.0
    };
    let chunk = history_chunk(campaign, gpu_real).min(batch);
    let records = chunk as f64 * history_bytes_per_candidate(campaign, gpu_real);
    residuals + records.max(full_history_bytes(campaign, gpu_real))
}

/// The memory available to a new job now (bytes): `MemAvailable` of
/// `/proc/meminfo`; `None` where that cannot be read.
pub fn available_memory() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    meminfo_field(&text, "MemAvailable")
}

/// The peak resident memory of this process so far (bytes), `VmHWM` of
/// `/proc/self/status`; `None` where that cannot be read.
pub fn peak_resident_memory() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    meminfo_field(&text, "VmHWM")
}

/// A `Name:   1234 kB` line's value in bytes.
fn meminfo_field(text: &str, name: &str) -> Option<f64> {
    let line = text.lines().find(|l| l.split(':').next() == Some(name))?;
    let mut words = line.split(':').nth(1)?.split_whitespace();
    let value: f64 = words.next()?.parse().ok()?;
    match words.next() {
        Some("kB") => Some(value * 1024.0),
        None => Some(value),
        Some(_) => None,
    }
}

/// The polish's candidate-steps per second as a share of the GA's fitness
/// rate on the same path (the CPU lanes' or the GPU's, measured by `run
/// --backend auto` where `check` has its figures). Its candidates are
/// records of the scored output at every sample
/// ([`crate::eval::Evaluator::scored_outputs`]) turned into residuals and a
/// linear solve per iteration, in batches of `starts × (2 × genes + 1)`:
/// measured on the eleven shipped campaigns on both paths (2026-11-26, idle
/// 2-core Xeon, lavapipe), 0.27 to 0.86 of the path's fitness rate, median
/// 0.47 (0.13 when the polish asked for whole histories).
pub const POLISH_SHARE_OF_FITNESS_RATE: f64 = 0.47;

/// The polish's rounds of `starts × (2 × genes + 1)` candidates a job is
/// expected to take (the first linearisation and six iterations), at most
/// its `max_iterations + 1`: the shipped campaigns' polishes stopped
/// converged after 3 to 16 iterations, their evaluations worth 4.0 to 14.4
/// full rounds (median 6.6; starts retired early take fewer).
pub const POLISH_ROUNDS_EXPECTED: usize = 7;

/// Candidate-steps per second assumed for the GPU path before any is
/// measured: lavapipe's f32 kernels on two cores measure about 1.2e8
/// (README, throughput); a discrete GPU runs one to two orders of magnitude
/// more, so on one an estimate from it is an upper bound.
pub const GPU_STEPS_PER_S_ASSUMED: f64 = 1e8;

/// What a job on the GPU path costs besides the GA and the polish: the
/// process, the campaign, opening the GPU (lavapipe's pipelines), `auto`'s
/// trial where nothing is cached. Measured on the nine shipped campaigns
/// (2026-11-26, under load): a run's wall time outside its job plus the
/// trial, 0.65 to 2.6 s (of which the trial 0.2 to 1.0 s, none once
/// `auto`'s choice is cached).
pub const STARTUP_SECONDS: f64 = 1.0;

/// The same on the CPU path, which opens no GPU and, for the short jobs
/// `auto` runs there unmeasured, takes no trial (the lanes' native code
/// builds while the first generations interpret): measured on the eleven
/// shipped campaigns (2026-11-26, idle), a run's wall time outside its GA
/// and polish was 0.04 to 0.64 s, median 0.08.
pub const CPU_STARTUP_SECONDS: f64 = 0.2;

/// A job's wall time, estimated before any work from its steps: start-up,
/// the GA's candidates at the fitness path's rate, then the polish's
/// expected candidates at [`POLISH_SHARE_OF_FITNESS_RATE`] of it.
#[derive(Debug, Clone, Serialize)]
pub struct TimeEstimate {
    /// The GA's candidates at most: population × generations (an upper
    /// bound: elites are not evaluated again).
    pub candidates: f64,
    /// The GA's RK4 steps.
    pub steps: f64,
    /// CPU cores assumed.
    pub cpu_cores: usize,
    /// The GA's candidate-steps per second on the CPU (every core).
    pub cpu_steps_per_s_assumed: f64,
    /// The job on the CPU: start-up, the GA, then the polish (s).
    pub cpu_seconds: f64,
    /// The GA's candidate-steps per second on the GPU.
    pub gpu_steps_per_s_assumed: f64,
    /// The job on the GPU: start-up, the GA, then the polish (s).
    pub gpu_seconds: f64,
    /// [`STARTUP_SECONDS`], in the GPU's total; where the GPU's start-up
    /// was measured ([`Self::with_gpu_startup`]), the CPU's start-up plus it.
    pub startup_seconds: f64,
    /// [`CPU_STARTUP_SECONDS`], in the CPU's total.
    pub cpu_startup_seconds: f64,
    /// Whether the CPU's rate is the one the last run of this job on this
    /// machine ran at ([`crate::job::backend::observed_cpu_rate`]).
    pub cpu_rate_observed: bool,
    /// The polish's candidates at most: `starts × (2 × genes + 1)` per
    /// iteration and once more for the first linearisation (0 without the
    /// polish).
    pub polish_candidates: f64,
    /// Its RK4 steps at most.
    pub polish_steps: f64,
    /// The polish's candidates expected: [`POLISH_ROUNDS_EXPECTED`] rounds
    /// (or fewer where its iteration limit is lower).
    pub polish_candidates_expected: f64,
    /// Their RK4 steps.
    pub polish_steps_expected: f64,
    /// The polish's candidate-steps per second on the CPU and on the GPU
    /// ([`POLISH_SHARE_OF_FITNESS_RATE`] of each path's GA rate).
    pub cpu_polish_steps_per_s: f64,
    /// See `cpu_polish_steps_per_s`.
    pub gpu_polish_steps_per_s: f64,
    /// The polish's share of `cpu_seconds` (s).
    pub cpu_polish_seconds: f64,
    /// The polish's share of `gpu_seconds` (s).
    pub gpu_polish_seconds: f64,
}

impl TimeEstimate {
    /// For `campaign` at `steps_per_candidate` RK4 steps per candidate, on
    /// `cores` CPU cores at the assumed per-core rate and a GPU assumed to
    /// run `gpu_steps_per_s`.
    pub fn of(
        campaign: &Campaign,
        steps_per_candidate: f64,
        cores: usize,
        gpu_steps_per_s: f64,
    ) -> Self {
        let s = &campaign.search;
        let candidates = (s.population * s.generations) as f64;
        let (rounds, expected) = if s.polish.enabled {
            let per_round = s.polish.starts * (2 * campaign.genes.len() + 1);
            let rounds = s.polish.max_iterations + 1;
            (
                (per_round * rounds) as f64,
                (per_round * rounds.min(POLISH_ROUNDS_EXPECTED)) as f64,
            )
        } else {
            (0.0, 0.0)
        };
        Self {
            candidates,
            steps: candidates * steps_per_candidate,
            cpu_cores: cores,
            cpu_steps_per_s_assumed: 0.0,
            cpu_seconds: 0.0,
            gpu_steps_per_s_assumed: 0.0,
            gpu_seconds: 0.0,
            startup_seconds: STARTUP_SECONDS,
            cpu_startup_seconds: CPU_STARTUP_SECONDS,
            cpu_rate_observed: false,
            polish_candidates: rounds,
            polish_steps: rounds * steps_per_candidate,
            polish_candidates_expected: expected,
            polish_steps_expected: expected * steps_per_candidate,
            cpu_polish_steps_per_s: 0.0,
            gpu_polish_steps_per_s: 0.0,
            cpu_polish_seconds: 0.0,
            gpu_polish_seconds: 0.0,
        }
        .with_cpu_rate(crate::campaign::CPU_STEPS_PER_S_PER_CORE * cores as f64)
        .with_gpu_rate(gpu_steps_per_s)
    }

    /// At a path's GA rate `rate` (candidate-steps per second) after
    /// `startup` seconds: the polish's rate, the polish's seconds and the
    /// job's.
    fn at_rate(&self, rate: f64, startup: f64) -> (f64, f64, f64) {
        let polish_rate = POLISH_SHARE_OF_FITNESS_RATE * rate;
        let polish = self.polish_steps_expected / polish_rate;
        (polish_rate, polish, startup + self.steps / rate + polish)
    }

    /// The same with the GA's CPU rate `rate` (candidate-steps per second,
    /// every core), as measured.
    pub fn with_cpu_rate(self, rate: f64) -> Self {
        let (polish_rate, polish, seconds) = self.at_rate(rate, self.cpu_startup_seconds);
        Self {
            cpu_steps_per_s_assumed: rate,
            cpu_polish_steps_per_s: polish_rate,
            cpu_polish_seconds: polish,
            cpu_seconds: seconds,
            ..self
        }
    }

    /// The same with the GPU opened in `seconds` (its adapter, device and
    /// first kernel built and warmed up, as `auto`'s trial timed it) on top
    /// of the start-up the CPU path pays as well.
    pub fn with_gpu_startup(self, seconds: f64) -> Self {
        let startup_seconds = self.cpu_startup_seconds + seconds;
        Self {
            startup_seconds,
            ..self
        }
        .with_gpu_rate(self.gpu_steps_per_s_assumed)
    }

    /// The same with the GA's GPU rate `rate` (candidate-steps per second),
    /// as measured.
    pub fn with_gpu_rate(self, rate: f64) -> Self {
        let (polish_rate, polish, seconds) = self.at_rate(rate, self.startup_seconds);
        Self {
            gpu_steps_per_s_assumed: rate,
            gpu_polish_steps_per_s: polish_rate,
            gpu_polish_seconds: polish,
            gpu_seconds: seconds,
            ..self
        }
    }
}

/// The polish's part of a [`TimeEstimate`] (as `check --json` writes it),
/// as `check` words it after the GA's line: empty without a polish.
pub fn polish_estimate_text(e: &serde_json::Value) -> String {
    let f = |k: &str| e[k].as_f64().unwrap_or(0.0);
    if f("polish_candidates") == 0.0 {
        return String::new();
    }
    format!(
        "\n  the polish after it: about {:.3e} candidates expected, at most {:.3e} (its \
         iteration limit), {:.3e} RK4 steps of scored records: about {} on the CPU and {} \
         on the GPU, at {:.0} % of each path's rate; and about {} of start-up on the CPU, \
         {} on the GPU; all included in the times above",
        f("polish_candidates_expected"),
        f("polish_candidates"),
        f("polish_steps_expected"),
        crate::campaign::human_duration(f("cpu_polish_seconds")),
        crate::campaign::human_duration(f("gpu_polish_seconds")),
        100.0 * POLISH_SHARE_OF_FITNESS_RATE,
        crate::campaign::human_duration(f("cpu_startup_seconds")),
        crate::campaign::human_duration(f("startup_seconds")),
    )
}

/// `512 KiB`, `3.4 MiB`, `1.20 TiB`.
pub fn human_bytes(b: f64) -> String {
    const UNITS: [&str; 6] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB"];
    let mut v = b;
    let mut u = 0;
    while v >= 1024.0 && u + 1 < UNITS.len() {
        v /= 1024.0;
        u += 1;
    }
    match u {
        0 => format!("{v:.0} B"),
        _ if v < 10.0 => format!("{v:.2} {}", UNITS[u]),
        _ if v < 100.0 => format!("{v:.1} {}", UNITS[u]),
        _ => format!("{v:.0} {}", UNITS[u]),
    }
}

/// A size as the user writes it: bytes, or a number with `K`, `M`, `G`, `T`
/// (powers of 1024; `KiB`, `MB`, … read the same).
pub fn parse_bytes(s: &str) -> Option<f64> {
    let t = s.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == 'e' || c == 'E'))
        .unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let v: f64 = num.parse().ok()?;
    let unit = unit.trim().to_ascii_lowercase();
    let scale = match unit.trim_end_matches('b').trim_end_matches('i') {
        "" => 1.0,
        "k" => 1024.0,
        "m" => MIB,
        "g" => 1024.0 * MIB,
        "t" => 1024.0 * 1024.0 * MIB,
        _ => return None,
    };
    let bytes = v * scale;
    (bytes.is_finite() && bytes > 0.0).then_some(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_in_powers_of_1024() {
        assert_eq!(parse_bytes("512M"), Some(512.0 * MIB));
        assert_eq!(parse_bytes("2GiB"), Some(2048.0 * MIB));
        assert_eq!(parse_bytes("1.5 gb"), Some(1536.0 * MIB));
        assert_eq!(parse_bytes("4096"), Some(4096.0));
        assert_eq!(parse_bytes("12X"), None);
        assert_eq!(parse_bytes("0"), None);
        assert_eq!(parse_bytes("-1G"), None);
    }

    #[test]
    fn meminfo_lines_read_in_bytes() {
        let text = "MemTotal:       24589016 kB\nMemAvailable:   22012340 kB\n";
        assert_eq!(
            meminfo_field(text, "MemAvailable"),
            Some(22_012_340.0 * 1024.0)
        );
        assert_eq!(meminfo_field(text, "MemFree"), None);
    }

    #[test]
    fn human_bytes_keep_three_digits() {
        assert_eq!(human_bytes(512.0), "512 B");
        assert_eq!(human_bytes(3.5 * MIB), "3.50 MiB");
        assert_eq!(human_bytes(1.2e12), "1.09 TiB");
    }
}
