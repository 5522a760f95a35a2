//! Rig descriptions: a rig is data (a JSON file), compiled once into the form
//! that both the CPU reference and the kernels evaluate (see `crate::compile`).
//!
//! Shipped rigs live in `rigs/` and are built into the binary; a campaign names
//! one by id (`"rig": "duffing_base"`), points at a file (`"rig": "my_rig.json"`)
//! or holds one inline (`"rig": { … }`).

pub mod desc;
pub mod domain;

use std::path::{Path, PathBuf};

pub use desc::RigDesc;

/// The shipped rigs: (id, file text).
pub const SHIPPED: [(&str, &str); 10] = [
    ("tensile4", include_str!("../../rigs/tensile4.json")),
    ("duffing_base", include_str!("../../rigs/duffing_base.json")),
    ("stick_slip", include_str!("../../rigs/stick_slip.json")),
    (
        "friction_sdof",
        include_str!("../../rigs/friction_sdof.json"),
    ),
    (
        "inertial_sdof",
        include_str!("../../rigs/inertial_sdof.json"),
    ),
    ("bearing_2dof", include_str!("../../rigs/bearing_2dof.json")),
    ("quarter_car", include_str!("../../rigs/quarter_car.json")),
    (
        "quarter_car_friction",
        include_str!("../../rigs/quarter_car_friction.json"),
    ),
    ("emps", include_str!("../../rigs/emps.json")),
    (
        "emps_open_loop",
        include_str!("../../rigs/emps_open_loop.json"),
    ),
];

/// A rig file that cannot be used: where, and what was expected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: {path}: expected {expected}, found {found}")]
pub struct RigError {
    /// The rig file (or `<shipped NAME>`, or the campaign holding it inline).
    pub file: String,
    /// JSON path of the offending value (`elements[2].spring.k`).
    pub path: String,
    /// What would have been accepted.
    pub expected: String,
    /// What was there.
    pub found: String,
}

impl RigError {
    /// An error at `path` of `file`.
    pub fn new(
        file: impl Into<String>,
        path: impl Into<String>,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> Self {
        Self {
            file: file.into(),
            path: path.into(),
            expected: expected.into(),
            found: found.into(),
        }
    }
}

/// Where a rig came from, for messages.
#[derive(Debug, Clone, PartialEq)]
pub enum RigSource {
    /// A shipped rig by id.
    Shipped(&'static str),
    /// A file.
    File(PathBuf),
    /// Inline in a campaign file, at a JSON path.
    Inline(PathBuf, String),
}

impl RigSource {
    /// How messages name it.
    pub fn label(&self) -> String {
        match self {
            RigSource::Shipped(id) => format!("rigs/{id}.json"),
            RigSource::File(p) => p.display().to_string(),
            RigSource::Inline(p, path) => format!("{} ({path})", p.display()),
        }
    }
}

/// Parses rig text, naming the JSON path of the first thing wrong.
pub fn parse(text: &str, source: &RigSource) -> Result<RigDesc, RigError> {
    // A byte-order mark, as editors on some systems write it, is not content.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let de = &mut serde_json::Deserializer::from_str(text);
    let desc: RigDesc = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        RigError::new(
            source.label(),
            if path == "." {
                "(top level)".into()
            } else {
                path
            },
            "a valid rig description",
            inner.to_string(),
        )
    })?;
    // Anything after the rig's object (a bad merge's second object, a stray
    // brace) is an error, not something to ignore.
    de.end().map_err(|e| {
        RigError::new(
            source.label(),
            "(top level)",
            "the end of the file after the rig's JSON object",
            format!("more text at line {} column {}", e.line(), e.column()),
        )
    })?;
    domain::check_defaults(&desc).map_err(|(path, expected, v)| {
        RigError::new(source.label(), path, expected, v.to_string())
    })?;
    Ok(desc)
}

/// A shipped rig's description by id.
pub fn shipped(id: &str) -> Option<RigDesc> {
    SHIPPED
        .iter()
        .find(|(i, _)| *i == id)
        .map(|(i, text)| parse(text, &RigSource::Shipped(i)).expect("shipped rigs parse (tested)"))
}

/// Reads the rig named by a campaign's `"rig"` value: a shipped id, a path
/// (relative to `dir`, the campaign's folder) or an inline object.
pub fn resolve(
    value: &serde_json::Value,
    dir: &Path,
    campaign: &Path,
) -> Result<(RigDesc, RigSource), RigError> {
    match value {
        serde_json::Value::String(s) => {
            if let Some((id, text)) = SHIPPED.iter().find(|(i, _)| *i == s.as_str()) {
                let src = RigSource::Shipped(id);
                return Ok((parse(text, &src)?, src));
            }
            let path = dir.join(s);
            let text = crate::base::fsutil::read_description(&path).map_err(|e| {
                let ids: Vec<&str> = SHIPPED.iter().map(|(i, _)| *i).collect();
                RigError::new(
                    campaign.display().to_string(),
                    "rig",
                    format!("a shipped rig ({}) or a readable rig file", ids.join(", ")),
                    format!("{} ({e})", crate::base::text::echo(s)),
                )
            })?;
            let src = RigSource::File(path);
            Ok((parse(&text, &src)?, src))
        }
        serde_json::Value::Object(_) => {
            let src = RigSource::Inline(campaign.to_path_buf(), "rig".into());
            let text = value.to_string();
            Ok((parse(&text, &src)?, src))
        }
        other => Err(RigError::new(
            campaign.display().to_string(),
            "rig",
            "a rig id, a rig file path or a rig object",
            other.to_string(),
        )),
    }
}
