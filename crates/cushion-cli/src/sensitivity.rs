//! `cushion sensitivity FILE [--out DIR] [--threads N] [--resume] [--quiet]`: Sobol indices of
//! every chosen output of a `saltelli` sweep (docs/sensitivity.md). The sweep runs through the
//! same engine and output folder as `cushion sweep`; the analysis is
//! `cushion_sensitivity::study` over the summary's columns. This module also holds the steps the
//! Python binding shares
//! ([`prepare`], [`run_to_folder`], [`run_in_memory`]); only [`run`] prints.

use std::path::{Path, PathBuf};

use cushion_sensitivity::study::{resolve_outputs, write_study, STUDY_FILES};
use cushion_sensitivity::{run_study, SaltelliSample, SensitivityError, Study, StudyOptions};
use cushion_sweep::engine::{compute, thread_pool, Plan};
use cushion_sweep::parquet_io::read_parquet_all;
use cushion_sweep::summary_table::TableSchema;
use cushion_sweep::sweep_file::Mode;
use cushion_sweep::{run_sweep, Hooks, Runs, SweepError, SweepFile, SweepOptions, SweepOutcome};

#[derive(clap::Args, Debug)]
#[command(after_help = "\
The file is a sweep file with [sampling] mode = \"saltelli\" and an optional [sensitivity] table \
(outputs, resamples, conf_level, seed, on_failed); see sweeps/sensitivity.toml and \
docs/sensitivity.md. Writes the sweep's files and sensitivity.parquet, sensitivity.csv, \
sensitivity.svg.\n\n\
Exit status: 0 done; 2 bad input (one message naming the key, the value and what is allowed; \
nothing written) or a folder another command is writing into; 1 anything else, runs that did not \
end ok included (on_failed = \"stop\").")]
pub struct SensitivityArgs {
    /// The sweep file (TOML, [sampling] mode = "saltelli").
    pub file: PathBuf,
    /// Output folder (default: `runs/<sweep name>`).
    #[arg(long, help = "Output folder [default: runs/<sweep name>]")]
    pub out: Option<PathBuf>,
    /// Worker threads [default: all cores]. The results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Continue an interrupted study in the same folder: the runs of the chunks already
    /// written are kept (the sweep file must be unchanged), the rest are run, and the analysis
    /// reads them all.
    #[arg(long)]
    pub resume: bool,
    /// No progress bar and no summary printed.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Why a sensitivity study did not finish.
#[derive(Debug)]
pub enum Failure {
    /// The sweep, or bad input (exit status as `cushion sweep`).
    Sweep(SweepError),
    /// Runs did not end `ok` and `on_failed = "stop"`, or nothing was left to analyse.
    FailedRuns(String),
}

impl Failure {
    pub fn exit_code(&self) -> i32 {
        match self {
            Failure::Sweep(e) => e.exit_code(),
            Failure::FailedRuns(_) => 1,
        }
    }
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::Sweep(e) => write!(f, "{e}"),
            Failure::FailedRuns(m) => write!(f, "{m}"),
        }
    }
}

impl From<SweepError> for Failure {
    fn from(e: SweepError) -> Self {
        Failure::Sweep(e)
    }
}

impl From<SensitivityError> for Failure {
    fn from(e: SensitivityError) -> Self {
        match e {
            SensitivityError::Config { .. } => Failure::Sweep(SweepError::Config(e.to_string())),
            SensitivityError::FailedRuns(m) => Failure::FailedRuns(m),
            SensitivityError::Io(m) => Failure::Sweep(SweepError::Io(m)),
            SensitivityError::Output { .. } => Failure::Sweep(SweepError::Internal(e.to_string())),
        }
    }
}

/// A study checked before any run: the sweep, the options, the outputs and the sample.
pub struct Prepared {
    pub sweep: SweepFile,
    pub options: StudyOptions,
    /// The input columns (the axis keys), in the sample's order.
    pub inputs: Vec<String>,
    pub outputs: Vec<String>,
    pub sample: SaltelliSample,
}

/// Check a sweep for a study: its mode is saltelli, its `[sensitivity]` table is valid, the
/// outputs (`outputs` overrides the table's) are numeric summary fields.
pub fn prepare(sweep: SweepFile, outputs: Option<Vec<String>>) -> Result<Prepared, SweepError> {
    let where_ = sweep.path.display().to_string();
    let bad = |e: SensitivityError| SweepError::Config(format!("{where_}: {e}"));
    if sweep.mode != Mode::Saltelli {
        return Err(SweepError::Config(format!(
            "{where_}: [sampling] mode = \"{}\": a sensitivity study needs mode = \"saltelli\" (with samples = N, a power of two)",
            sweep.mode.name()
        )));
    }
    let mut options = StudyOptions::from_table(sweep.sensitivity.as_ref()).map_err(bad)?;
    if let Some(o) = outputs {
        options.outputs = Some(o);
    }
    let inputs: Vec<String> = sweep.axes.iter().map(|a| a.key.clone()).collect();
    let schema = TableSchema::new(&sweep.axes).arrow;
    let outputs = resolve_outputs(&schema, &inputs, options.outputs.as_deref()).map_err(bad)?;
    let sample = SaltelliSample::new(
        inputs.len(),
        sweep.samples as usize,
        sweep.second_order,
        sweep.seed,
    )
    .map_err(bad)?;
    Ok(Prepared {
        sweep,
        options,
        inputs,
        outputs,
        sample,
    })
}

/// The analysis of a finished sample's summary (`batches`), on `threads` workers.
macro_rules! analyse {
    ($prep:expr, $batches:expr, $threads:expr) => {{
        let (pool, _) = thread_pool($threads)?;
        let p = &$prep;
        pool.install(|| run_study(&$batches, &p.inputs, &p.sample, &p.outputs, &p.options))?
    }};
}

/// Run the sample into a folder (as `cushion sweep --out`), analyse it and write the study's
/// files there. The warnings of both come back with the outcome.
pub fn run_to_folder(
    prep: Prepared,
    opts: &SweepOptions,
    hooks: &Hooks,
) -> Result<(SweepOutcome, Study, Vec<String>), Failure> {
    let threads = opts.threads;
    let sweep = prep.sweep.clone();
    let outcome = run_sweep(sweep, opts, hooks)?;
    let dir = &outcome.out_dir;
    // A previous study's files must not outlive the runs they described.
    remove_study_files(dir)?;
    let batches = read_parquet_all(&dir.join("summary.parquet"))?;
    let study = analyse!(prep, batches, threads);
    let warnings = write_study(dir, &study)?;
    Ok((outcome, study, warnings))
}

fn remove_study_files(dir: &Path) -> Result<(), SweepError> {
    for f in STUDY_FILES {
        let p = dir.join(f);
        if p.exists() {
            std::fs::remove_file(&p)
                .map_err(|e| SweepError::Io(format!("{}: {e}", p.display())))?;
        }
    }
    Ok(())
}

/// Run the sample in memory and analyse it (nothing written).
pub fn run_in_memory(
    prep: Prepared,
    threads: Option<usize>,
    hooks: &Hooks,
) -> Result<Study, Failure> {
    let plan = Plan::new(prep.sweep.clone())?;
    let n = plan.n_runs();
    let batches = compute(&plan, Runs::all(n), threads, hooks)?;
    Ok(analyse!(prep, batches, threads))
}

pub fn run(args: SensitivityArgs) -> i32 {
    match run_inner(&args) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("cushion sensitivity: {e}");
            e.exit_code()
        }
    }
}

fn run_inner(args: &SensitivityArgs) -> Result<(), Failure> {
    if args.threads == Some(0) {
        return Err(SweepError::Config("--threads must be at least 1".into()).into());
    }
    let sweep = SweepFile::from_file(&args.file).map_err(SweepError::Config)?;
    let prep = prepare(sweep, None)?;
    let opts = SweepOptions {
        out: args.out.clone(),
        threads: args.threads,
        resume: args.resume,
        shard: None,
        git_commit: super::git_commit(),
    };
    let bar = crate::progress::RunsBar::new(args.quiet, true);
    let progress = |done: u64, total: u64| bar.update(done, total);
    let hooks = Hooks {
        progress: Some(&progress),
        cancel: Some(&super::INTERRUPTED),
        chunk_written: Some(&super::chunk_written),
    };
    let result = run_to_folder(prep, &opts, &hooks);
    bar.finish();
    let (o, study, warnings) = result?;
    for w in o.warnings.iter().chain(&warnings) {
        eprintln!("cushion sensitivity: warning: {w}");
    }
    if !args.quiet {
        print!("{}", human_summary(&study));
        println!(
            "{}: {} runs ({} not ok), {} outputs analysed in {:.2} s; {:.2} s in all",
            o.out_dir.display(),
            o.runs_total,
            o.runs_failed,
            study.outputs.len(),
            study.analysis_seconds,
            o.wall_seconds + study.analysis_seconds
        );
    }
    Ok(())
}

/// Per output, the inputs by total index (with S1), the largest first; dropped base points.
fn human_summary(study: &Study) -> String {
    use cushion_sensitivity::{Finding, Sensitivity};
    let mut s = String::new();
    if study.dropped_base_points() > 0 {
        s.push_str(&format!(
            "{} runs did not end ok: dropped {} of {} base points (on_failed = \"drop_base_point\")\n",
            study.failed_runs,
            study.dropped_base_points(),
            study.base_points
        ));
    }
    for (name, f) in study.outputs.iter().zip(&study.findings) {
        match f {
            Finding::NotFinite { runs } => s.push_str(&format!(
                "{name}: not finite on {runs} runs, not analysed\n"
            )),
            Finding::Sensitivity(Sensitivity::Constant { value }) => {
                s.push_str(&format!("{name}: constant ({value})\n"))
            }
            Finding::Sensitivity(Sensitivity::Indices(ix)) => {
                let mut order: Vec<usize> = (0..study.inputs.len()).collect();
                order.sort_by(|&a, &b| ix.st[b].value.total_cmp(&ix.st[a].value));
                let parts: Vec<String> = order
                    .iter()
                    .map(|&j| {
                        format!(
                            "{} ST {:.2} S1 {:.2}",
                            study.inputs[j], ix.st[j].value, ix.s1[j].value
                        )
                    })
                    .collect();
                s.push_str(&format!("{name}: {}\n", parts.join("; ")));
            }
        }
    }
    s
}
