//! The profiles' checkpoint: every grid point's Levenberg–Marquardt state,
//! floats as their bits, written atomically, so that a resumed run
//! re-linearises the stored points and goes on with the same bits.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::base::fsutil::atomic_write;
use crate::search::SearchError;

const FORMAT: &str = "rigfit-profile-checkpoint";
const VERSION: u32 = 1;

/// One run's state (floats as bits).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(super) struct SavedRun {
    pub x: Vec<u64>,
    pub lambda: u64,
    pub nu: u64,
    pub done: bool,
}

/// One grid point: its gene, value held (scale space, bits), round and run
/// (`None`: its start blew up).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(super) struct SavedPoint {
    pub gene: usize,
    pub at: u64,
    pub round: u8,
    pub run: Option<SavedRun>,
}

/// The whole state between two iterations.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(super) struct Saved {
    pub format: String,
    pub version: u32,
    /// Digest of the genes, the fitted point, the noise and the settings.
    pub fingerprint: String,
    pub round: u8,
    pub round_iterations: usize,
    pub iterations: usize,
    pub evaluations: u64,
    pub wall_time_s: u64,
    pub chi2_opt: u64,
    pub points: Vec<SavedPoint>,
}

impl Saved {
    /// A state to save.
    pub(super) fn stamp(fingerprint: String) -> Self {
        Self {
            format: FORMAT.into(),
            version: VERSION,
            fingerprint,
            round: 1,
            round_iterations: 0,
            iterations: 0,
            evaluations: 0,
            wall_time_s: 0,
            chi2_opt: 0,
            points: Vec::new(),
        }
    }

    pub(super) fn save(&self, path: &Path) -> Result<(), SearchError> {
        let text = serde_json::to_vec(self).expect("the checkpoint serialises");
        atomic_write(path, &text).map_err(|source| SearchError::Io {
            action: "writing the profiles' checkpoint",
            path: path.into(),
            source,
        })
    }

    /// The checkpoint at `path`, refused unless it was written for
    /// `fingerprint`.
    pub(super) fn load(path: &Path, fingerprint: &str) -> Result<Self, SearchError> {
        let bytes = std::fs::read(path).map_err(|source| SearchError::Io {
            action: "reading the profiles' checkpoint",
            path: path.into(),
            source,
        })?;
        let bad = |reason: String| SearchError::CheckpointFormat {
            path: path.into(),
            reason,
        };
        let saved: Self = serde_json::from_slice(&bytes).map_err(|e| bad(e.to_string()))?;
        if saved.format != FORMAT || saved.version != VERSION {
            return Err(bad(format!(
                "not a profile checkpoint of version {VERSION} (found {} {})",
                saved.format, saved.version
            )));
        }
        if saved.fingerprint != fingerprint {
            return Err(bad(
                "it was written for another fit (the fitted values, genes, noise or profile \
                 settings differ); delete it to compute the profiles afresh"
                    .into(),
            ));
        }
        Ok(saved)
    }
}

/// FNV-1a 64 of `text`, hex.
pub(super) fn digest(text: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}
