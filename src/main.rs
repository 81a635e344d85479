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

/// Ctrl-C (SIGINT) asks a sweep, design or sensitivity run to stop at its next chunk or round,
/// so nothing is left half-written; a second one ends the process at once.
#[cfg(unix)]
extern "C" fn on_interrupt(_: libc::c_int) {
    if cushion_cli::interrupt() {
        // SAFETY: `_exit` is async-signal-safe (unlike `exit`, it runs no destructors).
        unsafe { libc::_exit(130) };
    }
}

fn main() {
    #[cfg(unix)]
    // SAFETY: the handler only swaps an atomic and calls `_exit`, both async-signal-safe.
    unsafe {
        libc::signal(
            libc::SIGINT,
            on_interrupt as extern "C" fn(libc::c_int) as libc::sighandler_t,
        );
    }
    if std::env::var_os(ABORT_ENV).is_some() {
        cushion_cli::on_chunk_written(abort_after_chunks);
    }
    std::process::exit(cushion_cli::run_from(std::env::args_os()));
}
