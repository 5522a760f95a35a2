//! What goes wrong with a series, naming the file and the place in it.

use std::path::PathBuf;

/// Errors of a series: its file, its table, its folder, its tasks.
#[derive(Debug, thiserror::Error)]
pub enum SeriesError {
    /// The series file or its table says something wrong.
    #[error("{}: {place}: {reason}", file.display())]
    Input {
        /// The file.
        file: PathBuf,
        /// Where in it: a JSON path (`campaign`), a line and column
        /// (`line 4, column "record"`), or `(file)`.
        place: String,
        /// What is wrong and what was expected.
        reason: String,
    },
    /// A file could not be read or written.
    #[error("`{}`: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// The series' folder cannot be used.
    #[error("series folder `{}`: {reason}", path.display())]
    Folder {
        /// The folder.
        path: PathBuf,
        /// Why not.
        reason: String,
    },
    /// A task number or test the manifest does not hold.
    #[error("{0}")]
    Task(String),
    /// The series' folder lock or its files, as a job's.
    #[error(transparent)]
    Job(#[from] crate::job::JobError),
}

impl SeriesError {
    /// Whether the user's input is at fault (a bad file, folder or task
    /// number) rather than the machine.
    pub fn blames_input(&self) -> bool {
        match self {
            Self::Input { .. } | Self::Folder { .. } | Self::Task(_) => true,
            Self::Io { .. } => false,
            Self::Job(e) => e.blames_input(),
        }
    }

    pub(crate) fn input(
        file: impl Into<PathBuf>,
        place: impl Into<String>,
        reason: impl Into<String>,
    ) -> Self {
        Self::Input {
            file: file.into(),
            place: place.into(),
            reason: reason.into(),
        }
    }

    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}
