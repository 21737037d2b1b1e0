//! `hopsim.lcp`: the Lemke solver of hopsim-lcp on numpy arrays.

use crate::errors::{guard, internal_error, test_hook};
use crate::signals::wait_for;
use hopsim_lcp::{dat::read_dat, solve_lcp, LcpInputError, LcpSolution};
use hopsim_sim::panic_message;
use nalgebra::{DMatrix, DVector};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::mpsc;

/// Problems up to this size are solved on the calling thread: they take milliseconds at
/// most, less than starting a thread costs them in relative terms.
const SOLVE_IN_PLACE_MAX_N: usize = 64;

/// What the solve of a binding gives back: its answer, or a panic's message.
type Solved = Result<Result<LcpSolution, LcpInputError>, String>;

/// Solves on the calling thread, the GIL released, for small problems; larger ones on a
/// thread of their own while the calling thread runs Python's signal handlers
/// ([`wait_for`]). On `KeyboardInterrupt` (or any exception a handler raises) the solve
/// is abandoned: its thread finishes in the background and its answer is dropped.
fn solve_interruptibly(py: Python<'_>, m: DMatrix<f64>, q: DVector<f64>) -> PyResult<Solved> {
    let n = q.len();
    let solve = move || {
        std::panic::catch_unwind(|| {
            test_hook("lcp.solve");
            solve_lcp(&m, &q)
        })
        .map_err(|payload| panic_message(payload.as_ref()))
    };
    if n <= SOLVE_IN_PLACE_MAX_N {
        return Ok(py.detach(solve));
    }
    let (send, mut receive) = mpsc::sync_channel(1);
    std::thread::Builder::new()
        .name("hopsim-lcp".into())
        .spawn(move || {
            // The caller may have gone (interrupted): then nobody wants the answer.
            let _ = send.send(solve());
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start the solver's thread: {e}")))?;
    Ok(wait_for(py, &mut receive)?
        .unwrap_or_else(|| Err("the solver's thread ended without an answer".into())))
}

/// Solves `w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0` by Lemke's method (docs/lcp.md), the GIL
/// released; Ctrl-C during the solve of a large problem raises `KeyboardInterrupt` within
/// about 50 ms. `m` is a C- or Fortran-ordered float64 `(n, n)` array, `q` float64 `(n,)`.
/// Returns `status`, `z`, `w`, `pivots`, `method` and `certificate` (`complementarity`,
/// `most_negative`, `residual`, `tolerance`, `holds`). Raises `ValueError` for a
/// non-square `M`, a `q` of another length, or a non-finite entry.
#[pyfunction]
pub fn lcp_solve<'py>(
    py: Python<'py>,
    m: PyReadonlyArray2<'py, f64>,
    q: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyDict>> {
    const WHAT: &str = "lcp.solve";
    guard(py, WHAT, || {
        let m = m.as_array();
        let q = q.as_array();
        let (rows, cols) = m.dim();
        let m = DMatrix::from_fn(rows, cols, |i, j| m[[i, j]]);
        let q = DVector::from_iterator(q.len(), q.iter().copied());
        let solution = solve_interruptibly(py, m, q)?
            .map_err(|message| internal_error(py, WHAT, None, &message))?
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        solution_dict(py, &solution)
    })
}

/// The dict of [`lcp_solve`].
fn solution_dict<'py>(py: Python<'py>, solution: &LcpSolution) -> PyResult<Bound<'py, PyDict>> {
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

/// Reads a Siconos `.dat` LCP file, the GIL released: `(M, q, comment)`. Raises `ValueError` when the file
/// cannot be read or is malformed.
#[pyfunction]
pub fn lcp_read_dat<'py>(py: Python<'py>, path: PathBuf) -> PyResult<DatProblem<'py>> {
    let problem = guard(py, "lcp.read_dat", || {
        py.detach(|| read_dat(&path))
            .map_err(|e| PyValueError::new_err(e.to_string()))
    })?;
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
