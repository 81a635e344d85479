//! The `cushion` command line inside the package: the console script `cushion` and `python -m
//! cushion` call [`main`], which runs the very clap command the `cushion` binary runs
//! (`cushion-cli`), with its messages and exit statuses.

use pyo3::prelude::*;

use crate::errors::guarded;

/// Run the command line with ``argv`` (the program's name first, as in ``sys.argv``) and return
/// its exit status: 0 success, 1 a run not ``ok`` or a failed write, 2 bad input. It prints what
/// the ``cushion`` command prints, on the process's standard output and error.
#[pyfunction]
pub fn main(py: Python<'_>, argv: Vec<String>) -> PyResult<i32> {
    py.detach(|| guarded("the cushion command", || cushion_cli::run_from(argv)))
}
