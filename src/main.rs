//! The `cushion` command: the command line of `cushion-cli`, whose exit status it returns.

fn main() {
    std::process::exit(cushion_cli::run_from(std::env::args_os()));
}
