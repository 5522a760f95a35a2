//! Library errors as the package's exceptions (`rigfit.errors`): every message
//! is the library's one line with its causes after it, and a panic becomes
//! `rigfit.Error`, never a bare `PanicException`.

use std::panic::{AssertUnwindSafe, catch_unwind};

use pyo3::prelude::*;
use pyo3::types::PyType;

/// Which exception of `rigfit.errors` an error becomes.
#[derive(Debug, Clone, Copy)]
pub enum Kind {
    /// `rigfit.Error`: a job that failed after its input was accepted.
    Error,
    /// `rigfit.CampaignError` (a ValueError): a campaign or a setting refused.
    Campaign,
    /// `rigfit.DataError` (a ValueError): a record refused.
    Data,
    /// `rigfit.DeviceError` (a RuntimeError): the GPU failed or is missing.
    Device,
}

impl Kind {
    fn class_name(self) -> &'static str {
        match self {
            Kind::Error => "Error",
            Kind::Campaign => "CampaignError",
            Kind::Data => "DataError",
            Kind::Device => "DeviceError",
        }
    }
}

/// The exception `kind` with `message`.
pub fn raise(kind: Kind, message: impl Into<String>) -> PyErr {
    let message = message.into();
    Python::with_gil(|py| {
        let class = py
            .import("rigfit.errors")
            .and_then(|m| m.getattr(kind.class_name()))
            .and_then(|c| c.downcast_into::<PyType>().map_err(PyErr::from));
        match class {
            Ok(class) => PyErr::from_type(class, message),
            Err(e) => e,
        }
    })
}

/// An error and its causes on one line, as the CLI prints them.
pub fn chain(e: &(dyn std::error::Error + 'static)) -> String {
    let mut s = e.to_string();
    let mut source = e.source();
    while let Some(cause) = source {
        let c = cause.to_string();
        if !s.ends_with(&c) {
            s.push_str(": ");
            s.push_str(&c);
        }
        source = cause.source();
    }
    s
}

/// A campaign refusal: a refused record is a `DataError`, the rest a
/// `CampaignError`.
pub fn campaign(e: &rigfit::campaign::CampaignError) -> PyErr {
    match e {
        rigfit::campaign::CampaignError::Data { .. } => raise(Kind::Data, chain(e)),
        _ => raise(Kind::Campaign, chain(e)),
    }
}

/// An evaluation error: a device failure is a `DeviceError`.
pub fn eval(e: &rigfit::eval::EvalError) -> PyErr {
    match e {
        rigfit::eval::EvalError::Device(_) => raise(Kind::Device, chain(e)),
        _ => raise(Kind::Error, chain(e)),
    }
}

/// The text of a panic's payload.
pub fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(no message)".into())
}

/// Runs `f`, turning a panic into `rigfit.Error` naming it as a bug.
pub fn guard<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => Err(raise(
            Kind::Error,
            format!(
                "internal error (a bug in rigfit, please report it): {}",
                panic_text(&*payload)
            ),
        )),
    }
}
