//! `hopsim.lcp`: the Lemke solver of hopsim-lcp on numpy arrays.

use hopsim_lcp::{dat::read_dat, solve_lcp};
use nalgebra::{DMatrix, DVector};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// Solves `w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0` by Lemke's method (docs/lcp.md), the GIL
/// released. `m` is a C- or Fortran-ordered float64 `(n, n)` array, `q` float64 `(n,)`.
/// Returns `status`, `z`, `w`, `pivots`, `method` and `certificate` (`complementarity`,
/// `most_negative`, `residual`, `tolerance`, `holds`). Raises `ValueError` for a
/// non-square `M`, a `q` of another length, or a non-finite entry.
#[pyfunction]
pub fn lcp_solve<'py>(
    py: Python<'py>,
    m: PyReadonlyArray2<'py, f64>,
    q: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let m = m.as_array();
    let q = q.as_array();
    let (rows, cols) = m.dim();
    let m = DMatrix::from_fn(rows, cols, |i, j| m[[i, j]]);
    let q = DVector::from_iterator(q.len(), q.iter().copied());
    let solution = py
        .detach(|| solve_lcp(&m, &q))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let c = &solution.certificate;
    let certificate = PyDict::new(py);
    certificate.set_item("complementarity", c.complementarity)?;
    certificate.set_item("most_negative", c.most_negative)?;
    certificate.set_item("residual", c.residual)?;
    certificate.set_item("tolerance", c.tolerance)?;
    certificate.set_item("holds", c.holds())?;
    let d = PyDict::new(py);
    d.set_item("status", solution.status.as_str())?;
    d.set_item("z", PyArray1::from_slice(py, solution.z.as_slice()))?;
    d.set_item("w", PyArray1::from_slice(py, solution.w.as_slice()))?;
    d.set_item("pivots", solution.pivots)?;
    d.set_item("method", solution.method.as_str())?;
    d.set_item("certificate", certificate)?;
    Ok(d)
}

/// `(M, q, comment)` of an LCP file.
type DatProblem<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>, String);

/// Reads a Siconos `.dat` LCP file: `(M, q, comment)`. Raises `ValueError` when the file
/// cannot be read or is malformed.
#[pyfunction]
pub fn lcp_read_dat<'py>(py: Python<'py>, path: PathBuf) -> PyResult<DatProblem<'py>> {
    let problem = read_dat(&path).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let n = problem.m.nrows();
    let rows: Vec<f64> = (0..n)
        .flat_map(|i| problem.m.row(i).iter().copied().collect::<Vec<_>>())
        .collect();
    let m = PyArray1::from_vec(py, rows).reshape([n, problem.m.ncols()])?;
    Ok((
        m,
        PyArray1::from_slice(py, problem.q.as_slice()),
        problem.comment,
    ))
}
