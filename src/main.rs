//! The `cushion` command: the command line of `cushion-cli`, whose exit status it returns.

/// Test hook of the end-to-end tests: end the process abruptly (exit status 99, no cleanup, as
/// a kill would) once a sweep has written this many chunks. The binary owns its process, so the
/// hook lives here, not in the library the Python extension also runs.
const ABORT_ENV: &str = "CUSHION_SWEEP_ABORT_AFTER_CHUNKS";

fn abort_after_chunks(n: usize) {
    let limit: Option<usize> = std::env::var(ABORT_ENV).ok().and_then(|v| v.parse().ok());
    if limit == Some(n) {
        eprintln!("cushion sweep: {ABORT_ENV}={n}: stopping abruptly (test hook)");
        std::process::exit(99);
    }
}

fn main() {
    // Ctrl-C asks a sweep, design or sensitivity run to stop at its next chunk or round, so
    // nothing is left half-written; a second one ends the process at once.
    let _ = ctrlc::set_handler(|| {
        if cushion_cli::interrupt() {
            std::process::exit(130);
        }
    });
    if std::env::var_os(ABORT_ENV).is_some() {
        cushion_cli::on_chunk_written(abort_after_chunks);
    }
    std::process::exit(cushion_cli::run_from(std::env::args_os()));
}
