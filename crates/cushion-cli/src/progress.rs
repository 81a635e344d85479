//! The progress bar the long subcommands (`sweep`, `design`, `sensitivity`) draw on standard
//! error when it is a terminal.

/// A bar of runs done out of the total, with their rate; `eta`: also the time left (not for a
/// design question, whose total grows with each round of the search).
fn runs_bar(eta: bool) -> indicatif::ProgressBar {
    let template = if eta {
        "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} runs  {rate}  ETA {eta}"
    } else {
        "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} runs  {rate}"
    };
    let pb = indicatif::ProgressBar::new(0);
    pb.set_style(
        indicatif::ProgressStyle::with_template(template)
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
            .with_key(
                "rate",
                |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                    let _ = write!(w, "{:.0} runs/s", s.per_sec());
                },
            ),
    );
    pb
}

/// The bar of a long subcommand, drawn only when standard error is a terminal and the command
/// is not `--quiet`.
pub(crate) struct RunsBar(Option<indicatif::ProgressBar>);

impl RunsBar {
    pub(crate) fn new(quiet: bool, eta: bool) -> RunsBar {
        use std::io::IsTerminal;
        RunsBar((!quiet && std::io::stderr().is_terminal()).then(|| runs_bar(eta)))
    }

    /// `done` of `total` runs; a new total (a resumed sweep's first report, a design question's
    /// next round) also restarts the rate and the time left.
    pub(crate) fn update(&self, done: u64, total: u64) {
        if let Some(pb) = &self.0 {
            if pb.length() != Some(total) {
                pb.set_length(total);
                pb.set_position(done);
                pb.reset_eta();
            } else {
                pb.set_position(done);
            }
        }
    }

    /// Clear the bar, before the command prints its answer or an error.
    pub(crate) fn finish(&self) {
        if let Some(pb) = &self.0 {
            pb.finish_and_clear();
        }
    }
}
