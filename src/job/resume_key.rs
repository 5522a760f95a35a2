//! What a campaign's checkpoint must agree on to be resumed: what can change
//! the search's path, and nothing else. The campaign file is compared by its
//! meaning (its JSON without the free-text `description` and without the
//! search's stopping limits, which only decide when a search stops, as
//! `--generations` does), each experiment's record by the numbers the
//! campaign read from it (a comment line, a column it does not read, or a
//! number written another way changes nothing), and a rig file by its bytes.

use std::fmt::Write as _;
use std::path::Path;

use serde_json::Value;

use crate::campaign::{Campaign, FNV_BASIS, fnv1a};
use crate::search::Fingerprint;

/// The campaign's search keys that only decide when a search stops; a resumed
/// search may be given others.
pub const STOPPING_LIMITS: [&str; 6] = [
    "generations",
    "stall_generations",
    "target_fitness",
    "max_evaluations",
    "max_time_s",
    "checkpoint_every",
];

/// What a campaign's checkpoint must agree on to be resumed.
pub fn fingerprint(campaign: &Campaign, backend: &str, precision: &str) -> Fingerprint {
    let mut f = Fingerprint::new()
        .with(
            "campaign settings (description and stopping limits aside)",
            format!("{:016x}", settings_digest(&campaign.raw_json)),
        )
        .with("backend", backend)
        .with("precision", precision)
        .with("substeps", campaign.solver.substeps.to_string());
    if let Some(rig) = rig_file(campaign) {
        f = f.with_file("rig file", rig);
    }
    for x in &campaign.problem.experiments {
        f = f.with(
            format!("record of experiment {}", x.name),
            format!("{:016x}", record_digest(x)),
        );
    }
    for g in &campaign.genes {
        f = f.with(
            format!("gene {}", g.name),
            format!("[{:e}, {:e}] {:?}", g.lower, g.upper, g.scale),
        );
    }
    f
}

/// The digest of the campaign's JSON without what cannot change a resumed
/// search (its text where it is not JSON).
pub fn settings_digest(raw_json: &str) -> u64 {
    let Ok(mut v) = serde_json::from_str::<Value>(raw_json) else {
        return fnv1a(FNV_BASIS, raw_json.as_bytes());
    };
    if let Some(top) = v.as_object_mut() {
        top.remove("description");
        if let Some(search) = top.get_mut("search").and_then(Value::as_object_mut) {
            for k in STOPPING_LIMITS {
                search.remove(k);
            }
        }
    }
    fnv1a(FNV_BASIS, v.to_string().as_bytes())
}

/// The digest of the numbers an experiment scores: its samples, timing,
/// window, weight and drive (each float by its exact shortest form).
fn record_digest(x: &crate::eval::ExperimentData) -> u64 {
    struct Fnv(u64);
    impl std::fmt::Write for Fnv {
        fn write_str(&mut self, s: &str) -> std::fmt::Result {
            self.0 = fnv1a(self.0, s.as_bytes());
            Ok(())
        }
    }
    let mut h = Fnv(FNV_BASIS);
    // Writing into a hash cannot fail.
    let _ = write!(h, "{x:?}");
    h.0
}

/// The rig file the campaign names, where it names a file.
fn rig_file(campaign: &Campaign) -> Option<&Path> {
    let v: Value = serde_json::from_str(&campaign.raw_json).ok()?;
    let rig = v.get("rig")?.as_str()?;
    campaign
        .inputs
        .iter()
        .skip(1)
        .find(|p| p.ends_with(rig))
        .map(|p| p.as_path())
}
