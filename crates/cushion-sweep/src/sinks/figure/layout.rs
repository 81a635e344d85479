//! What figure 3 draws, as data: its panels, the trajectory columns each one plots, their units,
//! labels and colours, and the two event lines. The command's SVG (`figure.rs`) and
//! `cushion.plot.run` in Python (through the extension's `FIGURE3` and `FIGURE3_MARKS`) both
//! draw from this table, so the two figures show the same things in the same units and colours.

/// One curve of a panel: a column of the trajectory (`TrajectoryPoint::COLUMNS`).
#[derive(Clone, Copy, Debug)]
pub struct CurveSpec {
    pub column: &'static str,
    /// What it is, in words ("robot flange").
    pub name: &'static str,
    /// Its symbol, with `_` before a subscript ("x_r"; Python sets it as math text).
    pub symbol: &'static str,
    /// `#rrggbb`.
    pub color: &'static str,
}

/// One panel: a quantity over time, in one unit.
#[derive(Clone, Copy, Debug)]
pub struct PanelSpec {
    pub title: &'static str,
    /// The y axis' quantity in words, and its symbol ("" when the curves' differ).
    pub quantity: &'static str,
    pub symbol: &'static str,
    pub unit: &'static str,
    /// SI value times `factor` = the value in `unit`.
    pub factor: f64,
    pub curves: &'static [CurveSpec],
    /// Shown instead of the curves when none has a finite value (a scene without gas).
    pub absent: &'static str,
}

/// A dashed vertical line at an instant of the run's summary.
#[derive(Clone, Copy, Debug)]
pub struct MarkSpec {
    /// The summary's field (`t_detect`, `t_brake`).
    pub field: &'static str,
    pub label: &'static str,
    pub color: &'static str,
}

const ROBOT: &str = "#1f77b4";
const TOOL: &str = "#ff7f0e";
const OBJECT: &str = "#2ca02c";
const CONTACT: &str = "#9467bd";

const fn curve(
    column: &'static str,
    name: &'static str,
    symbol: &'static str,
    color: &'static str,
) -> CurveSpec {
    CurveSpec {
        column,
        name,
        symbol,
        color,
    }
}

/// The paper's figure 3, top to bottom.
pub const FIGURE3: [PanelSpec; 4] = [
    PanelSpec {
        title: "Positions",
        quantity: "position",
        symbol: "",
        unit: "mm",
        factor: 1e3,
        curves: &[
            curve("x_r", "robot flange", "x_r", ROBOT),
            curve("x_t", "tool", "x_t", TOOL),
            curve("x_p", "object", "x_p", OBJECT),
        ],
        absent: "no positions",
    },
    PanelSpec {
        title: "Velocities",
        quantity: "velocity",
        symbol: "",
        unit: "m/s",
        factor: 1.0,
        curves: &[
            curve("v_r", "robot flange", "v_r", ROBOT),
            curve("v_t", "tool", "v_t", TOOL),
            curve("v_p", "object", "v_p", OBJECT),
        ],
        absent: "no velocities",
    },
    PanelSpec {
        title: "Gas pressure",
        quantity: "gas pressure",
        symbol: "p_1",
        unit: "kPa",
        factor: 1e-3,
        curves: &[curve("p1", "gas pressure", "p_1", ROBOT)],
        absent: "no gas in this scene (n/a)",
    },
    PanelSpec {
        title: "Forces",
        quantity: "force",
        symbol: "",
        unit: "N",
        factor: 1.0,
        curves: &[
            curve("F_r", "force on the robot", "F_r", ROBOT),
            curve("F_c", "contact force tool-object", "F_c", CONTACT),
        ],
        absent: "no forces",
    },
];

/// The detection (sensor switching) and the brake start.
pub const FIGURE3_MARKS: [MarkSpec; 2] = [
    MarkSpec {
        field: "t_detect",
        label: "detection",
        color: "#d62728",
    },
    MarkSpec {
        field: "t_brake",
        label: "brake start",
        color: "#6e6e6e",
    },
];

impl CurveSpec {
    /// The legend's text: name and symbol ("robot flange x_r").
    pub fn label(&self) -> String {
        format!("{} {}", self.name, self.symbol)
    }
}

impl PanelSpec {
    /// The y axis' text: quantity, symbol and unit ("gas pressure p_1 [kPa]").
    pub fn y_label(&self) -> String {
        if self.symbol.is_empty() {
            format!("{} [{}]", self.quantity, self.unit)
        } else {
            format!("{} {} [{}]", self.quantity, self.symbol, self.unit)
        }
    }
}

/// `#rrggbb` as its three channels.
pub fn rgb(hex: &str) -> (u8, u8, u8) {
    let channel = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).unwrap_or(0);
    (channel(1), channel(3), channel(5))
}

#[cfg(test)]
mod tests {
    use super::*;
    use cushion_model::TrajectoryPoint;

    #[test]
    fn every_curve_is_a_trajectory_column_and_every_colour_parses() {
        for panel in FIGURE3 {
            for c in panel.curves {
                assert!(TrajectoryPoint::COLUMNS.contains(&c.column), "{}", c.column);
                assert_eq!(c.color.len(), 7, "{}", c.color);
                let (r, g, b) = rgb(c.color);
                assert_eq!(format!("#{r:02x}{g:02x}{b:02x}"), c.color);
            }
        }
        assert_eq!(rgb("#d62728"), (214, 39, 40));
        assert_eq!(FIGURE3[2].y_label(), "gas pressure p_1 [kPa]");
        assert_eq!(FIGURE3[0].y_label(), "position [mm]");
        assert_eq!(
            FIGURE3[3].curves[1].label(),
            "contact force tool-object F_c"
        );
    }
}
