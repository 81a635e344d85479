//! End-to-end tests: the `cushion` command run as a user runs it, with the real model. One test
//! binary for all of them (one compile and link of the engine); `common` holds what they share.

mod common;

mod command;
mod design;
mod sensitivity;
mod simulate;
mod simulate_bad_input;
mod simulate_scenes;
mod sweep;
