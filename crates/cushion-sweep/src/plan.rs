//! What to run: the sweep file, its sampling, which runs, and the columns of a run's row.

pub mod runs;
pub mod sampling;
pub mod summary_table;
pub mod sweep_file;
