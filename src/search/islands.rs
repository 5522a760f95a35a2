//! Islands: K seeded searches of one problem that trade their best
//! candidates through a shared folder every few generations (the ring
//! migration of an island-model GA).
//!
//! Each island is an ordinary search under the [`super::Executor`]; the
//! exchange is a [`Migration`] the executor calls after a generation when the
//! search goes on. Island `i` writes its `migrants` best genomes and their
//! costs to `<folder>/<i>-<generation>.json` (atomically: a reader sees the
//! whole file or none), then waits up to `wait_s` seconds for the file of its
//! ring neighbour `(i − 1) mod K` for the same generation. Present, the
//! migrants replace the island's worst ([`super::Solver::immigrate`]); absent
//! (a slow, dead or requeued neighbour), the island goes on and the exchange
//! is recorded as missed, which makes the run no longer reproducible. A
//! neighbour that has ended writes `<j>-done.json`; its later exchanges are
//! then known never to come and are not waited for (nor counted as missed:
//! where it ends is as deterministic as the rest of its search).
//!
//! With every island alive, a given seed and schedule give the same bits
//! whether the islands run as threads of one process or as separate
//! processes: an island's batches depend only on its seed and on the files
//! its neighbour wrote, never on when they arrived.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use super::SearchError;
use super::genes::{GeneSpec, clamp_into};
use super::report::{SearchOutcome, elite_spread, ranking};
use super::solver::Solver;
use crate::base::fsutil::atomic_write;

/// The campaign's `"search": {"islands": {…}}` object.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IslandSettings {
    /// Islands (searches) in the ring (≥ 1; `rigfit run --islands K`).
    pub count: usize,
    /// Generations between two exchanges (≥ 1; default 10).
    #[serde(default = "default_every")]
    pub every: usize,
    /// Best candidates an island sends its neighbour at each exchange, which
    /// replace the neighbour's worst (≥ 1 and below the population; default 2).
    #[serde(default = "default_migrants")]
    pub migrants: usize,
    /// Longest wait for a neighbour's migrants at one exchange (s, > 0;
    /// default 60); past it the island goes on without them.
    #[serde(default = "default_wait_s")]
    pub wait_s: f64,
}

fn default_every() -> usize {
    10
}
fn default_migrants() -> usize {
    2
}
fn default_wait_s() -> f64 {
    60.0
}

/// Most islands a ring may hold.
pub const MAX_ISLANDS: usize = 1024;

impl IslandSettings {
    /// `count` islands with the default schedule.
    pub fn with_count(count: usize) -> Self {
        Self {
            count,
            every: default_every(),
            migrants: default_migrants(),
            wait_s: default_wait_s(),
        }
    }

    /// The setting out of range, if any, for a search of `population`:
    /// `(field, expected, found)`.
    pub fn invalid(&self, population: usize) -> Option<(&'static str, String, String)> {
        if self.count < 1 || self.count > MAX_ISLANDS {
            let expected = format!("between 1 and {MAX_ISLANDS}");
            return Some(("islands.count", expected, self.count.to_string()));
        }
        if self.every < 1 {
            return Some(("islands.every", "at least 1".into(), "0".into()));
        }
        if self.migrants < 1 || self.migrants >= population {
            let expected = format!("between 1 and the population less one ({})", population - 1);
            return Some(("islands.migrants", expected, self.migrants.to_string()));
        }
        if !(self.wait_s > 0.0 && self.wait_s.is_finite()) {
            let found = self.wait_s.to_string();
            return Some(("islands.wait_s", "a time > 0 s".into(), found));
        }
        None
    }
}

/// Island `island`'s seed: the `(island + 1)`-th output of SplitMix64 started
/// at the campaign's `seed`, so that islands of one seed are far apart and a
/// given `(seed, island)` always gives the same search.
pub fn island_seed(seed: u64, island: usize) -> u64 {
    let mut z = seed.wrapping_add((island as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Something the executor calls after every generation whose search goes on
/// ([`super::Executor::migrate`]), with the solver between two batches.
pub trait Migration {
    /// Trades candidates after `generation` (0-based); may change the
    /// solver's population through [`Solver::immigrate`].
    fn migrate(&mut self, generation: usize, solver: &mut dyn Solver) -> Result<(), SearchError>;
}

/// One island's migrants for one exchange, as written in its file. Floats
/// are kept to the bit (serde_json's exact round trip).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Migrants {
    /// The island that sent them.
    pub island: usize,
    /// The generation after which they were sent.
    pub generation: usize,
    /// Genomes (scale space), best first.
    pub genomes: Vec<Vec<f64>>,
    /// Their costs.
    pub costs: Vec<f64>,
}

/// What happened at one exchange.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ExchangeStatus {
    /// The neighbour's migrants arrived and were taken in.
    Made,
    /// None arrived within the wait (or the wait was interrupted).
    Missed,
    /// The neighbour had ended before this exchange; nothing was waited for.
    NeighbourEnded,
}

/// An island's exchanges so far, by generation.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ExchangeLog {
    /// `(generation, status)`, in generation order.
    pub exchanges: Vec<(usize, ExchangeStatus)>,
}

impl ExchangeLog {
    /// Exchanges whose status is `status`.
    pub fn count(&self, status: ExchangeStatus) -> usize {
        self.exchanges.iter().filter(|(_, s)| *s == status).count()
    }

    /// Records `status` at `generation`, replacing what a search resumed
    /// from an earlier checkpoint had recorded from there on.
    fn record(&mut self, generation: usize, status: ExchangeStatus) {
        self.exchanges.retain(|&(g, _)| g < generation);
        self.exchanges.push((generation, status));
    }
}

/// The file island `island` sends after `generation`.
pub fn migrants_path(folder: &Path, island: usize, generation: usize) -> PathBuf {
    folder.join(format!("{island}-{generation}.json"))
}

/// The file that says island `island` has ended.
pub fn ended_path(folder: &Path, island: usize) -> PathBuf {
    folder.join(format!("{island}-done.json"))
}

/// Says that island `island` has ended after `generations` generations: its
/// neighbour stops waiting for it.
pub fn mark_ended(folder: &Path, island: usize, generations: usize) -> Result<(), SearchError> {
    let path = ended_path(folder, island);
    let text = format!("{{\"island\": {island}, \"generations\": {generations}}}\n");
    atomic_write(&path, text.as_bytes()).map_err(|source| SearchError::Io {
        action: "writing",
        path,
        source,
    })
}

/// Removes island `island`'s files from `folder` (a fresh start's, so that
/// an earlier run's migrants are never taken for this one's).
pub fn clear_island(folder: &Path, island: usize) {
    let prefix = format!("{island}-");
    let Ok(entries) = std::fs::read_dir(folder) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let name = name.to_string_lossy();
        let ours = name.strip_prefix(&prefix).is_some_and(|rest| {
            rest.strip_suffix(".json")
                .is_some_and(|g| g == "done" || g.bytes().all(|b| b.is_ascii_digit()))
        });
        if ours {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// The ring exchange of one island through a shared folder.
pub struct Exchange {
    folder: PathBuf,
    island: usize,
    settings: IslandSettings,
    interrupt: Option<Arc<AtomicBool>>,
    log: Arc<Mutex<ExchangeLog>>,
}

/// How often a waiting island looks for its neighbour's file.
const POLL: Duration = Duration::from_millis(20);

impl Exchange {
    /// Island `island` of a ring set by `settings`, trading through `folder`
    /// (created if needed), recording into `log` (which a resumed island
    /// starts from its earlier log).
    pub fn new(
        folder: impl Into<PathBuf>,
        island: usize,
        settings: IslandSettings,
        log: Arc<Mutex<ExchangeLog>>,
    ) -> Self {
        Self {
            folder: folder.into(),
            island,
            settings,
            interrupt: None,
            log,
        }
    }

    /// A flag that ends a wait at once (the exchange is then missed).
    pub fn interrupt(mut self, flag: Arc<AtomicBool>) -> Self {
        self.interrupt = Some(flag);
        self
    }

    fn interrupted(&self) -> bool {
        self.interrupt
            .as_ref()
            .is_some_and(|f| f.load(Ordering::SeqCst))
    }

    /// Writes this island's migrants for `generation`.
    fn send(&self, generation: usize, solver: &dyn Solver) -> Result<(), SearchError> {
        let (population, costs) = solver.population();
        let best: Vec<usize> = ranking(costs)
            .into_iter()
            .take(self.settings.migrants)
            .collect();
        let migrants = Migrants {
            island: self.island,
            generation,
            genomes: best.iter().map(|&i| population[i].clone()).collect(),
            costs: best.iter().map(|&i| costs[i]).collect(),
        };
        let path = migrants_path(&self.folder, self.island, generation);
        let text = serde_json::to_string(&migrants).expect("migrants serialise") + "\n";
        atomic_write(&path, text.as_bytes()).map_err(|source| SearchError::Io {
            action: "writing migrants",
            path,
            source,
        })
    }

    /// The neighbour's migrants for `generation`, waiting for them.
    fn receive(&self, generation: usize, genes: usize) -> Result<Migrants, ExchangeStatus> {
        let k = self.settings.count;
        let from = (self.island + k - 1) % k;
        let path = migrants_path(&self.folder, from, generation);
        let ended = ended_path(&self.folder, from);
        let deadline = Instant::now() + Duration::from_secs_f64(self.settings.wait_s);
        loop {
            if let Some(m) = read_migrants(&path, from, generation, genes) {
                return Ok(m);
            }
            // An ended island wrote every file it will ever write before
            // its end marker: look once more, then stop waiting.
            if ended.exists() {
                return read_migrants(&path, from, generation, genes)
                    .ok_or(ExchangeStatus::NeighbourEnded);
            }
            if self.interrupted() || Instant::now() >= deadline {
                return Err(ExchangeStatus::Missed);
            }
            std::thread::sleep(POLL);
        }
    }
}

/// The migrants in `path` if it holds `from`'s for `generation` with genomes
/// of `genes` genes and finite costs; `None` otherwise (absent, or not such
/// a file, which is then waited past like an absent one).
fn read_migrants(path: &Path, from: usize, generation: usize, genes: usize) -> Option<Migrants> {
    let text = std::fs::read_to_string(path).ok()?;
    let m: Migrants = serde_json::from_str(&text).ok()?;
    let fits = m.island == from
        && m.generation == generation
        && m.genomes.len() == m.costs.len()
        && m.genomes.iter().all(|g| g.len() == genes)
        && m.costs.iter().all(|c| c.is_finite());
    fits.then_some(m)
}

impl Migration for Exchange {
    fn migrate(&mut self, generation: usize, solver: &mut dyn Solver) -> Result<(), SearchError> {
        if !(generation + 1).is_multiple_of(self.settings.every) || self.settings.count < 2 {
            return Ok(());
        }
        self.send(generation, solver)?;
        let status = match self.receive(generation, solver.genes().len()) {
            Ok(m) => {
                let bounds = solver.bounds().to_vec();
                let genomes: Vec<Vec<f64>> = m
                    .genomes
                    .iter()
                    .map(|g| {
                        g.iter()
                            .zip(&bounds)
                            .map(|(&x, &(lo, hi))| clamp_into(x, lo, hi))
                            .collect()
                    })
                    .collect();
                if !solver.immigrate(&genomes, &m.costs) {
                    return Err(SearchError::InvalidSettings {
                        field: "islands",
                        reason: format!(
                            "the {} cannot take migrants; islands need the GA (method \"ga\")",
                            solver.method().label()
                        ),
                    });
                }
                ExchangeStatus::Made
            }
            Err(status) => status,
        };
        let mut log = self.log.lock().unwrap_or_else(|e| e.into_inner());
        log.record(generation, status);
        Ok(())
    }
}

/// One search outcome from the outcomes of several islands, best first:
/// the best island's (its history, termination and method) with every
/// island's final population merged and sorted by cost (an island's order
/// breaking ties), the evaluations summed and the generations and wall time
/// the longest island's. `None` for no outcome.
pub fn merge_outcomes(genes: &[GeneSpec], outcomes: &[&SearchOutcome]) -> Option<SearchOutcome> {
    let best = outcomes
        .iter()
        .enumerate()
        .min_by(|(i, a), (j, b)| a.best_cost.total_cmp(&b.best_cost).then(i.cmp(j)))
        .map(|(_, o)| *o)?;
    let mut members: Vec<(&Vec<f64>, f64)> = outcomes
        .iter()
        .flat_map(|o| o.population.iter().zip(o.costs.iter().copied()))
        .collect();
    members.sort_by(|a, b| a.1.total_cmp(&b.1));
    let scaled: Vec<Vec<f64>> = members
        .iter()
        .map(|(g, _)| g.iter().zip(genes).map(|(&v, s)| s.to_scaled(v)).collect())
        .collect();
    let mut merged = best.clone();
    merged.population = members.iter().map(|(g, _)| (*g).clone()).collect();
    merged.costs = members.iter().map(|(_, c)| *c).collect();
    merged.elite_spread = elite_spread(&scaled, genes);
    merged.evaluations = outcomes.iter().map(|o| o.evaluations).sum();
    merged.generations = outcomes.iter().map(|o| o.generations).max().unwrap_or(0);
    merged.wall_time_s = outcomes.iter().map(|o| o.wall_time_s).fold(0.0, f64::max);
    merged.warnings = Vec::new();
    for o in outcomes {
        for w in &o.warnings {
            if !merged.warnings.contains(w) {
                merged.warnings.push(w.clone());
            }
        }
    }
    merged.polish = None;
    Some(merged)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn island_seeds_differ_and_repeat() {
        let seeds: Vec<u64> = (0..8).map(|i| island_seed(1, i)).collect();
        let mut unique = seeds.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), 8);
        assert_eq!(seeds[3], island_seed(1, 3));
        assert_ne!(island_seed(1, 0), island_seed(2, 0));
    }

    #[test]
    fn settings_out_of_range_are_named() {
        let mut s = IslandSettings::with_count(4);
        assert_eq!(s.invalid(16), None);
        s.migrants = 16;
        assert_eq!(s.invalid(16).unwrap().0, "islands.migrants");
        s = IslandSettings::with_count(0);
        assert_eq!(s.invalid(16).unwrap().0, "islands.count");
        s = IslandSettings::with_count(2);
        s.wait_s = f64::NAN;
        assert_eq!(s.invalid(16).unwrap().0, "islands.wait_s");
    }

    #[test]
    fn islands_refuse_cmaes() {
        let s: crate::search::SearchSettings = serde_json::from_str(
            r#"{"population": 16, "generations": 5, "method": "cmaes", "islands": {"count": 2}}"#,
        )
        .unwrap();
        let e = s.validate().unwrap_err();
        assert_eq!(e.field, "islands");
        assert!(e.expected.contains("CMA-ES cannot take migrants"), "{e}");
    }

    #[test]
    fn clearing_removes_only_that_islands_files() {
        let dir = tempfile::tempdir().unwrap();
        for name in [
            "1-9.json",
            "1-done.json",
            "11-9.json",
            "1-x.json",
            "2-9.json",
        ] {
            std::fs::write(dir.path().join(name), "{}").unwrap();
        }
        clear_island(dir.path(), 1);
        let mut left: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left, ["1-x.json", "11-9.json", "2-9.json"]);
    }

    #[test]
    fn a_later_record_replaces_what_a_resume_repeats() {
        let mut log = ExchangeLog::default();
        log.record(9, ExchangeStatus::Made);
        log.record(19, ExchangeStatus::Missed);
        log.record(19, ExchangeStatus::Made);
        assert_eq!(log.count(ExchangeStatus::Made), 2);
        assert_eq!(log.count(ExchangeStatus::Missed), 0);
    }
}
