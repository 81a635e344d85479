//! The design search's tests: the worst-case search on functions with known maxima, the
//! refinement on known regions, the design file, the verification, as one test binary.

mod common;

mod design_file;
mod engine_runs;
mod refine;
mod verify;
mod worst_case;
