//! The progress bar the long subcommands (`sweep`, `design`, `sensitivity`) draw on standard
//! error when it is a terminal.

/// A bar of runs done out of the total, with their rate; `eta`: also the time left (not for a
/// design question, whose total grows with each round of the search).
pub(crate) fn runs_bar(eta: bool) -> indicatif::ProgressBar {
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
