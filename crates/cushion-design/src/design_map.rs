//! `design-map.svg`: the answer at a glance.
//!
//! - Two design ranges or more: the first two ranges as the axes (each drawn uniformly in its
//!   normalised coordinate, so a log range is spread by decades), the other design axes at the
//!   chosen design. The background is the refined map's margin (the interpolation of
//!   [`crate::Refinement::map_margin`]: blue feasible, red infeasible, pale near 0), the boundary
//!   (where the map's margin changes sign) in black, the evaluated design points of this slice
//!   as dots (filled feasible, hollow infeasible) and the chosen design as a star.
//! - One design range (or only lists): one panel per limit bound, the worst case (its size
//!   with `abs`) at the design points of this slice against the design axis, the limit as a
//!   dashed line and the chosen design as a vertical line.

use std::path::Path;

use plotters::prelude::*;

use crate::axes::{Axis, AxisKind};
use crate::design_file::scene_value;
use crate::engine_runs::DesignResult;
use crate::refine::DesignPoint;
use crate::tables::target_names;

type Draw = Result<(), Box<dyn std::error::Error>>;

const FEASIBLE: RGBColor = RGBColor(33, 102, 172);
const INFEASIBLE: RGBColor = RGBColor(178, 24, 43);

/// Draw the map of an answered question.
pub fn write_design_map(path: &Path, r: &DesignResult) -> Draw {
    let axes = r.map.design_axes();
    let ranges: Vec<usize> = (0..axes.len())
        .filter(|&i| axes.axes()[i].is_continuous())
        .collect();
    if ranges.len() >= 2 {
        two_axes(path, r, ranges[0], ranges[1])
    } else {
        one_axis(path, r, ranges.first().copied().unwrap_or(0))
    }
}

/// A tick label: the real value at a normalised coordinate (the value along a list).
fn label(r: &DesignResult, axis: usize, c: f64) -> String {
    let a = &r.map.design_axes().axes()[axis];
    let x = match a.kind {
        AxisKind::Range { .. } => a.real(c),
        AxisKind::Values { count } => {
            let i = c.round();
            if (c - i).abs() > 1e-9 || i < 0.0 || i >= count as f64 {
                return String::new();
            }
            i
        }
    };
    match scene_value(&r.file.design[axis], x) {
        toml::Value::Float(f) => format!("{}", Sig(f)),
        toml::Value::String(s) => s,
        other => other.to_string(),
    }
}

/// A number with 3 significant digits.
struct Sig(f64);

impl std::fmt::Display for Sig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let x = self.0;
        if x == 0.0 {
            write!(f, "0")
        } else if (1e-3..1e4).contains(&x.abs()) {
            let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize;
            let s = format!("{x:.digits$}");
            let s = if s.contains('.') {
                s.trim_end_matches('0').trim_end_matches('.')
            } else {
                &s
            };
            write!(f, "{s}")
        } else {
            write!(f, "{x:.2e}")
        }
    }
}

/// The normalised coordinate of a design point along an axis (the index along a list).
fn coordinate(a: &Axis, x: f64) -> f64 {
    a.coordinate(x).unwrap_or(x)
}

/// The design points that share the chosen design's values along every axis but `free`.
fn slice<'a>(r: &'a DesignResult, free: &[usize]) -> Vec<&'a DesignPoint> {
    r.map
        .points()
        .iter()
        .filter(|p| {
            p.design
                .iter()
                .zip(&r.best.design)
                .enumerate()
                .all(|(i, (a, b))| free.contains(&i) || a == b)
        })
        .collect()
}

fn fixed_caption(r: &DesignResult, free: &[usize]) -> String {
    let fixed: Vec<String> = r
        .file
        .design
        .iter()
        .enumerate()
        .filter(|(i, _)| !free.contains(i))
        .map(|(i, a)| {
            let c = coordinate(&r.map.design_axes().axes()[i], r.best.design[i]);
            format!("{} = {}", a.key, label(r, i, c))
        })
        .collect();
    if fixed.is_empty() {
        String::new()
    } else {
        format!(" at {}", fixed.join(", "))
    }
}

fn margin_colour(m: f64, scale: f64) -> RGBColor {
    if !m.is_finite() {
        return RGBColor(120, 0, 20);
    }
    // 16 shades a side: neighbouring pixels of one shade are drawn as one rectangle.
    let u = ((m.abs() / scale).clamp(0.0, 1.0).sqrt() * 16.0).round() / 16.0;
    let (end, pale) = if m >= 0.0 {
        (FEASIBLE, (209.0, 229.0, 240.0))
    } else {
        (INFEASIBLE, (253.0, 219.0, 199.0))
    };
    let mix = |a: f64, b: u8| (a + (b as f64 - a) * u).round() as u8;
    RGBColor(mix(pale.0, end.0), mix(pale.1, end.1), mix(pale.2, end.2))
}

fn two_axes(path: &Path, r: &DesignResult, ix: usize, iy: usize) -> Draw {
    const N: usize = 128;
    let axes = r.map.design_axes().axes();
    let mut margins = vec![vec![0.0; N]; N];
    let mut point = r.best.design.clone();
    for (i, row) in margins.iter_mut().enumerate() {
        for (j, m) in row.iter_mut().enumerate() {
            point[ix] = axes[ix].real((i as f64 + 0.5) / N as f64);
            point[iy] = axes[iy].real((j as f64 + 0.5) / N as f64);
            *m = r.map.map_margin(&point)?;
        }
    }
    let scale = margins
        .iter()
        .flatten()
        .filter(|m| m.is_finite())
        .fold(0.0f64, |a, m| a.max(m.abs()))
        .max(1e-3);

    let root = SVGBackend::new(path, (820, 760)).into_drawing_area();
    root.fill(&WHITE)?;
    let title = format!(
        "{}: feasible designs (blue) by margin{}",
        r.file.name,
        fixed_caption(r, &[ix, iy])
    );
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(20)
        .x_label_area_size(55)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..1.0, 0.0..1.0)?;
    let fx = |c: &f64| label(r, ix, *c);
    let fy = |c: &f64| label(r, iy, *c);
    chart
        .configure_mesh()
        .disable_mesh()
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 18))
        .x_desc(axes[ix].key.as_str())
        .y_desc(axes[iy].key.as_str())
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .draw()?;
    let w = 1.0 / N as f64;
    let mut tiles = Vec::new();
    for (i, row) in margins.iter().enumerate() {
        let mut j0 = 0;
        for j in 1..=N {
            let c = margin_colour(row[j0], scale);
            if j == N || margin_colour(row[j], scale) != c {
                let x = i as f64 * w;
                tiles.push(Rectangle::new(
                    [(x, j0 as f64 * w), (x + w, j as f64 * w)],
                    c.filled(),
                ));
                j0 = j;
            }
        }
    }
    chart.draw_series(tiles)?;
    // The boundary: edges between pixels whose margins have opposite signs.
    let mut edges = Vec::new();
    for i in 0..N {
        for j in 0..N {
            let here = margins[i][j] >= 0.0;
            if i + 1 < N && (margins[i + 1][j] >= 0.0) != here {
                let x = (i + 1) as f64 * w;
                edges.push(vec![(x, j as f64 * w), (x, (j + 1) as f64 * w)]);
            }
            if j + 1 < N && (margins[i][j + 1] >= 0.0) != here {
                let y = (j + 1) as f64 * w;
                edges.push(vec![(i as f64 * w, y), ((i + 1) as f64 * w, y)]);
            }
        }
    }
    chart.draw_series(
        edges
            .into_iter()
            .map(|e| PathElement::new(e, BLACK.stroke_width(2))),
    )?;
    let pts = slice(r, &[ix, iy]);
    chart.draw_series(pts.iter().map(|p| {
        let c = (
            coordinate(&axes[ix], p.design[ix]),
            coordinate(&axes[iy], p.design[iy]),
        );
        let style = if p.feasible {
            BLACK.mix(0.6).filled()
        } else {
            BLACK.mix(0.6).stroke_width(1)
        };
        Circle::new(c, 2, style)
    }))?;
    let best = (
        coordinate(&axes[ix], r.best.design[ix]),
        coordinate(&axes[iy], r.best.design[iy]),
    );
    chart
        .draw_series(std::iter::once(Cross::new(
            best,
            9,
            RGBColor(255, 200, 0).stroke_width(4),
        )))?
        .label(format!("chosen design (margin {})", Sig(r.best.margin)))
        .legend(|(x, y)| Cross::new((x + 8, y), 6, RGBColor(255, 200, 0).stroke_width(3)));
    chart.draw_series(std::iter::once(Cross::new(best, 9, BLACK.stroke_width(1))))?;
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()?;
    root.present()?;
    Ok(())
}

fn one_axis(path: &Path, r: &DesignResult, ix: usize) -> Draw {
    let axes = r.map.design_axes().axes();
    let limits = r.map.limits();
    let names = target_names(limits);
    // One panel per limit bound, on its target.
    let mut panels = Vec::new();
    for l in &r.file.limits {
        for (bound, upper) in [(l.max, true), (l.min, false)] {
            let Some(bound) = bound else { continue };
            let t = limits.targets().iter().position(|t| {
                limits.metrics()[t.metric] == l.metric
                    && matches!(
                        (t.direction, upper),
                        (crate::Direction::Max | crate::Direction::AbsMax, true)
                            | (crate::Direction::Min | crate::Direction::AbsMin, false)
                    )
            });
            if let Some(t) = t {
                let what = if l.abs {
                    format!("|{}|", l.metric)
                } else {
                    l.metric.clone()
                };
                panels.push((t, bound, what));
            }
        }
    }
    let mut pts: Vec<(f64, &DesignPoint)> = slice(r, &[ix])
        .into_iter()
        .map(|p| (coordinate(&axes[ix], p.design[ix]), p))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (x0, x1) = match axes[ix].kind {
        AxisKind::Range { .. } => (0.0, 1.0),
        AxisKind::Values { count } => (-0.5, count as f64 - 0.5),
    };

    let height = 330 * panels.len().max(1) as u32;
    let root = SVGBackend::new(path, (820, height + 40)).into_drawing_area();
    root.fill(&WHITE)?;
    let (top, body) = root.split_vertically(40);
    top.titled(
        &format!(
            "{}: worst case over the for_all box against {}{}",
            r.file.name,
            axes[ix].key,
            fixed_caption(r, &[ix])
        ),
        ("sans-serif", 20),
    )?;
    let areas = body.split_evenly((panels.len().max(1), 1));
    let best_x = coordinate(&axes[ix], r.best.design[ix]);
    for ((t, bound, what), area) in panels.iter().zip(&areas) {
        let direction = limits.targets()[*t].direction;
        let ys: Vec<(f64, f64, bool)> = pts
            .iter()
            .filter(|(_, p)| !p.worst[*t].failed)
            .map(|(x, p)| (*x, direction.size(p.worst[*t].value), p.feasible))
            .collect();
        let lo = ys.iter().map(|y| y.1).fold(*bound, f64::min);
        let hi = ys.iter().map(|y| y.1).fold(*bound, f64::max);
        let pad = ((hi - lo) * 0.08).max(1e-9 * hi.abs().max(1.0));
        let mut chart = ChartBuilder::on(area)
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d(x0..x1, (lo - pad)..(hi + pad))?;
        let fx = |c: &f64| label(r, ix, *c);
        chart
            .configure_mesh()
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .x_desc(axes[ix].key.as_str())
            .y_desc(format!("worst {what} ({})", names[*t]))
            .x_label_formatter(&fx)
            .draw()?;
        chart.draw_series(LineSeries::new(
            ys.iter().map(|y| (y.0, y.1)),
            FEASIBLE.stroke_width(2),
        ))?;
        chart.draw_series(ys.iter().map(|y| {
            let style = if y.2 {
                FEASIBLE.filled()
            } else {
                INFEASIBLE.filled()
            };
            Circle::new((y.0, y.1), 3, style)
        }))?;
        chart.draw_series(DashedLineSeries::new(
            vec![(x0, *bound), (x1, *bound)],
            8,
            5,
            INFEASIBLE.stroke_width(2),
        ))?;
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(best_x, lo - pad), (best_x, hi + pad)],
            RGBColor(255, 170, 0).stroke_width(2),
        )))?;
    }
    root.present()?;
    Ok(())
}
