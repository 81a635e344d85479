//! The small report written next to a sweep's summary: SVG charts read at a glance.
//!
//! - `report-speed-force.svg` (when `robot.dead_time` is an axis): object final speed and peak
//!   robot force |F_r| against dead time, one colour per module. Where the sweep varies other
//!   keys too, each dead-time group (the exact values when there are at most 25, else 20 equal
//!   bins) shows the median as a line with markers and the range (min to max) as a bar.
//! - `report-heatmap.svg` (when `hydraulic.gas_pressure` and `hydraulic.orifice_radius` are
//!   axes): hydraulic runs only, gas pressure (log) against orifice radius; each cell shows the
//!   worst case (largest) |F_r| and object final speed over the runs in that cell (whatever
//!   else varies: dead time, object mass). The cells are the axis values when there are at most
//!   30 of each, else 16 x 12 bins.
//!
//! Only runs with status `ok` are drawn; the caption says how many were left out.

use std::collections::BTreeMap;
use std::path::Path;

use arrow_array::{Array, Float64Array, RecordBatch, StringArray};
use plotters::prelude::*;

use crate::parquet_io::read_parquet;

mod heatmap;
mod speed_force;

use heatmap::heatmap;
use speed_force::speed_force;

pub const SPEED_FORCE_SVG: &str = "report-speed-force.svg";
pub const HEATMAP_SVG: &str = "report-heatmap.svg";

const DEAD_TIME: &str = "robot.dead_time";
const GAS: &str = "hydraulic.gas_pressure";
const ORIFICE: &str = "hydraulic.orifice_radius";

fn module_color(m: &str) -> RGBColor {
    match m {
        "hydraulic" => RGBColor(31, 119, 180),
        "bistable" => RGBColor(255, 127, 14),
        "rigid" => RGBColor(110, 110, 110),
        _ => RGBColor(44, 160, 44),
    }
}

fn f64_col(b: &RecordBatch, name: &str) -> Option<Float64Array> {
    b.column_by_name(name)
        .and_then(|c| c.as_any().downcast_ref::<Float64Array>().cloned())
}

fn str_col(b: &RecordBatch, name: &str) -> Option<StringArray> {
    b.column_by_name(name)
        .and_then(|c| c.as_any().downcast_ref::<StringArray>().cloned())
}

/// At most this many values per chart are kept for medians and quartiles (a deterministic
/// every-k-th subsample beyond it); minima, maxima and the heat map use every run. Memory stays
/// flat in the number of runs.
const SAMPLE_CAP: usize = 40_000;

/// One axis seen in a first pass: its distinct values (up to a cap) and range.
#[derive(Clone)]
struct AxisScan {
    distinct: Vec<f64>,
    overflow: bool,
    min: f64,
    max: f64,
}

impl AxisScan {
    fn new() -> AxisScan {
        AxisScan {
            distinct: Vec::new(),
            overflow: false,
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
        }
    }
    fn add(&mut self, v: f64, cap: usize) {
        if !v.is_finite() {
            return;
        }
        self.min = self.min.min(v);
        self.max = self.max.max(v);
        if !self.overflow {
            if let Err(i) = self.distinct.binary_search_by(|d| d.total_cmp(&v)) {
                self.distinct.insert(i, v);
                if self.distinct.len() > cap {
                    self.overflow = true;
                    self.distinct.clear();
                }
            }
        }
    }
    /// The groups: the distinct values when at most `cap`, else `bins` equal bins (in log when
    /// `log`).
    fn grouping(&self, bins: usize, log: bool) -> Grouping {
        if !self.overflow {
            return Grouping {
                centres: self.distinct.clone(),
                exact: true,
                lo: 0.0,
                w: 1.0,
                log,
            };
        }
        let tr = |v: f64| if log { v.ln() } else { v };
        let (lo, hi) = (tr(self.min), tr(self.max));
        let w = ((hi - lo) / bins as f64).max(f64::MIN_POSITIVE);
        let centres = (0..bins)
            .map(|i| {
                let c = lo + (i as f64 + 0.5) * w;
                if log {
                    c.exp()
                } else {
                    c
                }
            })
            .collect();
        Grouping {
            centres,
            exact: false,
            lo,
            w,
            log,
        }
    }
}

struct Grouping {
    centres: Vec<f64>,
    exact: bool,
    lo: f64,
    w: f64,
    log: bool,
}

impl Grouping {
    fn index(&self, v: f64) -> Option<usize> {
        if !v.is_finite() || self.centres.is_empty() {
            return None;
        }
        if self.exact {
            return self.centres.binary_search_by(|d| d.total_cmp(&v)).ok();
        }
        let t = if self.log { v.ln() } else { v };
        Some((((t - self.lo) / self.w).max(0.0) as usize).min(self.centres.len() - 1))
    }
}

/// Min, max and a bounded sample of one group's values.
#[derive(Clone)]
struct Acc {
    min: f64,
    max: f64,
    sample: Vec<f64>,
}

impl Acc {
    fn new() -> Acc {
        Acc {
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
            sample: Vec::new(),
        }
    }
    fn add(&mut self, v: f64, keep: bool) {
        if v.is_finite() {
            self.min = self.min.min(v);
            self.max = self.max.max(v);
            if keep {
                self.sample.push(v);
            }
        }
    }
    fn is_empty(&self) -> bool {
        self.min > self.max
    }
}

/// What the charts need, gathered in two streaming passes over `summary.parquet`.
struct Data {
    total: usize,
    ok: usize,
    modules: Vec<String>,
    has_dt: bool,
    has_map: bool,
    dt: Grouping,
    /// module -> per dead-time group: (speed, force).
    sf: BTreeMap<String, Vec<(Acc, Acc)>>,
    gas: Grouping,
    orifice: Grouping,
    /// Hydraulic runs: per (gas, orifice) cell, the largest |F_r| and object speed.
    cells: Vec<Vec<(f64, f64)>>,
    hydraulic_runs: usize,
}

fn for_each_row(
    dir: &Path,
    base_module: &str,
    mut f: impl FnMut(&str, [f64; 5]),
) -> Result<(usize, bool, bool), String> {
    let (mut total, mut has_dt, mut has_map) = (0, false, false);
    for b in read_parquet(&dir.join("summary.parquet")).map_err(|e| e.to_string())? {
        let b = b.map_err(|e| e.to_string())?;
        let status = str_col(&b, "status").ok_or("no status column")?;
        let module = str_col(&b, "module");
        let dt = f64_col(&b, DEAD_TIME);
        let gas = f64_col(&b, GAS);
        let ori = f64_col(&b, ORIFICE);
        has_dt = dt.is_some();
        has_map = gas.is_some() && ori.is_some();
        let speed = f64_col(&b, "object_final_velocity").ok_or("no object_final_velocity")?;
        let force = f64_col(&b, "peak_robot_force").ok_or("no peak_robot_force")?;
        let get = |c: &Option<Float64Array>, i: usize| match c {
            Some(c) if !c.is_null(i) => c.value(i),
            _ => f64::NAN,
        };
        for i in 0..b.num_rows() {
            total += 1;
            if status.value(i) != "ok" || force.is_null(i) {
                continue;
            }
            let m = module.as_ref().map(|m| m.value(i)).unwrap_or(base_module);
            let sp = if speed.is_null(i) {
                f64::NAN
            } else {
                speed.value(i).abs()
            };
            f(
                m,
                [
                    get(&dt, i),
                    get(&gas, i),
                    get(&ori, i),
                    sp,
                    force.value(i).abs(),
                ],
            );
        }
    }
    Ok((total, has_dt, has_map))
}

fn load(dir: &Path) -> Result<Data, String> {
    let base_module = std::fs::read(dir.join("provenance.json"))
        .ok()
        .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
        .and_then(|p| p["base_scene"]["module"].as_str().map(|s| s.to_string()))
        .unwrap_or_else(|| "hydraulic".to_string());
    // Pass 1: modules, ranges and distinct values.
    let (mut sdt, mut sgas, mut sori) = (AxisScan::new(), AxisScan::new(), AxisScan::new());
    let mut modules: Vec<String> = Vec::new();
    let mut ok = 0usize;
    let (total, has_dt, has_map) = for_each_row(dir, &base_module, |m, v| {
        ok += 1;
        if !modules.iter().any(|x| x == m) {
            modules.push(m.to_string());
        }
        sdt.add(v[0], 25);
        if m == "hydraulic" {
            sgas.add(v[1], 30);
            sori.add(v[2], 30);
        }
    })?;
    modules.sort();
    let dt = sdt.grouping(20, false);
    let gas = sgas.grouping(16, true);
    let orifice = sori.grouping(12, false);
    // Pass 2: the groups' values.
    let every = ok.div_ceil(SAMPLE_CAP).max(1);
    let mut sf: BTreeMap<String, Vec<(Acc, Acc)>> = modules
        .iter()
        .map(|m| (m.clone(), vec![(Acc::new(), Acc::new()); dt.centres.len()]))
        .collect();
    let mut cells = vec![vec![(f64::NAN, f64::NAN); orifice.centres.len()]; gas.centres.len()];
    let mut hydraulic_runs = 0usize;
    let mut n = 0usize;
    for_each_row(dir, &base_module, |m, v| {
        let keep = n.is_multiple_of(every);
        n += 1;
        if let (Some(g), Some(groups)) = (dt.index(v[0]), sf.get_mut(m)) {
            groups[g].0.add(v[3], keep);
            groups[g].1.add(v[4], keep);
        }
        if m == "hydraulic" {
            if let (Some(a), Some(b)) = (gas.index(v[1]), orifice.index(v[2])) {
                hydraulic_runs += 1;
                let c = &mut cells[a][b];
                let mx = |old: f64, new: f64| {
                    if old.is_nan() {
                        new
                    } else if new.is_nan() {
                        old
                    } else {
                        old.max(new)
                    }
                };
                *c = (mx(c.0, v[4]), mx(c.1, v[3]));
            }
        }
    })?;
    Ok(Data {
        total,
        ok,
        modules,
        has_dt,
        has_map,
        dt,
        sf,
        gas,
        orifice,
        cells,
        hydraulic_runs,
    })
}

/// Write the report charts that the sweep's axes allow; returns the files written.
pub fn write_report(dir: &Path) -> Result<Vec<std::path::PathBuf>, String> {
    let data = load(dir)?;
    let mut written = Vec::new();
    for f in [SPEED_FORCE_SVG, HEATMAP_SVG] {
        let _ = std::fs::remove_file(dir.join(f));
    }
    if data.has_dt && data.ok > 0 && !data.dt.centres.is_empty() {
        let p = dir.join(SPEED_FORCE_SVG);
        speed_force(&p, &data).map_err(|e| format!("{}: {e}", p.display()))?;
        written.push(p);
    }
    if data.has_map && data.hydraulic_runs > 0 {
        let p = dir.join(HEATMAP_SVG);
        heatmap(&p, &data).map_err(|e| format!("{}: {e}", p.display()))?;
        written.push(p);
    }
    Ok(written)
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// One group on the chart: (x, min, median, max, lower quartile, upper quartile).
type GroupStats = (f64, f64, f64, f64, f64, f64);

type Draw<E> = Result<(), DrawingAreaErrorKind<E>>;

/// A part of a report chart's SVG drawing.
type Area<'b> = DrawingArea<SVGBackend<'b>, plotters::coord::Shift>;

/// A chart on a part of the drawing, with numbers on both axes.
type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;
