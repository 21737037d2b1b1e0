//! The extension module `hopsim._hopsim` of the Python package `hopsim` (docs/python.md):
//! thin wrappers over the Rust crates (scenes, the run loop, the run summary, the Lemke
//! solver, MCAP recordings, sweeps). The pure-Python package `hopsim` re-exports it with
//! trajectories, tables and the Dask front end of sweeps.

mod batch;
mod errors;
mod lcp;
mod mcap;
mod names;
mod optimize;
mod recording;
mod scene;
mod signals;
mod simulation;
mod sweep;

use pyo3::prelude::*;

#[pymodule]
fn _hopsim(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<simulation::PySimulation>()?;
    m.add_class::<simulation::PyActuation>()?;
    m.add_class::<optimize::PySearch>()?;
    m.add_class::<batch::PyBatch>()?;
    for class in errors::Class::ALL {
        m.add(class.name(), errors::class(py, class)?)?;
    }
    // Whether the wheel was built with the cargo feature `test-hooks` (errors::test_hook).
    m.add("_TEST_HOOKS", cfg!(feature = "test-hooks"))?;
    m.add_function(wrap_pyfunction!(lcp::lcp_solve, m)?)?;
    m.add_function(wrap_pyfunction!(lcp::lcp_read_dat, m)?)?;
    m.add_function(wrap_pyfunction!(mcap::read_mcap, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_runs, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_csv, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_figure_names, m)?)?;
    Ok(())
}
