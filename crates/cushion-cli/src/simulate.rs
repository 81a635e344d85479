//! `cushion simulate [SCENE.toml] [--set KEY=VALUE]... [--json] [--csv FILE] [--mcap FILE]
//! [--plot FILE.svg]`: run one scene, print its summary, write its trajectories.
//!
//! Exit status: 0 the run ended `ok`; 1 the run ended with another status (the summary, with
//! its `status` and `message`, is still printed, and the requested trajectory files hold the
//! run up to where it stopped) or an output file could not be written; 2 bad input (unreadable
//! scene file, unknown key, wrong type, invalid value or combination, `--set` without `=`, an
//! output path in a missing directory): one message on standard error and no output file.

use std::path::{Path, PathBuf};

use cushion_model::{simulate, RunOptions, RunStatus, Scene, Summary};
use cushion_sweep::{figure, trajectory_csv, trajectory_mcap};

#[derive(clap::Args, Debug)]
#[command(after_help = "\
Exit status: 0 run ended ok; 1 run ended with another status (summary still printed, status and \
message in it) or an output could not be written; 2 bad input (one message naming the key, the \
value and what is allowed; no output file written).")]
pub struct SimulateArgs {
    /// Scene file (TOML; its keys are listed in docs/scene-keys.md). Without it the default scene runs.
    #[arg(value_name = "SCENE.toml")]
    pub scene: Option<PathBuf>,

    /// Set one key, after the scene file; repeatable, applied in order
    /// (e.g. `--set module=bistable --set robot.dead_time=0.01`).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,

    /// Print the summary as one JSON object (the fields of docs/model.md) and nothing else on stdout.
    #[arg(long)]
    pub json: bool,

    /// Write the trajectories as CSV (columns t,x_r,v_r,x_t,v_t,x_p,v_p,s,p1,F_c,F_r; SI units).
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,

    /// Write the trajectories and the event log as MCAP (topics /state and /events) for Foxglove.
    #[arg(long, value_name = "FILE")]
    pub mcap: Option<PathBuf>,

    /// Draw the paper's figure 3 for this run (positions, velocities, gas pressure, forces) as SVG.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,

    /// Recorded trajectories hold every solver step and event, plus uniform samples every
    /// SECONDS of simulated time (0: steps and events only). Default: t_end / 2000.
    #[arg(long, value_name = "SECONDS")]
    pub sample_interval: Option<f64>,
}

/// Bad input (exit 2) or a failed write (exit 1), with its one message.
enum Failure {
    Input(String),
    Output(String),
}

pub fn run(args: SimulateArgs) -> i32 {
    match run_inner(&args) {
        Ok(code) => code,
        Err(Failure::Input(msg)) => {
            eprintln!("cushion simulate: {msg}");
            2
        }
        Err(Failure::Output(msg)) => {
            eprintln!("cushion simulate: {msg}");
            1
        }
    }
}

fn run_inner(args: &SimulateArgs) -> Result<i32, Failure> {
    let scene = build_scene(args)?;
    scene
        .validate()
        .map_err(|e| Failure::Input(e.to_string()))?;
    let outputs = outputs(args)?;
    let recording = RunOptions::recording(&scene, args.sample_interval).map_err(|e| {
        let dt = args.sample_interval.unwrap_or_default();
        Failure::Input(format!("--sample-interval = {dt}: {e}"))
    })?;
    let opts = RunOptions {
        trajectory: !outputs.is_empty(),
        ..recording
    };
    let result = simulate(&scene, &opts);
    let summary = &result.summary;
    if summary.status == RunStatus::Invalid {
        // validate() accepted the scene, but the model found it unusable: still bad input.
        return Err(Failure::Input(summary.message.clone()));
    }

    let mut written: Vec<&Path> = Vec::new();
    if let Some(traj) = &result.trajectory {
        for (kind, path) in &outputs {
            let res = match kind {
                Output::Csv => trajectory_csv::write_csv(path, traj),
                Output::Mcap => trajectory_mcap::write_mcap(path, traj, &result.events),
                Output::Plot => figure::write_svg(path, traj, summary, &plot_title(args, &scene)),
            };
            if let Err(e) = res {
                // Leave no half set of outputs behind.
                for p in &written {
                    let _ = std::fs::remove_file(p);
                }
                return Err(Failure::Output(format!(
                    "{} {}: {e}",
                    kind.flag(),
                    path.display()
                )));
            }
            written.push(path);
        }
    } else if !outputs.is_empty() {
        return Err(Failure::Output(
            "the run recorded no trajectory; nothing written".into(),
        ));
    }

    let text = if args.json {
        match serde_json::to_string(summary) {
            Ok(s) => s + "\n",
            Err(e) => return Err(Failure::Output(format!("summary as JSON: {e}"))),
        }
    } else {
        human_summary(args, &scene, summary, &written)
    };
    // Not `print!`: a closed pipe (`cushion simulate | head -1`) must not panic.
    {
        use std::io::Write;
        let mut out = std::io::stdout().lock();
        let _ = out.write_all(text.as_bytes()).and_then(|_| out.flush());
    }
    Ok(if summary.status == RunStatus::Ok {
        0
    } else {
        1
    })
}

/// The scene file (or the defaults), then every `--set` in order.
fn build_scene(args: &SimulateArgs) -> Result<Scene, Failure> {
    let mut scene = match &args.scene {
        Some(path) => Scene::from_file(path).map_err(|e| Failure::Input(e.to_string()))?,
        None => Scene::default(),
    };
    for item in &args.set {
        let Some((key, value)) = item.split_once('=') else {
            return Err(Failure::Input(format!(
                "--set `{item}`: expected KEY=VALUE (e.g. --set robot.dead_time=0.01); keys: {}",
                Scene::keys().join(", ")
            )));
        };
        scene
            .set_from_str(key.trim(), value.trim())
            .map_err(|e| Failure::Input(format!("--set {item}: {e}")))?;
    }
    Ok(scene)
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Output {
    Csv,
    Mcap,
    Plot,
}

impl Output {
    fn flag(self) -> &'static str {
        match self {
            Output::Csv => "--csv",
            Output::Mcap => "--mcap",
            Output::Plot => "--plot",
        }
    }
}

/// The requested output files, checked before the run: each must name a file in an existing
/// directory, and no two may be the same path.
fn outputs(args: &SimulateArgs) -> Result<Vec<(Output, PathBuf)>, Failure> {
    let mut out = Vec::new();
    for (kind, path) in [
        (Output::Csv, &args.csv),
        (Output::Mcap, &args.mcap),
        (Output::Plot, &args.plot),
    ] {
        let Some(path) = path else { continue };
        if path.as_os_str().is_empty() || path.is_dir() {
            return Err(Failure::Input(format!(
                "{} `{}`: not a file name (expected a file path in an existing directory)",
                kind.flag(),
                path.display()
            )));
        }
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        if !dir.is_dir() {
            return Err(Failure::Input(format!(
                "{} `{}`: directory `{}` does not exist (expected a file path in an existing directory)",
                kind.flag(),
                path.display(),
                dir.display()
            )));
        }
        if let Some((other, _)) = out.iter().find(|(_, p)| p == path) {
            let other: &Output = other;
            return Err(Failure::Input(format!(
                "{} `{}`: same file as {} (expected distinct output files)",
                kind.flag(),
                path.display(),
                other.flag()
            )));
        }
        out.push((kind, path.clone()));
    }
    Ok(out)
}

fn float_key(scene: &Scene, key: &str) -> Option<f64> {
    match scene.get(key).ok()? {
        toml::Value::Float(f) => Some(f),
        toml::Value::Integer(i) => Some(i as f64),
        _ => None,
    }
}

fn text_key(scene: &Scene, key: &str) -> Option<String> {
    match scene.get(key).ok()? {
        toml::Value::String(s) => Some(s),
        other => Some(other.to_string()),
    }
}

fn scene_label(args: &SimulateArgs) -> String {
    let base = match &args.scene {
        Some(p) => p.display().to_string(),
        None => "default scene".to_string(),
    };
    match args.set.len() {
        0 => base,
        n => format!("{base} + {n} --set"),
    }
}

fn plot_title(args: &SimulateArgs, scene: &Scene) -> String {
    let source = match &args.scene {
        Some(p) => p
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        None => "default scene".to_string(),
    };
    let source = match args.set.len() {
        0 => source,
        n => format!("{source} + {n} --set"),
    };
    let mut parts = Vec::new();
    if let Some(m) = text_key(scene, "module") {
        parts.push(format!("{m} module"));
    }
    if let Some(dt) = float_key(scene, "robot.dead_time") {
        parts.push(format!("dead time {} ms", trim_zeros(fmt_sig(dt * 1e3, 4))));
    }
    if let Some(m) = float_key(scene, "object.mass") {
        parts.push(format!("object {} kg", trim_zeros(fmt_sig(m, 4))));
    }
    parts.push(source);
    parts.join(", ")
}

/// `70.00` -> `70`, `0.2460` -> `0.246` (plain decimals only).
fn trim_zeros(s: String) -> String {
    if s.contains('.') && !s.contains('e') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// `v` with `digits` significant digits, plain for ordinary magnitudes, scientific otherwise.
fn fmt_sig(v: f64, digits: usize) -> String {
    if !v.is_finite() {
        return v.to_string();
    }
    if v == 0.0 {
        return "0".to_string();
    }
    let e = v.abs().log10().floor() as i32;
    if (-4..6).contains(&e) {
        let decimals = (digits as i32 - 1 - e).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.*e}", digits - 1)
    }
}

fn opt(v: Option<f64>, scale: f64, unit: &str, none: &str) -> (String, String) {
    match v {
        Some(x) => (fmt_sig(x * scale, 5), unit.to_string()),
        None => (none.to_string(), String::new()),
    }
}

/// One line of the readable summary: the field's JSON name, its value and unit, what it means.
type Row = (&'static str, (String, String), String);

/// The readable summary: one aligned line per summary field, then the files written.
fn human_summary(args: &SimulateArgs, scene: &Scene, s: &Summary, written: &[&Path]) -> String {
    let rows = summary_rows(args, scene, s);
    let name_w = rows.iter().map(|r| r.0.len()).max().unwrap_or(0);
    // Align value+unit only over rows that carry a description (short values).
    let val_w = rows
        .iter()
        .filter(|r| !r.2.is_empty())
        .map(|r| r.1 .0.len() + 1 + r.1 .1.len())
        .max()
        .unwrap_or(0);
    let mut out = String::new();
    for (name, (value, unit), what) in rows {
        let vu = if unit.is_empty() {
            value
        } else {
            format!("{value} {unit}")
        };
        if what.is_empty() {
            out.push_str(&format!("{name:<name_w$}  {vu}\n"));
        } else {
            out.push_str(&format!("{name:<name_w$}  {vu:<val_w$}  {what}\n"));
        }
    }
    for p in written {
        out.push_str(&format!("{:<name_w$}  {}\n", "wrote", p.display()));
    }
    out
}

/// The rows of [`human_summary`], in the order of the summary's fields.
fn summary_rows(args: &SimulateArgs, scene: &Scene, s: &Summary) -> Vec<Row> {
    let num = |x: f64, scale: f64, unit: &str| (fmt_sig(x * scale, 5), unit.to_string());
    let count = |n: u32| (n.to_string(), String::new());
    let yes_no = |b: bool| (if b { "yes" } else { "no" }.to_string(), String::new());
    let mut rows: Vec<Row> = vec![
        ("scene", (scene_label(args), String::new()), String::new()),
        (
            "module",
            (text_key(scene, "module").unwrap_or_default(), String::new()),
            String::new(),
        ),
        (
            "status",
            (s.status.name().to_string(), String::new()),
            String::new(),
        ),
    ];
    if !s.message.is_empty() {
        rows.push(("message", (s.message.clone(), String::new()), String::new()));
    }
    rows.extend([
        (
            "t_detect",
            opt(s.t_detect, 1e3, "ms", "never"),
            "sensor switched".to_string(),
        ),
        (
            "t_brake",
            opt(s.t_brake, 1e3, "ms", "never"),
            "robot starts braking".to_string(),
        ),
        (
            "peak_robot_force",
            num(s.peak_robot_force, 1.0, "N"),
            "force on the robot at its largest |F_r|".into(),
        ),
        (
            "t_peak_robot_force",
            num(s.t_peak_robot_force, 1e3, "ms"),
            "time of that peak".into(),
        ),
        (
            "robot_impulse",
            num(s.robot_impulse, 1.0, "N s"),
            "integral of F_r over the run".into(),
        ),
        (
            "peak_contact_force",
            num(s.peak_contact_force, 1.0, "N"),
            "largest tool-object contact force".into(),
        ),
        (
            "object_impacts",
            count(s.object_impacts),
            "tool-object contact phases".into(),
        ),
        (
            "forward_stop_impacts",
            count(s.forward_stop_impacts),
            "impacts on the forward end-stop".into(),
        ),
        (
            "back_stop_impacts",
            count(s.back_stop_impacts),
            "impacts on the back end-stop".into(),
        ),
        (
            "object_final_velocity",
            opt(s.object_final_velocity, 1.0, "m/s", "n/a (no object)"),
            "object speed at the end".into(),
        ),
        (
            "object_final_momentum",
            opt(s.object_final_momentum, 1.0, "kg m/s", "n/a (no object)"),
            "object momentum at the end".into(),
        ),
        (
            "object_travel",
            opt(s.object_travel, 1e3, "mm", "n/a (no object)"),
            "x_p(end) - x_p(0)".into(),
        ),
        (
            "max_stroke",
            num(s.max_stroke, 1e3, "mm"),
            "largest stroke s".into(),
        ),
        (
            "back_stop_hit",
            yes_no(s.back_stop_hit),
            "tool reached the back end-stop".into(),
        ),
        (
            "max_gas_pressure",
            opt(s.max_gas_pressure, 1e-3, "kPa", "n/a (no gas)"),
            "largest gas pressure p1".into(),
        ),
        (
            "energy_residual",
            opt(s.energy_residual, 1.0, "", "off"),
            "energy ledger mismatch / largest term".into(),
        ),
        (
            "stats",
            (
                format!(
                    "{} steps ({} rejected), {} rhs evals, {} events{}",
                    s.stats.steps,
                    s.stats.rejected,
                    s.stats.rhs_evals,
                    s.stats.events,
                    if s.stats.stiff { ", stiff" } else { "" }
                ),
                String::new(),
            ),
            String::new(),
        ),
    ]);
    rows
}

#[cfg(test)]
mod tests {
    use super::fmt_sig;

    #[test]
    fn significant_digits() {
        assert_eq!(fmt_sig(0.070, 4), "0.07000");
        assert_eq!(fmt_sig(-12.345678, 5), "-12.346");
        assert_eq!(fmt_sig(1234.5, 5), "1234.5");
        assert_eq!(fmt_sig(0.0, 5), "0");
        assert_eq!(fmt_sig(1.5e-7, 3), "1.50e-7");
        assert_eq!(fmt_sig(2.5e8, 3), "2.50e8");
    }
}
