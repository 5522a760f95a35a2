//! `rigfit._rigfit.Record`: a record's columns held as arrays (a DataFrame
//! given to `Campaign.set_data`, a grid `rigfit.simulate` runs on), lent to a
//! campaign as the library's in-memory record, never written out as text;
//! and the records a campaign is built from, as Python holds them.

use std::path::PathBuf;
use std::sync::Arc;

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyTuple};

use crate::errors::{self, Kind};
use rigfit::record::Record;
use rigfit::record::lent::{Lent, Loan};

/// Named columns of one length, as a campaign reads a record's channels.
#[pyclass(module = "rigfit._rigfit", name = "Record", frozen)]
pub struct PyRecord {
    pub inner: Arc<Record>,
}

#[pymethods]
impl PyRecord {
    /// The column names, in order.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.inner.channels.iter().map(|c| c.name.clone()).collect()
    }

    /// Rebuilt from its names and columns when unpickled.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let make = py.import("rigfit._rigfit")?.getattr("record_of")?;
        let columns: Vec<Bound<'py, PyArray1<f64>>> = self
            .inner
            .channels
            .iter()
            .map(|c| PyArray1::from_slice(py, &c.values))
            .collect();
        (make, (self.names(), columns)).into_pyobject(py)
    }
}

/// A record of named float64 columns of one length, kept bit for bit.
#[pyfunction]
pub fn record_of(
    names: Vec<String>,
    columns: Vec<PyReadonlyArray1<'_, f64>>,
) -> PyResult<PyRecord> {
    let columns: Vec<Vec<f64>> = columns.iter().map(|c| c.as_array().to_vec()).collect();
    rigfit::record::lent::record_of(names, columns)
        .map(|r| PyRecord { inner: Arc::new(r) })
        .ok_or_else(|| {
            errors::raise(
                Kind::Data,
                "expected one name per column and columns of one length",
            )
        })
}

/// A record as a campaign holds it: a file's bytes (read once, when it was
/// first built) or columns in memory.
#[derive(FromPyObject)]
pub enum Source {
    Record(Py<PyRecord>),
    Bytes(Py<PyBytes>),
}

impl Source {
    pub fn clone_ref(&self, py: Python<'_>) -> Source {
        match self {
            Source::Record(r) => Source::Record(r.clone_ref(py)),
            Source::Bytes(b) => Source::Bytes(b.clone_ref(py)),
        }
    }

    /// The library's loan of it (a file's bytes copied, columns shared).
    pub fn loan(&self, py: Python<'_>) -> Loan {
        match self {
            Source::Record(r) => Loan::Record(r.get().inner.clone()),
            Source::Bytes(b) => Loan::Bytes(Arc::from(b.as_bytes(py))),
        }
    }
}

impl<'py> IntoPyObject<'py> for Source {
    type Target = PyAny;
    type Output = Bound<'py, PyAny>;
    type Error = std::convert::Infallible;

    fn into_pyobject(self, py: Python<'py>) -> Result<Self::Output, Self::Error> {
        Ok(match self {
            Source::Record(r) => r.into_bound(py).into_any(),
            Source::Bytes(b) => b.into_bound(py).into_any(),
        })
    }
}

/// Records by path, as a campaign is built from them.
pub type Records = Vec<(PathBuf, Source)>;

/// `records` lent by path.
pub fn lent(py: Python<'_>, records: &[(PathBuf, Source)]) -> Lent {
    let mut lent = Lent::none();
    for (path, source) in records {
        lent.lend(path.clone(), source.loan(py));
    }
    lent
}
