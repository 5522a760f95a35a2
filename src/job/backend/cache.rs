//! Where `auto` keeps what it measured: the choice of each job on each
//! machine ([`cache_file`], keyed by [`TrialKey`]), listed by `rigfit
//! devices` ([`kept_choices`]), and the CPU's rate a job observed
//! ([`observed_cpu_rate`]), from which `check` estimates. Every file is
//! written whole and atomically; one that cannot be read is an empty cache.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::BackendTrial;
use crate::campaign::Campaign;

/// Where the choices are kept: `RIGFIT_CACHE_DIR`, else
/// `$XDG_CACHE_HOME/rigfit`, else `~/.cache/rigfit`; the file
/// `backend-trials.json`. `None` when none of them is set.
pub fn cache_file() -> Option<PathBuf> {
    Some(crate::base::fsutil::cache_dir()?.join("backend-trials.json"))
}

/// Where `auto` keeps a choice in the cache ([`cache_file`]): the machine
/// (processor and adapters) and the job (the campaign's digest, the
/// precision asked for, the population). Written as one line
/// (`"<processor> | <adapters> | campaign <digest> | <precision> | population
/// <n>"`) and read back by [`TrialKey::parse`], so that what writes a key and
/// what lists the keys kept (`rigfit devices`) cannot drift apart.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TrialKey {
    /// The processor's model name ([`processor`]).
    pub processor: String,
    /// The adapters ([`adapters_key`]).
    pub adapters: String,
    /// The campaign's digest (its file and records), in hex.
    pub digest: String,
    /// The precision asked for (`"auto"`, `"f32"`, `"f64"`).
    pub precision: String,
    /// The job's population.
    pub population: usize,
}

impl TrialKey {
    /// The key of `campaign` at `precision` on this processor and `adapters`.
    pub fn of(campaign: &Campaign, adapters: &str, precision: &str) -> Self {
        Self {
            processor: processor(),
            adapters: adapters.to_string(),
            digest: format!("{:016x}", campaign.digest),
            precision: precision.to_string(),
            population: campaign.search.population,
        }
    }

    /// The key a line of the cache names, `None` where it is not one.
    pub fn parse(key: &str) -> Option<Self> {
        // From the right: the processor's name and the adapters' may hold
        // anything but the separator before them.
        let mut right = key.rsplitn(4, " | ");
        let population = right.next()?.strip_prefix("population ")?.parse().ok()?;
        let precision = right.next()?.to_string();
        let digest = right.next()?.strip_prefix("campaign ")?.to_string();
        let (processor, adapters) = right.next()?.split_once(" | ")?;
        Some(Self {
            processor: processor.to_string(),
            adapters: adapters.to_string(),
            digest,
            precision,
            population,
        })
    }

    /// Whether `other` is this key on any adapters.
    fn on_any_adapters(&self, other: &Self) -> bool {
        *self
            == Self {
                adapters: self.adapters.clone(),
                ..other.clone()
            }
    }
}

impl std::fmt::Display for TrialKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} | {} | campaign {} | {} | population {}",
            self.processor, self.adapters, self.digest, self.precision, self.population
        )
    }
}

/// The cache key of `campaign` run with `--backend auto` at `precision`
/// (`"auto"`, `"f32"` or `"f64"`, as asked) on this machine's adapters.
pub fn auto_key(campaign: &Campaign, precision: &str) -> String {
    let adapters = adapters_key(&crate::gpu::list_adapters());
    TrialKey::of(campaign, &adapters, precision).to_string()
}

/// The adapters as a cache key names them.
pub fn adapters_key(adapters: &[crate::gpu::AdapterSummary]) -> String {
    adapters
        .iter()
        .map(|a| format!("{} ({}, {})", a.name, a.backend, a.driver))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A choice `auto` keeps in the cache ([`cache_file`]), as `rigfit devices`
/// lists it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KeptChoice {
    /// The campaign's digest (its file and records), as the key has it.
    pub digest: String,
    /// The precision asked for (`"auto"`, `"f32"`, `"f64"`).
    pub precision: String,
    /// The job's population.
    pub population: usize,
    /// What was measured and chosen.
    pub trial: BackendTrial,
}

/// Every choice kept for this processor and `adapters` ([`adapters_key`]),
/// in the cache's order.
pub fn kept_choices(adapters: &str) -> Vec<KeptChoice> {
    cache_file().map_or_else(Vec::new, |file| {
        kept_choices_in(&file, &processor(), adapters)
    })
}

fn kept_choices_in(file: &Path, processor: &str, adapters: &str) -> Vec<KeptChoice> {
    read_cache::<BackendTrial>(file)
        .into_iter()
        .filter_map(|(key, trial)| {
            let key = TrialKey::parse(&key)?;
            (key.processor == processor && key.adapters == adapters).then_some(KeptChoice {
                digest: key.digest,
                precision: key.precision,
                population: key.population,
                trial,
            })
        })
        .collect()
}

/// [`auto_key`], where `always` or where the cache holds a choice for this
/// processor, campaign, precision and population on some adapters (read
/// without listing the adapters, which takes tens of milliseconds: a short
/// job lists them only where a choice may be waiting for it).
pub(super) fn auto_key_if(campaign: &Campaign, precision: &str, always: bool) -> Option<String> {
    let mut key = TrialKey::of(campaign, "", precision);
    let may_be_cached = || {
        cache_file().is_some_and(|file| {
            read_cache::<serde_json::Value>(&file)
                .keys()
                .filter_map(|k| TrialKey::parse(k))
                .any(|k| key.on_any_adapters(&k))
        })
    };
    if !(always || may_be_cached()) {
        return None;
    }
    key.adapters = adapters_key(&crate::gpu::list_adapters());
    Some(key.to_string())
}

/// The processor's model name (Linux's /proc/cpuinfo), else the architecture.
pub fn processor() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

/// Every entry of a cache file (`{key: value}`), none where it is missing
/// or unreadable.
fn read_cache<T: serde::de::DeserializeOwned>(file: &Path) -> BTreeMap<String, T> {
    crate::base::fsutil::read_input(file, 1 << 20)
        .ok()
        .and_then(|b| serde_json::from_slice(&b).ok())
        .unwrap_or_default()
}

/// Keeps `value` under `key` in the cache file `file` (written whole,
/// atomically).
fn keep_in<T: Serialize + serde::de::DeserializeOwned>(
    file: &Path,
    key: &str,
    value: T,
) -> std::io::Result<()> {
    if let Some(dir) = file.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut all: BTreeMap<String, T> = read_cache(file);
    all.insert(key.to_string(), value);
    let json = serde_json::to_vec_pretty(&all).expect("a cache serialises");
    crate::base::fsutil::atomic_write(file, &json)
}

/// The choice cached under `key` in [`cache_file`], marked as cached.
pub fn cached(key: &str) -> Option<BackendTrial> {
    cached_in(&cache_file()?, key)
}

fn cached_in(file: &Path, key: &str) -> Option<BackendTrial> {
    read_cache::<BackendTrial>(file)
        .remove(key)
        .map(|t| BackendTrial {
            cached: true,
            trial_s: 0.0,
            ..t
        })
}

/// Keeps `trial` under `key` in [`cache_file`] (the file written whole,
/// atomically). A cache that cannot be written is only a missed saving: the
/// caller warns, the job goes on.
pub fn remember(key: &str, trial: &BackendTrial) -> std::io::Result<()> {
    match cache_file() {
        Some(file) => keep_in(&file, key, trial.clone()),
        None => Ok(()),
    }
}

/// What a job's search ran at on every CPU core: what `check` estimates the
/// next run of the same job from, where `auto` measured nothing (a short
/// job runs on the CPU unmeasured) or the CPU was forced.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObservedRate {
    /// Candidate-steps per second of the search (its own work included).
    pub cpu_rate: f64,
    /// The search's evaluations.
    pub evaluations: u64,
    /// The search's wall time (s).
    pub seconds: f64,
}

/// The file of [`ObservedRate`]s: `observed-rates.json` beside
/// [`cache_file`].
fn observed_file() -> Option<PathBuf> {
    Some(cache_file()?.with_file_name("observed-rates.json"))
}

/// The key of a job's [`ObservedRate`]: the processor and its cores, the
/// campaign's digest, the CPU's precision (`"f64"`, `"f32"`) and the
/// population (no adapters: listing them takes longer than the shortest
/// jobs' start-up).
pub fn observed_key(campaign: &Campaign, precision: &str) -> String {
    let cores = crate::eval::all_cores();
    format!(
        "{} ({cores} cores) | campaign {:016x} | {precision} | population {}",
        processor(),
        campaign.digest,
        campaign.search.population
    )
}

/// The CPU rate the last run of `campaign` at `precision` on this machine
/// observed, if one was kept.
pub fn observed_cpu_rate(campaign: &Campaign, precision: &str) -> Option<f64> {
    let file = observed_file()?;
    read_cache::<ObservedRate>(&file)
        .remove(&observed_key(campaign, precision))
        .map(|o| o.cpu_rate)
        .filter(|r| r.is_finite() && *r > 0.0)
}

/// Keeps what a job's search ran at on every CPU core, for `check`. A rate
/// that cannot be kept is only a rougher estimate next time.
pub fn remember_observed(
    campaign: &Campaign,
    precision: &str,
    observed: ObservedRate,
) -> std::io::Result<()> {
    match observed_file() {
        Some(file) => keep_in(&file, &observed_key(campaign, precision), observed),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_key_reads_back_as_it_was_written_whatever_the_adapters() {
        let key = |adapters: &str| TrialKey {
            processor: "AMD EPYC 9R14 96-Core Processor".into(),
            adapters: adapters.into(),
            digest: "0123456789abcdef".into(),
            precision: "auto".into(),
            population: 4096,
        };
        for adapters in [
            "",
            "llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan, Mesa 22.3.6)",
            "a (Vulkan, 1), b | c (Vulkan, 2)",
        ] {
            let k = key(adapters);
            assert_eq!(TrialKey::parse(&k.to_string()), Some(k.clone()), "{k}");
            assert!(k.on_any_adapters(&key("other (Vulkan, 3)")));
        }
        let other_job = TrialKey {
            population: 2048,
            ..key("")
        };
        assert!(!key("").on_any_adapters(&other_job));
        for not_a_key in [
            "",
            "EPYC | x | campaign 00 | f64",
            "EPYC | x | 00 | f64 | population 1",
            "EPYC | x | campaign 00 | f64 | population many",
            "EPYC campaign 00 | f64 | population 1",
        ] {
            assert_eq!(TrialKey::parse(not_a_key), None, "{not_a_key}");
        }
    }

    #[test]
    fn a_cached_choice_reads_back_marked_as_cached() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("cache").join("backend-trials.json");
        let t = BackendTrial {
            chosen: "cpu".into(),
            gpu_rate: 1e7,
            gpu_kernel: Some("generic".into()),
            gpu_kernel_rates: [("generic".into(), 1e7), ("specialised".into(), 5e6)].into(),
            cpu_rate: 1e8,
            candidates: 128,
            campaign: None,
            gpu_steps_timed: None,
            steps_timed: None,
            shortened: None,
            skipped: false,
            trial_s: 0.25,
            cached: false,
            gpu_startup_s: Some(0.3),
        };
        assert_eq!(cached_in(&file, "k"), None);
        keep_in(&file, "k", t.clone()).unwrap();
        let back = cached_in(&file, "k").unwrap();
        assert!(back.cached);
        assert_eq!(back.trial_s, 0.0);
        assert_eq!((back.chosen.as_str(), back.cpu_rate), ("cpu", 1e8));
        assert_eq!(back.gpu_kernel.as_deref(), Some("generic"));
        assert_eq!(back.gpu_startup_s, Some(0.3));
        assert_eq!(back.gpu_kernel_rates, t.gpu_kernel_rates);
        assert_eq!(cached_in(&file, "other"), None);
        // `rigfit devices` lists the choices of this processor and these
        // adapters alone, each with what its key says.
        let key = |p: &str, a: &str, n: usize| {
            let key = format!("{p} | {a} | campaign 00ff | f64 | population {n}");
            let parsed = TrialKey::parse(&key).expect("a key reads back");
            assert_eq!(parsed.to_string(), key);
            key
        };
        keep_in(&file, &key("EPYC", "lavapipe (Vulkan, 22)", 256), t.clone()).unwrap();
        keep_in(&file, &key("EPYC", "other (Vulkan, 1)", 512), t.clone()).unwrap();
        keep_in(
            &file,
            &key("Xeon", "lavapipe (Vulkan, 22)", 1024),
            t.clone(),
        )
        .unwrap();
        let kept = kept_choices_in(&file, "EPYC", "lavapipe (Vulkan, 22)");
        assert_eq!(kept.len(), 1, "{kept:?}");
        assert_eq!(
            (
                kept[0].digest.as_str(),
                kept[0].precision.as_str(),
                kept[0].population
            ),
            ("00ff", "f64", 256)
        );
        assert_eq!(kept[0].trial, t);
        assert!(
            back.line().contains("as measured before"),
            "{}",
            back.line()
        );
        assert!(t.line().contains("chose the CPU"), "{}", t.line());
    }
}
