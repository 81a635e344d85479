//! The output sinks of one run, shared by `cushion simulate` and a sweep's recorded runs:
//! trajectories as CSV and MCAP (and reading MCAP back), and the SVG figures.

pub mod figure;
pub mod mcap_read;
pub mod quantities;
pub mod trajectory_csv;
pub mod trajectory_mcap;
