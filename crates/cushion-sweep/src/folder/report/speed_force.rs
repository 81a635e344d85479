//! `report-speed-force.svg`: object final speed and peak robot force |F_r| against dead time,
//! one colour per module, median and range per dead-time group (see `report.rs`).

use super::*;
use crate::quantities::label;

/// One of the two charts side by side.
struct Panel {
    /// 0: the object's final speed, 1: |F_r|.
    which: usize,
    /// The summary metric, shown by its size.
    metric: &'static str,
    caption: &'static str,
    /// Digits of the y labels.
    ydigits: usize,
}

const PANELS: [Panel; 2] = [
    Panel {
        which: 0,
        metric: "object_final_velocity",
        caption: "Object final speed",
        ydigits: 2,
    },
    Panel {
        which: 1,
        metric: "peak_robot_force",
        caption: "Peak robot force",
        ydigits: 0,
    },
];

pub(super) fn speed_force(path: &Path, d: &Data) -> Draw<std::io::Error> {
    let root = SVGBackend::new(path, (1200, 520)).into_drawing_area();
    root.fill(&WHITE)?;
    let left_out = d.total - d.ok;
    let title = format!(
        "Object final speed and peak robot force against dead time ({} runs{})",
        d.ok,
        if left_out > 0 {
            format!(", {left_out} failed runs left out")
        } else {
            String::new()
        }
    );
    let (top, body) = root.split_vertically(50);
    top.titled(&title, ("sans-serif", 24))?;
    let (left, right) = body.split_horizontally(600);
    // More runs than one per module and dead-time group on average: their spread is drawn too.
    let several = d.dt.centres.len() < d.ok / d.modules.len().max(1);
    for (area, panel) in [&left, &right].into_iter().zip(&PANELS) {
        let stats = group_stats(d, panel.which, several);
        let mut chart = panel_axes(area, panel, &stats, &d.dt.centres, several)?;
        draw_modules(&mut chart, &stats, several)?;
        draw_legend(&mut chart)?;
    }
    root.present()?;
    Ok(())
}

/// Per module, per dead-time group with values: (x, min, median, max, lower quartile, upper
/// quartile) of quantity `which`.
fn group_stats(d: &Data, which: usize, several: bool) -> BTreeMap<&str, Vec<GroupStats>> {
    let centres = &d.dt.centres;
    let modules = &d.modules;
    let mut stats: BTreeMap<&str, Vec<GroupStats>> = BTreeMap::new();
    // Modules side by side around each group's dead time, so their bars do not overlap.
    let gap = if centres.len() > 1 {
        (centres[1] - centres[0]) * 1e3
    } else {
        10.0
    };
    let dodge = |k: usize| (k as f64 - (modules.len() as f64 - 1.0) / 2.0) * gap * 0.18;
    for (k, m) in modules.iter().enumerate() {
        let s = d.sf[m]
            .iter()
            .enumerate()
            .map(|(g, accs)| (g, if which == 0 { &accs.0 } else { &accs.1 }))
            .filter(|(_, a)| !a.is_empty())
            .map(|(g, a)| {
                let mut v = a.sample.clone();
                if v.is_empty() {
                    v.push(0.5 * (a.min + a.max));
                }
                let md = median(&mut v); // sorts v
                let q = |p: f64| v[((v.len() - 1) as f64 * p).round() as usize];
                let x = centres[g] * 1e3 + if several { dodge(k) } else { 0.0 };
                (x, a.min, md, a.max, q(0.25), q(0.75))
            })
            .collect();
        stats.insert(m.as_str(), s);
    }
    stats
}

/// The panel's chart: dead time in ms across (the groups' span, padded), the quantity up from
/// zero with head room for the legend.
fn panel_axes<'a, 'b>(
    area: &'a Area<'b>,
    panel: &Panel,
    stats: &BTreeMap<&str, Vec<GroupStats>>,
    centres: &[f64],
    several: bool,
) -> Result<Chart<'a, 'b>, DrawingAreaErrorKind<std::io::Error>> {
    let ymax = stats
        .values()
        .flatten()
        .map(|s| s.3)
        .fold(0.0f64, f64::max)
        .max(1e-9)
        * 1.3; // head room for the legend
    let (x0, x1) = (
        centres.first().copied().unwrap_or(0.0) * 1e3,
        centres.last().copied().unwrap_or(0.1) * 1e3,
    );
    let pad = ((x1 - x0) * 0.05).max(1.0);
    let caption = panel.caption;
    let mut chart = ChartBuilder::on(area)
        .caption(
            if several {
                format!("{caption} (median; bars: quartiles, min..max)")
            } else {
                caption.to_string()
            },
            ("sans-serif", 20),
        )
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d((x0 - pad)..(x1 + pad), 0.0..ymax)?;
    let ydigits = panel.ydigits;
    chart
        .configure_mesh()
        .x_desc(label("robot.dead_time", false))
        .y_desc(label(panel.metric, true))
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.ydigits$}"))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 16))
        .bold_line_style(RGBColor(225, 225, 225))
        .light_line_style(WHITE)
        .draw()?;
    Ok(chart)
}

/// Per module in its colour: the medians as a line with markers (with a legend entry), and
/// with `several` runs per group, the range and quartiles as bars behind them.
fn draw_modules(
    chart: &mut Chart,
    stats: &BTreeMap<&str, Vec<GroupStats>>,
    several: bool,
) -> Draw<std::io::Error> {
    for (m, s) in stats {
        let color = module_color(m);
        if several {
            chart.draw_series(s.iter().map(|(x, lo, _, hi, _, _)| {
                PathElement::new(vec![(*x, *lo), (*x, *hi)], color.mix(0.5).stroke_width(1))
            }))?;
            chart.draw_series(s.iter().map(|(x, _, _, _, q1, q3)| {
                PathElement::new(vec![(*x, *q1), (*x, *q3)], color.mix(0.55).stroke_width(6))
            }))?;
        }
        chart
            .draw_series(LineSeries::new(
                s.iter().map(|t| (t.0, t.2)),
                color.stroke_width(2),
            ))?
            .label(m.to_string())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 22, y)], color.stroke_width(3))
            });
        chart.draw_series(s.iter().map(|t| Circle::new((t.0, t.2), 4, color.filled())))?;
    }
    Ok(())
}

/// The modules' legend, top left, over the chart.
fn draw_legend<'a, 'b: 'a>(chart: &mut Chart<'a, 'b>) -> Draw<std::io::Error> {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(180, 180, 180))
        .label_font(("sans-serif", 15))
        .draw()
}
