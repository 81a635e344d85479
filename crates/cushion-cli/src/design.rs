//! `cushion design FILE [--out DIR] [--threads N] [--quiet]`: answer a design question (see
//! `cushion_design::design_file` for the file, `cushion_design::output` for what lands on
//! disk). This command draws the progress bar, prints the answer a person reads and finds the
//! git commit for the provenance; the library does none of that.

use std::path::PathBuf;

use cushion_design::{answer_json, run_design, DesignFile, DesignOptions};
use cushion_sweep::{Hooks, SweepError};
use serde_json::Value as Json;

#[derive(clap::Args, Debug)]
#[command(after_help = "\
Exit status: 0 answered (feasible or not: the answer says); 2 bad input (one message naming the \
key, the value and what is allowed; nothing written) or a folder another command is writing \
into; 1 anything else.")]
pub struct DesignArgs {
    /// The design file (TOML; see sweeps/design-question.toml).
    pub file: PathBuf,
    /// Output folder (default: `runs/<name>`).
    #[arg(long, help = "Output folder [default: runs/<design name>]")]
    pub out: Option<PathBuf>,
    /// Worker threads [default: all cores]. The answer does not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress bar and no answer printed.
    #[arg(long, short)]
    pub quiet: bool,
}

pub fn run(args: DesignArgs) -> i32 {
    match run_inner(&args) {
        Ok(()) => 0,
        Err(SweepError::Cancelled) => {
            eprintln!("cushion design: stopped (interrupted); nothing written");
            SweepError::Cancelled.exit_code()
        }
        Err(e) => {
            eprintln!("cushion design: {e}");
            e.exit_code()
        }
    }
}

fn run_inner(args: &DesignArgs) -> Result<(), SweepError> {
    if args.threads == Some(0) {
        return Err(SweepError::Config("--threads must be at least 1".into()));
    }
    let file = DesignFile::from_file(&args.file).map_err(SweepError::Config)?;
    let opts = DesignOptions {
        out: args.out.clone(),
        threads: args.threads,
        git_commit: super::git_commit(),
    };
    let bar = crate::progress::RunsBar::new(args.quiet, false);
    let progress = |done: u64, total: u64| bar.update(done, total);
    let hooks = Hooks {
        progress: Some(&progress),
        cancel: Some(&super::INTERRUPTED),
        chunk_written: None,
    };
    let result = run_design(file, &opts, &hooks);
    bar.finish();
    let o = result?;
    for w in &o.warnings {
        eprintln!("cushion design: warning: {w}");
    }
    if !args.quiet {
        print!(
            "{}",
            human_answer(&answer_json(&o.result), &o.out_dir, o.wall_seconds)
        );
    }
    Ok(())
}

/// A JSON number or string as a person reads it.
fn show(v: &Json) -> String {
    match v {
        Json::Number(n) => n
            .as_f64()
            .map(|x| {
                format!("{x:.4}")
                    .trim_end_matches('0')
                    .trim_end_matches('.')
                    .to_string()
            })
            .filter(|s| !s.is_empty() && s != "-0" && s != "0")
            .unwrap_or_else(|| n.to_string()),
        Json::String(s) => s.clone(),
        Json::Null => "-".into(),
        other => other.to_string(),
    }
}

fn show_point(p: &Json) -> String {
    p.as_object()
        .map(|m| {
            m.iter()
                .map(|(k, v)| format!("{k} = {}", show(v)))
                .collect::<Vec<_>>()
                .join(", ")
        })
        .unwrap_or_default()
}

fn limit_text(w: &Json) -> String {
    let l = &w["limit"];
    let what = if l["abs"] == Json::Bool(true) {
        format!("|{}|", w["metric"].as_str().unwrap_or("?"))
    } else {
        w["metric"].as_str().unwrap_or("?").to_string()
    };
    let mut parts = Vec::new();
    if !l["min"].is_null() {
        parts.push(format!(">= {}", show(&l["min"])));
    }
    if !l["max"].is_null() {
        parts.push(format!("<= {}", show(&l["max"])));
    }
    format!("{what} {}", parts.join(", "))
}

fn worst_lines(out: &mut String, list: &Json) {
    for w in list.as_array().into_iter().flatten() {
        let value = if w["failed"] == Json::Bool(true) {
            "a failed run".to_string()
        } else {
            show(&w["value"])
        };
        out.push_str(&format!(
            "  {} ({}): worst {value} at {}\n",
            w["name"].as_str().unwrap_or("?"),
            limit_text(w),
            show_point(&w["at"]),
        ));
    }
}

/// The short answer: the design, its worst cases with their witnesses, the margin, verified or
/// not, runs and time.
fn human_answer(a: &Json, out_dir: &std::path::Path, wall: f64) -> String {
    let mut s = String::new();
    let feasible = a["feasible"] == Json::Bool(true);
    s.push_str(&format!(
        "{} design: {}\n",
        if feasible {
            "chosen"
        } else {
            "no feasible design found; closest"
        },
        show_point(&a["design"])
    ));
    worst_lines(&mut s, &a["worst"]);
    let margin = a["margin"].as_f64();
    s.push_str(&format!(
        "  margin {} ({})\n",
        margin.map_or("-inf (a failed run)".into(), |m| format!(
            "{:.2} %",
            100.0 * m
        )),
        if feasible {
            "every limit met"
        } else {
            "a limit missed"
        }
    ));
    if let Some(o) = a["objective"].as_object() {
        s.push_str(&format!(
            "  objective: {} {} = {}\n",
            o["sense"].as_str().unwrap_or("?"),
            o["metric"].as_str().unwrap_or("?"),
            show(&o["value"])
        ));
    }
    let v = &a["verification"];
    let n = v["points_per_range"].as_u64().unwrap_or(0);
    s.push_str(&format!(
        "verified on a grid of {n} per for_all range ({} runs): {}\n",
        v["runs"],
        if v["all_met"] == Json::Bool(true) {
            "every run meets every limit".to_string()
        } else {
            format!(
                "{} runs miss a limit ({} failed)",
                v["violations"], v["failed"]
            )
        }
    ));
    worst_lines(&mut s, &v["worst"]);
    s.push_str(&format!(
        "{}: {} design points ({} feasible), {} runs ({} search + {} verification) in {wall:.2} s\n",
        out_dir.display(),
        a["design_points"],
        a["feasible_points"],
        a["runs"]["total"],
        a["runs"]["search"],
        a["runs"]["verify"],
    ));
    s
}
