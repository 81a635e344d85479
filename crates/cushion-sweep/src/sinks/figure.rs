//! The paper's figure 3 for one run, as SVG: four panels over time in ms:
//!
//! 1. positions of robot flange, tool and object (mm),
//! 2. their velocities (m/s),
//! 3. gas pressure `p1` (kPa; the panel says "no gas" for bistable and rigid scenes),
//! 4. force of the module on the robot `F_r` and the tool-object contact force `F_c` (N).
//!
//! The detection time (sensor switching) is a dashed red vertical line in every panel, the
//! brake start a dashed grey one. What is drawn (columns, units, labels, colours) is the table
//! of `layout.rs`, which `cushion.plot.run` draws from too.

use std::io;
use std::path::Path;

use cushion_model::{Summary, Trajectory, TrajectoryPoint};
use plotters::prelude::*;

mod layout;
mod panel;

pub use layout::{CurveSpec, MarkSpec, PanelSpec, FIGURE3, FIGURE3_MARKS};
use panel::draw_panel;

/// Figure size in pixels (width, height).
pub const SIZE: (u32, u32) = (1200, 1300);

/// One curve as drawn: its legend text, colour, column of `TrajectoryPoint::values` and the
/// factor to the panel's unit.
struct Curve {
    label: String,
    color: RGBColor,
    column: usize,
    factor: f64,
}

impl Curve {
    fn value(&self, p: &TrajectoryPoint) -> f64 {
        p.values()[self.column] * self.factor
    }
}

struct Panel {
    caption: &'static str,
    y_desc: String,
    curves: Vec<Curve>,
    /// Shown instead of the curves when no curve has a finite value.
    absent: &'static str,
}

fn color(hex: &str) -> RGBColor {
    let (r, g, b) = layout::rgb(hex);
    RGBColor(r, g, b)
}

/// The panels of [`FIGURE3`], ready to draw.
fn panels() -> Vec<Panel> {
    FIGURE3
        .iter()
        .map(|spec| Panel {
            caption: spec.title,
            y_desc: spec.y_label(),
            curves: spec
                .curves
                .iter()
                .map(|c| Curve {
                    label: c.label(),
                    color: color(c.color),
                    column: TrajectoryPoint::COLUMNS
                        .iter()
                        .position(|k| *k == c.column)
                        .expect("figure 3's curves are trajectory columns (layout's test)"),
                    factor: spec.factor,
                })
                .collect(),
            absent: spec.absent,
        })
        .collect()
}

/// Draw figure 3 of one run as SVG text. `title` heads the figure (e.g. module and dead time).
pub fn render_svg(trajectory: &Trajectory, summary: &Summary, title: &str) -> io::Result<String> {
    let pts = &trajectory.points;
    if pts.is_empty() {
        return Err(io::Error::other("cannot plot an empty trajectory"));
    }
    let t0 = pts.first().map(|p| p.t * 1e3).unwrap_or(0.0);
    let mut t1 = pts.last().map(|p| p.t * 1e3).unwrap_or(1.0);
    if t1.is_nan() || t1 <= t0 {
        t1 = t0 + 1.0;
    }
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        let body = root
            .titled(title, ("sans-serif", 22).into_font().color(&BLACK))
            .map_err(draw_err)?;
        let areas = body.split_evenly((4, 1));
        for (area, panel) in areas.iter().zip(panels()) {
            draw_panel(area, &panel, pts, (t0, t1), summary)?;
        }
        root.present().map_err(draw_err)?;
    }
    Ok(svg)
}

/// Draw figure 3 of one run into an SVG file (atomically).
pub fn write_svg(
    path: &Path,
    trajectory: &Trajectory,
    summary: &Summary,
    title: &str,
) -> io::Result<()> {
    let svg = render_svg(trajectory, summary, title)?;
    crate::atomic::write_atomic(path, svg.as_bytes())
}

fn draw_err<E: std::error::Error + Send + Sync + 'static>(e: E) -> io::Error {
    io::Error::other(format!("drawing the figure: {e}"))
}

/// Min-max decimation: per time bucket of `width` (about 3 pixels), keep the points of least
/// and greatest value, in time order, plus the first and last point of the line. Peaks survive
/// and sloped lines are drawn as straight strokes instead of pixel staircases.
fn decimate(points: &[(f64, f64)], width: f64) -> Vec<(f64, f64)> {
    if points.len() < 3 || width.is_nan() || width <= 0.0 {
        return points.to_vec();
    }
    let mut out = Vec::with_capacity(points.len().min(4096));
    out.push(points[0]);
    let mut i = 0;
    while i < points.len() {
        let start = points[i].0;
        let (mut lo, mut hi) = (i, i);
        let mut j = i;
        while j < points.len() && points[j].0 < start + width {
            if points[j].1 < points[lo].1 {
                lo = j;
            }
            if points[j].1 > points[hi].1 {
                hi = j;
            }
            j += 1;
        }
        let j = j.max(i + 1);
        let (a, b) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        for k in [a, b] {
            if out.last() != Some(&points[k]) {
                out.push(points[k]);
            }
        }
        i = j;
    }
    let last = points[points.len() - 1];
    if out.last() != Some(&last) {
        out.push(last);
    }
    out
}

fn format_ms(t: f64) -> String {
    format!("{:.1} ms", t * 1e3)
}

/// Tick labels: few digits, no float noise (0.30000000000000004 -> 0.3).
fn format_tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".to_string()
    } else if !(1e-3..1e5).contains(&a) {
        format!("{v:.1e}")
    } else {
        let s = format!("{v:.3}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if s == "-0" {
            "0".to_string()
        } else {
            s.to_string()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn traj(gas: bool) -> Trajectory {
        let points = (0..=300)
            .map(|i| {
                let t = i as f64 * 1e-3;
                TrajectoryPoint {
                    t,
                    x_r: t,
                    v_r: if t < 0.08 {
                        1.0
                    } else {
                        (1.0 - 10.0 * (t - 0.08)).max(0.0)
                    },
                    x_t: t - 2e-3 * (t * 30.0).sin().abs(),
                    v_t: 0.8,
                    x_p: 1e-3 + 0.5 * t,
                    v_p: if t < 0.01 { 0.0 } else { 0.6 },
                    s: 1e-3,
                    p1: if gas {
                        1000.0 + 5e4 * (-(t - 0.02).powi(2) / 1e-4).exp()
                    } else {
                        f64::NAN
                    },
                    f_c: (40.0 * (-(t - 0.01).powi(2) / 1e-6).exp()).max(0.0),
                    f_r: -30.0 * (-(t - 0.01).powi(2) / 1e-6).exp()
                        + 8.0 * (-(t - 0.15).powi(2) / 1e-5).exp(),
                }
            })
            .collect();
        Trajectory { points }
    }

    fn summary() -> Summary {
        let mut s = Summary::invalid("");
        s.t_detect = Some(0.0105);
        s.t_brake = Some(0.0805);
        s
    }

    #[test]
    fn svg_has_four_panels_and_markers() {
        let svg = render_svg(&traj(true), &summary(), "hydraulic, dead time 70 ms").unwrap();
        assert!(svg.starts_with("<svg"));
        assert!(svg.trim_end().ends_with("</svg>"));
        for text in [
            "Positions",
            "Velocities",
            "Gas pressure",
            "Forces",
            "time [ms]",
            "detection 10.5 ms",
            "force on the robot F_r",
        ] {
            assert!(svg.contains(text), "missing {text}");
        }
        if let Ok(dir) = std::env::var("CUSHION_FIGURE_DIR") {
            std::fs::write(Path::new(&dir).join("figure_test.svg"), &svg).unwrap();
        }
    }

    #[test]
    fn no_gas_says_so() {
        let svg = render_svg(&traj(false), &summary(), "bistable").unwrap();
        assert!(svg.contains("no gas in this scene"));
    }

    #[test]
    fn empty_trajectory_is_an_error() {
        assert!(render_svg(&Trajectory::default(), &summary(), "x").is_err());
    }

    #[test]
    fn decimation_keeps_peaks_and_ends() {
        let pts: Vec<(f64, f64)> = (0..10_000)
            .map(|i| {
                let t = i as f64 * 1e-3;
                (
                    t,
                    if i == 4321 {
                        50.0
                    } else if i == 777 {
                        -9.0
                    } else {
                        t.sin()
                    },
                )
            })
            .collect();
        let d = decimate(&pts, 0.03);
        assert!(d.len() < 1000, "{}", d.len());
        assert_eq!(d.first(), pts.first());
        assert_eq!(d.last(), pts.last());
        assert!(d.contains(&pts[4321]) && d.contains(&pts[777]));
        assert!(d.windows(2).all(|w| w[0].0 < w[1].0), "time order");
    }

    #[test]
    fn ticks_are_short() {
        assert_eq!(format_tick(0.30000000000000004), "0.3");
        assert_eq!(format_tick(-0.0), "0");
        assert_eq!(format_tick(25.0), "25");
        assert_eq!(format_tick(2e-5), "2.0e-5");
    }
}
