//! One panel of figure 3 (`figure.rs`): its y range, axes, curves, detection and brake lines,
//! and the legend column beside it.

use super::*;

/// Width in pixels of the legend column to the right of each panel.
const LEGEND_WIDTH: u32 = 240;

/// One panel of the figure: the plot on the left, its legend column on the right.
pub(super) fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &Panel,
    pts: &[TrajectoryPoint],
    (t0, t1): (f64, f64),
    summary: &Summary,
) -> io::Result<()>
where
    DB::ErrorType: 'static,
{
    let (w, _) = area.dim_in_pixel();
    let (plot_area, legend_area) = area.split_horizontally(w.saturating_sub(LEGEND_WIDTH));
    let range = y_range(panel, pts);
    let (y0, y1) = range.unwrap_or((0.0, 1.0));
    let mut chart = panel_axes(&plot_area, panel, (t0, t1), (y0, y1))?;
    let mut legend = if range.is_none() {
        draw_absent(&mut chart, panel, (t0, t1))?;
        Vec::new()
    } else {
        draw_curves(&mut chart, panel, pts, (t0, t1))?
    };
    legend.extend(draw_event_lines(&mut chart, summary, (t0, t1), (y0, y1))?);
    draw_legend(&legend_area, &legend)
}

/// Finite (min, max) of the panel's curves, padded; `None` when nothing is finite.
fn y_range(panel: &Panel, pts: &[TrajectoryPoint]) -> Option<(f64, f64)> {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for c in &panel.curves {
        for p in pts {
            let v = c.value(p);
            if v.is_finite() {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
    }
    if !lo.is_finite() {
        return None;
    }
    let span = hi - lo;
    let pad = if span > 0.0 {
        0.06 * span
    } else {
        (lo.abs() * 0.1).max(1e-3)
    };
    Some((lo - pad, hi + pad))
}

/// A panel's chart: time in ms across, the panel's quantity up.
type PanelChart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// One line of a panel's legend column.
struct LegendEntry {
    label: String,
    color: RGBColor,
    dashed: bool,
}

/// A drawing error as the figure's I/O error.
fn area_err<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> io::Error {
    io::Error::other(format!("drawing the figure: {e:?}"))
}

/// The panel's chart with its caption, axes, grid and tick labels.
fn panel_axes<'a, DB: DrawingBackend>(
    plot_area: &'a DrawingArea<DB, plotters::coord::Shift>,
    panel: &Panel,
    (t0, t1): (f64, f64),
    (y0, y1): (f64, f64),
) -> io::Result<PanelChart<'a, DB>> {
    let mut chart = ChartBuilder::on(plot_area)
        .caption(panel.caption, ("sans-serif", 17).into_font())
        .margin_left(10)
        .margin_right(15)
        .margin_top(5)
        .margin_bottom(5)
        .x_label_area_size(40)
        .y_label_area_size(75)
        .build_cartesian_2d(t0..t1, y0..y1)
        .map_err(area_err)?;
    chart
        .configure_mesh()
        .x_desc("time [ms]")
        .y_desc(panel.y_desc.as_str())
        .x_labels(12)
        .y_labels(6)
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205))
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .x_label_formatter(&|v| format_tick(*v))
        .y_label_formatter(&|v| format_tick(*v))
        .draw()
        .map_err(area_err)?;
    Ok(chart)
}

/// In place of the curves when none has a value: the panel's note (e.g. "no gas").
fn draw_absent<DB: DrawingBackend>(
    chart: &mut PanelChart<DB>,
    panel: &Panel,
    (t0, t1): (f64, f64),
) -> io::Result<()> {
    let x = t0 + 0.35 * (t1 - t0);
    chart
        .draw_series(std::iter::once(Text::new(
            panel.absent,
            (x, 0.55),
            ("sans-serif", 18)
                .into_font()
                .color(&color(FIGURE3_MARKS[1].color)),
        )))
        .map_err(area_err)?;
    Ok(())
}

/// The panel's curves, decimated to the pixels; their legend entries (a curve without any
/// value is listed as n/a, in grey).
fn draw_curves<DB: DrawingBackend>(
    chart: &mut PanelChart<DB>,
    panel: &Panel,
    pts: &[TrajectoryPoint],
    (t0, t1): (f64, f64),
) -> io::Result<Vec<LegendEntry>> {
    let mut legend = Vec::new();
    for (k, c) in panel.curves.iter().enumerate() {
        // The first curve is drawn wider, so a curve lying on it (rigid module: tool on
        // flange) still shows both.
        let width = if k == 0 && panel.curves.len() > 1 {
            3
        } else {
            2
        };
        let segments = finite_segments(c, pts);
        if segments.iter().all(|s| s.is_empty()) {
            legend.push(LegendEntry {
                label: format!("{} (n/a)", c.label),
                color: RGBColor(190, 190, 190),
                dashed: false,
            });
            continue;
        }
        let bucket = (t1 - t0) * 3.0 / (SIZE.0 - LEGEND_WIDTH - 100) as f64;
        for seg in segments.into_iter().filter(|s| !s.is_empty()) {
            let seg = decimate(&seg, bucket);
            chart
                .draw_series(LineSeries::new(seg, c.color.stroke_width(width)))
                .map_err(area_err)?;
        }
        legend.push(LegendEntry {
            label: c.label.clone(),
            color: c.color,
            dashed: false,
        });
    }
    Ok(legend)
}

/// A curve's points (time in ms, value), broken into lines where the value is absent (NaN).
fn finite_segments(c: &Curve, pts: &[TrajectoryPoint]) -> Vec<Vec<(f64, f64)>> {
    let mut segments: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
    for p in pts {
        let v = c.value(p);
        if v.is_finite() {
            segments.last_mut().unwrap().push((p.t * 1e3, v));
        } else if !segments.last().unwrap().is_empty() {
            segments.push(Vec::new());
        }
    }
    segments
}

/// Dashed vertical lines at the detection and the brake start, where they fall in the time
/// span; their legend entries.
fn draw_event_lines<DB: DrawingBackend>(
    chart: &mut PanelChart<DB>,
    summary: &Summary,
    (t0, t1): (f64, f64),
    (y0, y1): (f64, f64),
) -> io::Result<Vec<LegendEntry>> {
    let mut legend = Vec::new();
    for (t, label, color) in [
        (
            summary.t_detect,
            FIGURE3_MARKS[0].label,
            color(FIGURE3_MARKS[0].color),
        ),
        (
            summary.t_brake,
            FIGURE3_MARKS[1].label,
            color(FIGURE3_MARKS[1].color),
        ),
    ] {
        let Some(t) = t.filter(|t| t.is_finite()) else {
            continue;
        };
        let x = t * 1e3;
        if x < t0 || x > t1 {
            continue;
        }
        chart
            .draw_series(DashedLineSeries::new(
                vec![(x, y0), (x, y1)],
                7,
                5,
                color.stroke_width(2),
            ))
            .map_err(area_err)?;
        legend.push(LegendEntry {
            label: format!("{label} {}", format_ms(t)),
            color,
            dashed: true,
        });
    }
    Ok(legend)
}

/// The legend column: a sample line and the label per entry, top-aligned with the plot.
fn draw_legend<DB: DrawingBackend>(
    legend_area: &DrawingArea<DB, plotters::coord::Shift>,
    legend: &[LegendEntry],
) -> io::Result<()> {
    let font = ("sans-serif", 13).into_font().color(&BLACK);
    for (i, entry) in legend.iter().enumerate() {
        let y = 40 + 22 * i as i32;
        let style = entry.color.stroke_width(2);
        if entry.dashed {
            legend_area
                .draw(&PathElement::new(vec![(4, y), (12, y)], style))
                .map_err(area_err)?;
            legend_area
                .draw(&PathElement::new(vec![(17, y), (25, y)], style))
                .map_err(area_err)?;
        } else {
            legend_area
                .draw(&PathElement::new(vec![(4, y), (28, y)], style))
                .map_err(area_err)?;
        }
        legend_area
            .draw(&Text::new(entry.label.as_str(), (36, y - 7), font.clone()))
            .map_err(area_err)?;
    }
    Ok(())
}
