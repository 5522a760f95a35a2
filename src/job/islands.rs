//! A job as islands (`"search": {"islands": …}`, `rigfit run --islands K`):
//! K seeded searches of the campaign trading their best candidates through
//! `<out>/islands/migrants/` ([`crate::search::islands`]), then the best of
//! them polished and written as any job's outputs.
//!
//! ```text
//! <out>/islands/<i>/checkpoint.json   island i's search (resumed by --resume)
//! <out>/islands/<i>/history.csv       its generations
//! <out>/islands/<i>/exchanges.json    its exchanges so far
//! <out>/islands/<i>/island.json       its outcome, once its search ended
//! <out>/islands/migrants/<i>-<g>.json what island i sent after generation g
//! <out>/islands/migrants/<i>-done.json  island i has ended
//! ```
//!
//! Every island runs in one process on threads sharing one evaluator
//! ([`run_islands`]), or each in a process of its own ([`run_island`], a
//! Slurm array task) and then [`gather`]: the same bits either way, since an
//! evaluator scores a candidate the same in any batch and the gather reads
//! the islands' outcomes back from their files in both cases.

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};

use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

use super::{
    CampaignCost, FolderMode, JobError, JobOptions, JobSummary, OutputFolder, conclude,
    fingerprint, gene_specs, polish, update_result,
};
use crate::base::fsutil::atomic_write;
use crate::campaign::Campaign;
use crate::eval::{EvalError, Evaluator};
use crate::search::islands::{
    Exchange, ExchangeLog, ExchangeStatus, IslandSettings, Migration, clear_island, island_seed,
    mark_ended, merge_outcomes,
};
use crate::search::{
    BatchCost, CostBatch, Executor, Fingerprint, GenerationReport, HistoryCsvObserver, Observer,
    ObserverMode, ProgressObserver, SearchError, SearchOutcome, Solver, TerminationReason,
};

/// The islands' folder inside the output folder.
pub const ISLANDS_DIR: &str = "islands";
/// The migrants' folder inside [`ISLANDS_DIR`].
pub const MIGRANTS_DIR: &str = "migrants";
/// An island's outcome, in its folder.
pub const ISLAND_FILE: &str = "island.json";
/// An island's exchanges so far, in its folder.
pub const EXCHANGES_FILE: &str = "exchanges.json";

/// How an island's search ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IslandStatus {
    /// Its search ran to its end.
    Finished,
    /// Interrupted: its checkpoint is kept for `--resume`.
    Interrupted,
}

/// What an island leaves in `island.json`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct IslandRecord {
    /// Its index in the ring.
    pub island: usize,
    /// Its seed ([`island_seed`]).
    pub seed: u64,
    /// How its search ended.
    pub status: IslandStatus,
    /// Its exchanges.
    pub exchanges: ExchangeLog,
    /// Its search's outcome (floats to the bit).
    pub outcome: SearchOutcome,
}

/// The campaign's islands, or the refusal of a job without them.
fn settings_of(campaign: &Campaign, out: &Path) -> Result<IslandSettings, JobError> {
    campaign.search.islands.ok_or_else(|| JobError::Islands {
        path: out.into(),
        reason: "the campaign sets no search.islands and no --islands was given".into(),
    })
}

/// Island `island`'s folder.
pub fn island_dir(out: &Path, island: usize) -> PathBuf {
    out.join(ISLANDS_DIR).join(island.to_string())
}

fn write_json(path: &Path, value: &impl Serialize) -> Result<(), JobError> {
    let text = serde_json::to_string_pretty(value).expect("serialises") + "\n";
    atomic_write(path, text.as_bytes()).map_err(|source| JobError::Write {
        path: path.into(),
        source,
    })
}

/// Runs every island on threads of this process, sharing `evaluator`, then
/// [`gather`]s them. `None` when interrupted: the islands' checkpoints are
/// kept and `--resume` continues them.
pub fn run_islands(
    campaign: &Campaign,
    evaluator: Box<dyn Evaluator>,
    opts: &JobOptions,
    backend_trial: Option<super::backend::BackendTrial>,
    mode: FolderMode,
) -> Result<Option<JobSummary>, JobError> {
    let settings = settings_of(campaign, &opts.out)?;
    let fp = job_fingerprint(campaign, evaluator.as_ref());
    let cost = Mutex::new(
        CampaignCost::new(campaign, evaluator, opts.require_gpu, opts.threads)
            .with_interrupt(opts.interrupt.clone()),
    );
    let results: Vec<Result<IslandRecord, JobError>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..settings.count)
            .map(|i| {
                let (cost, fp) = (&cost, fp.clone());
                s.spawn(move || island_search(campaign, i, SharedCost(cost), opts, fp, mode))
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join().unwrap_or_else(|_| {
                    Err(SearchError::Cost("an island's thread panicked".into()).into())
                })
            })
            .collect()
    });
    let cost = cost.into_inner().unwrap_or_else(|e| e.into_inner());
    let mut interrupted = false;
    for r in results {
        match r {
            Ok(record) => interrupted |= record.status == IslandStatus::Interrupted,
            Err(JobError::Search(SearchError::Eval(EvalError::Cancelled)))
                if opts.interrupt.load(Ordering::SeqCst) =>
            {
                interrupted = true;
            }
            Err(e) => return Err(e),
        }
    }
    if interrupted {
        return Ok(None);
    }
    gather(campaign, cost.into_evaluator(), opts, backend_trial).map(Some)
}

/// Runs island `island` alone (one process of several, or an array task):
/// its files only; [`gather`] polishes once the islands have ended.
pub fn run_island(
    campaign: &Campaign,
    evaluator: Box<dyn Evaluator>,
    opts: &JobOptions,
    island: usize,
    mode: FolderMode,
) -> Result<IslandRecord, JobError> {
    let settings = settings_of(campaign, &opts.out)?;
    if island >= settings.count {
        return Err(JobError::Islands {
            path: opts.out.clone(),
            reason: format!(
                "--island {island} is not one of the {} islands (0 to {})",
                settings.count,
                settings.count - 1
            ),
        });
    }
    let fp = job_fingerprint(campaign, evaluator.as_ref());
    let mut cost = CampaignCost::new(campaign, evaluator, opts.require_gpu, opts.threads)
        .with_interrupt(opts.interrupt.clone());
    island_search(campaign, island, &mut cost, opts, fp, mode)
}

/// The job's fingerprint, as [`super::run_observed`] builds it.
fn job_fingerprint(campaign: &Campaign, evaluator: &dyn Evaluator) -> Fingerprint {
    let info = evaluator.info();
    let precision = format!("{:?}", info.precision).to_lowercase();
    fingerprint(campaign, &info.backend, &precision)
}

/// One island's search into its folder, its exchanges through the
/// migrants' folder.
fn island_search<C: BatchCost>(
    campaign: &Campaign,
    island: usize,
    cost: C,
    opts: &JobOptions,
    fp: Fingerprint,
    mode: FolderMode,
) -> Result<IslandRecord, JobError> {
    let islands = settings_of(campaign, &opts.out)?;
    let dir = island_dir(&opts.out, island);
    let migrants = opts.out.join(ISLANDS_DIR).join(MIGRANTS_DIR);
    let checkpoint = dir.join(super::CHECKPOINT_FILE);
    let resume = opts.resume && checkpoint.is_file();
    let mode = match (opts.resume, resume) {
        (_, true) => FolderMode::Resume,
        (true, false) => FolderMode::Overwrite,
        (false, _) => mode,
    };
    let files: Vec<String> = [
        super::CHECKPOINT_FILE,
        "history.csv",
        EXCHANGES_FILE,
        ISLAND_FILE,
    ]
    .map(String::from)
    .to_vec();
    let _folder = OutputFolder::open(&dir, &files, &campaign.inputs, mode)?;
    std::fs::create_dir_all(&migrants).map_err(|source| JobError::Write {
        path: migrants.clone(),
        source,
    })?;
    let exchanges = dir.join(EXCHANGES_FILE);
    let log = if resume {
        std::fs::read_to_string(&exchanges)
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok())
            .unwrap_or_default()
    } else {
        clear_island(&migrants, island);
        let _ = std::fs::remove_file(dir.join(ISLAND_FILE));
        let _ = std::fs::remove_file(&exchanges);
        ExchangeLog::default()
    };
    let log = Arc::new(Mutex::new(log));
    let mut settings = campaign.search.clone();
    settings.seed = island_seed(campaign.search.seed, island);
    let genes = gene_specs(campaign);
    let solver = settings.method.solver(&settings, genes.clone())?;
    let fp = fp
        .with("island", island.to_string())
        .with("islands.count", islands.count.to_string())
        .with("islands.every", islands.every.to_string())
        .with("islands.migrants", islands.migrants.to_string());
    let exchange =
        Exchange::new(&migrants, island, islands, log.clone()).interrupt(opts.interrupt.clone());
    let mut exec = Executor::boxed(solver, cost)
        .fingerprint(fp)
        .checkpoint_to(&checkpoint)
        .interrupt(opts.interrupt.clone())
        .observe(
            HistoryCsvObserver::new(dir.join("history.csv"), &genes),
            ObserverMode::Every(10),
        )
        .observe(
            IslandProgress {
                island,
                quiet: opts.quiet,
            },
            ObserverMode::Every(islands.every),
        )
        .migrate(LoggedExchange {
            exchange,
            log: log.clone(),
            path: exchanges,
        });
    if resume {
        exec = exec.resume_from(&checkpoint)?;
    }
    let searched = exec.run();
    if searched.is_err() && !opts.interrupt.load(Ordering::SeqCst) {
        // A failed island ends: its neighbour stops waiting for it.
        let _ = mark_ended(&migrants, island, 0);
    }
    let outcome = searched?;
    let status = match outcome.termination {
        TerminationReason::Interrupted => IslandStatus::Interrupted,
        _ => IslandStatus::Finished,
    };
    let record = IslandRecord {
        island,
        seed: settings.seed,
        status,
        exchanges: log.lock().unwrap_or_else(|e| e.into_inner()).clone(),
        outcome,
    };
    write_json(&dir.join(ISLAND_FILE), &record)?;
    if status == IslandStatus::Finished {
        mark_ended(&migrants, island, record.outcome.generations)?;
    }
    Ok(record)
}

/// Polishes the best of the islands that finished and writes the job's
/// outputs into the output folder, as `rigfit run` does, with an `islands`
/// key in result.json: each island's seed, status, evaluations, best cost
/// and exchanges. An island that did not finish is listed, not waited for.
pub fn gather(
    campaign: &Campaign,
    evaluator: Box<dyn Evaluator>,
    opts: &JobOptions,
    backend_trial: Option<super::backend::BackendTrial>,
) -> Result<JobSummary, JobError> {
    let settings = settings_of(campaign, &opts.out)?;
    let records: Vec<Option<IslandRecord>> = (0..settings.count)
        .map(|i| {
            let path = island_dir(&opts.out, i).join(ISLAND_FILE);
            std::fs::read_to_string(path)
                .ok()
                .and_then(|t| serde_json::from_str::<IslandRecord>(&t).ok())
                .filter(|r| r.island == i)
        })
        .collect();
    let finished: Vec<&SearchOutcome> = records
        .iter()
        .flatten()
        .filter(|r| r.status == IslandStatus::Finished)
        .map(|r| &r.outcome)
        .collect();
    let genes = gene_specs(campaign);
    let Some(mut merged) = merge_outcomes(&genes, &finished) else {
        return Err(JobError::Islands {
            path: opts.out.clone(),
            reason: format!(
                "none of the {} islands has finished (no {}/<i>/{ISLAND_FILE} of a finished \
                 search); run them first (rigfit run --islands {} --island I)",
                settings.count, ISLANDS_DIR, settings.count
            ),
        });
    };
    let (table, notes) = islands_table(&settings, &records);
    merged.warnings.extend(notes);
    let mut cost = CampaignCost::new(campaign, evaluator, opts.require_gpu, opts.threads)
        .with_interrupt(opts.interrupt.clone());
    let outcome = if campaign.search.polish.enabled {
        let solver: Box<dyn Solver> = campaign
            .search
            .method
            .solver(&campaign.search, genes.clone())?;
        let step = polish(campaign, &genes, cost.precision());
        Executor::boxed(solver, &mut cost)
            .interrupt(opts.interrupt.clone())
            .observe(
                ProgressObserver::new(merged.generations, opts.quiet),
                ObserverMode::Always,
            )
            .then_polish(step, campaign.search.polish.starts)
            .polish_outcome(merged)?
    } else {
        merged
    };
    let summary = conclude(campaign, cost, outcome, &genes, opts, backend_trial, false)?;
    update_result(&opts.out, "islands", table)?;
    Ok(summary)
}

/// result.json's `islands` value, and the warnings the islands call for.
fn islands_table(
    settings: &IslandSettings,
    records: &[Option<IslandRecord>],
) -> (Value, Vec<String>) {
    let mut notes = Vec::new();
    let mut rows = Vec::new();
    let mut reproducible = true;
    for (i, r) in records.iter().enumerate() {
        let Some(r) = r else {
            reproducible = false;
            notes.push(format!(
                "island {i} left no outcome (killed, failed or not run); the best of the others \
                 was polished"
            ));
            rows.push(json!({"island": i, "status": "missing"}));
            continue;
        };
        let missed = r.exchanges.count(ExchangeStatus::Missed);
        if missed > 0 || r.status != IslandStatus::Finished {
            reproducible = false;
        }
        if missed > 0 {
            notes.push(format!(
                "island {i} missed {missed} exchange(s) (its neighbour was slow or dead); this \
                 run is not reproducible bit for bit"
            ));
        }
        rows.push(json!({
            "island": i,
            "seed": r.seed,
            "status": r.status,
            "generations": r.outcome.generations,
            "evaluations": r.outcome.evaluations,
            "best_cost": r.outcome.best_cost,
            "termination": r.outcome.termination,
            "exchanges_made": r.exchanges.count(ExchangeStatus::Made),
            "exchanges_missed": missed,
            "exchanges_after_neighbour_ended": r.exchanges.count(ExchangeStatus::NeighbourEnded),
        }));
    }
    let table = json!({
        "count": settings.count,
        "every": settings.every,
        "migrants": settings.migrants,
        "wait_s": settings.wait_s,
        "reproducible": reproducible,
        "islands": rows,
    });
    (table, notes)
}

/// The evaluator that island threads share, one batch at a time (each batch
/// takes every core the evaluator has).
struct SharedCost<'a, 'c>(&'a Mutex<CampaignCost<'c>>);

impl BatchCost for SharedCost<'_, '_> {
    fn cost(&mut self, genomes: &[Vec<f64>]) -> Result<CostBatch, SearchError> {
        let mut cost = self.0.lock().unwrap_or_else(|e| e.into_inner());
        cost.cost(genomes)
    }
}

/// The exchange, its log written to the island's folder after each one, so
/// that a resumed island reports the exchanges before its checkpoint too.
struct LoggedExchange {
    exchange: Exchange,
    log: Arc<Mutex<ExchangeLog>>,
    path: PathBuf,
}

impl Migration for LoggedExchange {
    fn migrate(&mut self, generation: usize, solver: &mut dyn Solver) -> Result<(), SearchError> {
        let before = self.log.lock().unwrap_or_else(|e| e.into_inner()).clone();
        self.exchange.migrate(generation, solver)?;
        let after = self.log.lock().unwrap_or_else(|e| e.into_inner()).clone();
        if after != before {
            let text = serde_json::to_string(&after).expect("log serialises") + "\n";
            atomic_write(&self.path, text.as_bytes()).map_err(|source| SearchError::Io {
                action: "writing",
                path: self.path.clone(),
                source,
            })?;
        }
        Ok(())
    }
}

/// One line per island every exchange, on stderr unless quiet.
struct IslandProgress {
    island: usize,
    quiet: bool,
}

impl Observer for IslandProgress {
    fn observe(&mut self, r: &GenerationReport) -> Result<(), SearchError> {
        if !self.quiet {
            eprintln!(
                "rigfit: island {}: generation {}, best 1 − R² {:.4e}, {} evaluations",
                self.island,
                r.generation + 1,
                r.best_cost,
                r.evaluations
            );
        }
        Ok(())
    }
}
