//! `sensitivity.svg`: for each of the first few analysed outputs, a panel of `S1` and `ST` per
//! input with their intervals, and beside it the `S2` matrix as a heat map (with second order).

use std::path::Path;

use plotters::prelude::*;

use crate::sobol::{Sensitivity, SobolIndices};
use crate::study::{Finding, Study};

/// Outputs drawn, at most.
pub const MAX_PANELS: usize = 4;

const S1_COLOR: RGBColor = RGBColor(31, 119, 180);
const ST_COLOR: RGBColor = RGBColor(255, 127, 14);

type Draw<E> = Result<(), DrawingAreaErrorKind<E>>;

/// The short name of an input on an axis: its key after the section (`robot.dead_time` ->
/// `dead_time`).
fn short(key: &str) -> &str {
    key.rsplit('.').next().unwrap_or(key)
}

/// A diverging colour for `v` in `[-1, 1]`: blue below 0, white at 0, red above.
fn diverging(v: f64) -> RGBColor {
    let t = v.clamp(-1.0, 1.0);
    let mix = |a: u8, b: u8, w: f64| (a as f64 + (b as f64 - a as f64) * w).round() as u8;
    if t >= 0.0 {
        RGBColor(mix(255, 178, t), mix(255, 24, t), mix(255, 43, t))
    } else {
        RGBColor(mix(255, 33, -t), mix(255, 102, -t), mix(255, 172, -t))
    }
}

/// Draw the chart of `study` to `path` (SVG).
pub fn write_chart(path: &Path, study: &Study) -> Result<(), String> {
    let panels: Vec<(&str, &SobolIndices)> = study
        .outputs
        .iter()
        .zip(&study.findings)
        .filter_map(|(o, f)| match f {
            Finding::Sensitivity(Sensitivity::Indices(s)) => Some((o.as_str(), s)),
            _ => None,
        })
        .take(MAX_PANELS)
        .collect();
    let rows = panels.len().max(1);
    let heat = study.second_order && study.inputs.len() > 1;
    let width = if heat { 1150 } else { 700 };
    let root = SVGBackend::new(path, (width, 340 * rows as u32)).into_drawing_area();
    draw(&root, study, &panels, heat).map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    study: &Study,
    panels: &[(&str, &SobolIndices)],
    heat: bool,
) -> Draw<DB::ErrorType> {
    root.fill(&WHITE)?;
    if panels.is_empty() {
        root.draw(&Text::new(
            "no output varies over the sample: nothing to draw",
            (30, 40),
            ("sans-serif", 18),
        ))?;
        return Ok(());
    }
    let names: Vec<String> = study.inputs.iter().map(|k| short(k).to_string()).collect();
    let areas = root.split_evenly((panels.len(), 1));
    for (area, (output, s)) in areas.iter().zip(panels) {
        if heat {
            let (left, right) = area.split_horizontally(700);
            draw_s1_st(&left, study, output, s, &names)?;
            draw_s2(&right, output, s, &names)?;
        } else {
            draw_s1_st(area, study, output, s, &names)?;
        }
    }
    Ok(())
}

/// One output's S1 and ST per input, bars with their intervals.
fn draw_s1_st<DB: DrawingBackend>(
    left: &DrawingArea<DB, plotters::coord::Shift>,
    study: &Study,
    output: &str,
    s: &SobolIndices,
    names: &[String],
) -> Draw<DB::ErrorType> {
    let d = names.len();
    // S1 and ST with their intervals.
    let lo =
        s.s1.iter()
            .chain(&s.st)
            .map(|e| e.value - e.conf)
            .fold(0.0f64, f64::min);
    let hi =
        s.s1.iter()
            .chain(&s.st)
            .map(|e| e.value + e.conf)
            .fold(1.0f64, f64::max);
    let mut chart = ChartBuilder::on(left)
        .caption(
            format!(
                "{output}: S1 and ST ({:.0} % intervals)",
                100.0 * study.conf_level
            ),
            ("sans-serif", 17),
        )
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(50)
        .build_cartesian_2d(-0.5f64..(d as f64 - 0.5), (lo - 0.05)..(hi + 0.05))?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(d)
        .x_label_formatter(&|x| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < names.len() {
                names[i as usize].clone()
            } else {
                String::new()
            }
        })
        .y_label_formatter(&|v| format!("{v:.1}"))
        .label_style(("sans-serif", 13))
        .draw()?;
    for (which, color, offset) in [(0, S1_COLOR, -0.19), (1, ST_COLOR, 0.19)] {
        let list = if which == 0 { &s.s1 } else { &s.st };
        let bars = list.iter().enumerate().map(|(j, e)| {
            let x = j as f64 + offset;
            Rectangle::new([(x - 0.16, 0.0), (x + 0.16, e.value)], color.filled())
        });
        let series = chart.draw_series(bars)?;
        series
            .label(if which == 0 { "S1" } else { "ST" })
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], color.filled()));
        chart.draw_series(list.iter().enumerate().map(|(j, e)| {
            let x = j as f64 + offset;
            PathElement::new(
                vec![(x, e.value - e.conf), (x, e.value + e.conf)],
                BLACK.stroke_width(2),
            )
        }))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()?;

    Ok(())
}

/// One output's S2 matrix as a heat map (the diagonal grey), each cell with its value.
fn draw_s2<DB: DrawingBackend>(
    right: &DrawingArea<DB, plotters::coord::Shift>,
    output: &str,
    s: &SobolIndices,
    names: &[String],
) -> Draw<DB::ErrorType> {
    let d = names.len();
    // The S2 matrix.
    let mut m = ChartBuilder::on(right)
        .caption(format!("{output}: S2"), ("sans-serif", 17))
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(80)
        .build_cartesian_2d(-0.5f64..(d as f64 - 0.5), -0.5f64..(d as f64 - 0.5))?;
    m.configure_mesh()
        .disable_mesh()
        .x_labels(d)
        .y_labels(d)
        .x_label_formatter(&|x| cell_name(names, *x, false))
        .y_label_formatter(&|y| cell_name(names, *y, true))
        .label_style(("sans-serif", 12))
        .draw()?;
    let scale =
        s.s2.iter()
            .map(|p| p.value.abs())
            .fold(0.0f64, f64::max)
            .max(1e-12);
    for j in 0..d {
        for k in 0..d {
            let value =
                s.s2.iter()
                    .find(|p| (p.j, p.k) == (j.min(k), j.max(k)))
                    .map(|p| p.value);
            let color = match value {
                Some(v) if j != k => diverging(v / scale),
                _ => RGBColor(225, 225, 225),
            };
            // Row k from the top.
            let (x0, y0) = (j as f64 - 0.5, (d - 1 - k) as f64 - 0.5);
            m.draw_series(std::iter::once(Rectangle::new(
                [(x0, y0), (x0 + 1.0, y0 + 1.0)],
                color.filled(),
            )))?;
            if let (Some(v), true) = (value, j != k) {
                m.draw_series(std::iter::once(Text::new(
                    format!("{v:.3}"),
                    (x0 + 0.25, y0 + 0.55),
                    ("sans-serif", 12),
                )))?;
            }
        }
    }
    Ok(())
}

/// The input at a cell's centre on the heat map's axes (the y axis runs top-down).
fn cell_name(names: &[String], v: f64, top_down: bool) -> String {
    let i = v.round();
    if (v - i).abs() > 1e-6 || i < 0.0 || i as usize >= names.len() {
        return String::new();
    }
    let i = i as usize;
    names[if top_down { names.len() - 1 - i } else { i }].clone()
}
