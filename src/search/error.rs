//! Errors of the search.

use std::path::PathBuf;

use crate::eval::EvalError;

/// Everything that can stop a search with an error.
#[derive(Debug, thiserror::Error)]
pub enum SearchError {
    /// A gene's description cannot be searched.
    #[error("gene `{name}`: {reason}")]
    InvalidGene {
        /// Gene name.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// A GA setting would make the algorithm ill-defined.
    #[error("search setting `{field}`: {reason}")]
    InvalidSettings {
        /// Setting name as in the campaign's `"search"` object.
        field: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The cost function returned the wrong number of costs.
    #[error("cost function returned {found} costs for {expected} genomes")]
    CostLength {
        /// Genomes handed in.
        expected: usize,
        /// Costs returned.
        found: usize,
    },
    /// The evaluator failed.
    #[error("evaluation failed")]
    Eval(#[from] EvalError),
    /// A cost function other than an [`crate::eval::Evaluator`] failed.
    #[error("cost function failed: {0}")]
    Cost(String),
    /// Reading or writing a file failed.
    #[error("{action} `{}`", path.display())]
    Io {
        /// What was being done ("writing checkpoint", …).
        action: &'static str,
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A checkpoint file is not a valid checkpoint of this search.
    #[error("checkpoint `{}` is unusable: {reason}", path.display())]
    CheckpointFormat {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// The checkpoint was written by a different campaign.
    #[error(
        "checkpoint `{}` was written for a different problem; changed: {}. A resumed search \
         continues the saved population and random stream, which belong to the model, records, \
         free parameters and search method they were made for (a description, a comment in a \
         record and the stopping limits may change): undo the change, or start afresh without \
         resuming",
        path.display(),
        changes.join("; ")
    )]
    FingerprintMismatch {
        /// The checkpoint file.
        path: PathBuf,
        /// Keys that differ.
        changed_keys: Vec<String>,
        /// One human-readable line per difference (`key: old → new`).
        changes: Vec<String>,
    },
    /// An observer failed.
    #[error("observer `{observer}` failed: {reason}")]
    Observer {
        /// Observer name.
        observer: &'static str,
        /// What went wrong.
        reason: String,
    },
}

impl SearchError {
    /// Whether the input is at fault rather than the search: a gene or
    /// setting it cannot search with, or a checkpoint of another campaign
    /// or format.
    pub fn blames_input(&self) -> bool {
        matches!(
            self,
            Self::FingerprintMismatch { .. }
                | Self::CheckpointFormat { .. }
                | Self::InvalidGene { .. }
                | Self::InvalidSettings { .. }
        )
    }
}
