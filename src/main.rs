//! The `cushion` command: thin clap subcommands over `cushion-model` and `cushion-sweep`.
//! Exit status: 0 success, 2 bad input (a message naming the key, value and what is allowed),
//! 1 anything else (I/O; for `simulate`, also a run that ended with a status other than `ok`,
//! whose summary is still printed).

mod cli;

use clap::Parser;

fn main() {
    let args = cli::Cli::parse();
    std::process::exit(cli::run(args));
}
