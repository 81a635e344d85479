//! `report-heatmap.svg`: the worst case of |F_r| and of the object's final speed per cell of gas
//! pressure and orifice radius, hydraulic runs (see `report.rs`).

use super::*;
use crate::quantities;

/// A perceptually ordered colour map (viridis, 5 stops, linear in between), `u` in [0, 1].
fn viridis(u: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let u = u.clamp(0.0, 1.0) * 4.0;
    let i = (u as usize).min(3);
    let f = u - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let mix = |x: f64, y: f64| (x + (y - x) * f).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

pub(super) fn heatmap(path: &Path, d: &Data) -> Draw<std::io::Error> {
    let root = SVGBackend::new(path, (1300, 580)).into_drawing_area();
    root.fill(&WHITE)?;
    let (top, body) = root.split_vertically(50);
    top.titled(
        &format!(
            "Hydraulic module: worst case over the other axes, per gas pressure and orifice radius ({} runs)",
            d.hydraulic_runs
        ),
        ("sans-serif", 22),
    )?;
    let (left, right) = body.split_horizontally(650);
    // Cell edges in plot coordinates: log10(pressure) and radius in mm.
    let gx = cell_edges(&d.gas.centres, true);
    let oy = cell_edges(&d.orifice.centres, false);
    for (area, which, metric) in [
        (&left, 0usize, "peak_robot_force"),
        (&right, 1usize, "object_final_velocity"),
    ] {
        let label = format!("max {}", quantities::label(metric, true));
        let map = Map::of(d, which);
        let (plot, bar) = area.split_horizontally(550);
        let mut chart = map_axes(&plot, &label, &gx, &oy)?;
        draw_cells(&mut chart, &map, &gx, &oy)?;
        if map.empty {
            continue;
        }
        colour_bar(&bar, map.lo, map.span)?;
    }
    root.present()?;
    Ok(())
}

/// The edges of the cells around their centres (halfway between neighbours, as far again
/// beyond the outer ones), in plot units: log10 of the value when `log`, else the value in
/// thousandths (m to mm).
fn cell_edges(c: &[f64], log: bool) -> Vec<f64> {
    let t: Vec<f64> = c
        .iter()
        .map(|v| if log { v.log10() } else { v * 1e3 })
        .collect();
    if t.len() == 1 {
        return vec![t[0] - 0.5, t[0] + 0.5];
    }
    let mut e = vec![t[0] - (t[1] - t[0]) / 2.0];
    for w in t.windows(2) {
        e.push((w[0] + w[1]) / 2.0);
    }
    e.push(t[t.len() - 1] + (t[t.len() - 1] - t[t.len() - 2]) / 2.0);
    e
}

/// One map: a quantity's worst case per cell, and the colour scale of its finite values.
struct Map {
    /// Per gas-pressure cell, per orifice cell; NaN where no run fell.
    cell: Vec<Vec<f64>>,
    lo: f64,
    span: f64,
    /// No cell has a finite value (then no colour bar).
    empty: bool,
}

impl Map {
    /// `which` 0: |F_r|, 1: the object's final speed.
    fn of(d: &Data, which: usize) -> Map {
        let cell: Vec<Vec<f64>> = d
            .cells
            .iter()
            .map(|col| {
                col.iter()
                    .map(|c| if which == 0 { c.0 } else { c.1 })
                    .collect()
            })
            .collect();
        let vals: Vec<f64> = cell
            .iter()
            .flatten()
            .copied()
            .filter(|v| v.is_finite())
            .collect();
        let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let span = if hi > lo { hi - lo } else { 1.0 };
        Map {
            cell,
            lo,
            span,
            empty: vals.is_empty(),
        }
    }
}

/// The map's chart: gas pressure (log) across, orifice radius up, the quantity as caption.
fn map_axes<'a, 'b>(
    plot: &'a Area<'b>,
    label: &str,
    gx: &[f64],
    oy: &[f64],
) -> Result<Chart<'a, 'b>, DrawingAreaErrorKind<std::io::Error>> {
    let mut chart = ChartBuilder::on(plot)
        .caption(label, ("sans-serif", 19))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(gx[0]..gx[gx.len() - 1], oy[0]..oy[oy.len() - 1])?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(format!(
            "{} (log)",
            quantities::label("hydraulic.gas_pressure", false)
        ))
        .y_desc(quantities::label("hydraulic.orifice_radius", false))
        .x_label_formatter(&|v| {
            let p = 10f64.powf(*v);
            if p >= 1e3 {
                format!("{:.0}k", p / 1e3)
            } else {
                format!("{p:.0}")
            }
        })
        .y_label_formatter(&|v| format!("{v:.1}"))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .draw()?;
    Ok(chart)
}

/// One rectangle per cell in the colour of its value (grey where no run fell); with few
/// cells, the value written in too.
fn draw_cells(chart: &mut Chart, map: &Map, gx: &[f64], oy: &[f64]) -> Draw<std::io::Error> {
    // n + 1 edges around n cells.
    let (n_gas, n_orifice) = (gx.len() - 1, oy.len() - 1);
    let few = n_gas * n_orifice <= 64;
    for a in 0..n_gas {
        for b in 0..n_orifice {
            let v = map.cell[a][b];
            let color = if v.is_finite() {
                viridis((v - map.lo) / map.span)
            } else {
                RGBColor(225, 225, 225)
            };
            chart.draw_series(std::iter::once(Rectangle::new(
                [(gx[a], oy[b]), (gx[a + 1], oy[b + 1])],
                color.filled(),
            )))?;
            if few && v.is_finite() {
                let u = (v - map.lo) / map.span;
                let tc = if u > 0.6 { BLACK } else { WHITE };
                chart.draw_series(std::iter::once(Text::new(
                    format!("{v:.3}"),
                    (
                        (gx[a] + gx[a + 1]) / 2.0 - (gx[a + 1] - gx[a]) * 0.3,
                        (oy[b] + oy[b + 1]) / 2.0,
                    ),
                    ("sans-serif", 12).into_font().color(&tc),
                )))?;
            }
        }
    }
    Ok(())
}

/// The colour bar beside a map, from `lo` to `lo + span`, its labels with as many digits as
/// the span needs.
fn colour_bar(bar: &Area, lo: f64, span: f64) -> Draw<std::io::Error> {
    let mut cb = ChartBuilder::on(bar)
        .margin_top(50)
        .margin_bottom(60)
        .margin_right(5)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..1.0, lo..(lo + span))?;
    let digits = if span >= 20.0 {
        0
    } else if span >= 2.0 {
        1
    } else if span >= 0.2 {
        2
    } else {
        3
    };
    cb.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_label_formatter(&|v| format!("{v:.digits$}"))
        .label_style(("sans-serif", 12))
        .draw()?;
    let steps = 64;
    cb.draw_series((0..steps).map(|k| {
        let a = lo + span * k as f64 / steps as f64;
        let b = lo + span * (k + 1) as f64 / steps as f64;
        Rectangle::new(
            [(0.0, a), (1.0, b)],
            viridis(k as f64 / (steps - 1) as f64).filled(),
        )
    }))?;
    Ok(())
}
