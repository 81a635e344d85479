//! How the charts name the quantities they show: a readable name, the unit on the axis and the
//! factor from SI to it (`robot.dead_time` in s is shown in ms: 1e3). The command's sweep
//! report and the Python package's charts (`cushion.plot.METRICS` and `AXES`, through the
//! extension's `QUANTITIES`) read this one table, so a quantity reads the same in both.

/// How one summary metric or scene key is shown.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quantity {
    /// The summary column or scene key.
    pub key: &'static str,
    pub name: &'static str,
    pub unit: &'static str,
    /// SI value times `factor` = the value in `unit`.
    pub factor: f64,
}

const fn q(key: &'static str, name: &'static str, unit: &'static str, factor: f64) -> Quantity {
    Quantity {
        key,
        name,
        unit,
        factor,
    }
}

/// Summary metrics (a sweep's summary columns, `cushion simulate --json`'s keys), as shown.
pub const METRICS: [Quantity; 24] = [
    q("t_detect", "detection time", "ms", 1e3),
    q("t_brake", "brake start", "ms", 1e3),
    q("peak_robot_force", "peak robot force", "N", 1.0),
    q("t_peak_robot_force", "time of peak robot force", "ms", 1e3),
    q("robot_impulse", "robot impulse", "N s", 1.0),
    q("peak_contact_force", "peak contact force", "N", 1.0),
    q("object_impacts", "tool-object impacts", "-", 1.0),
    q("forward_stop_impacts", "forward end-stop impacts", "-", 1.0),
    q("back_stop_impacts", "back end-stop impacts", "-", 1.0),
    q("object_final_velocity", "object final velocity", "m/s", 1.0),
    q(
        "object_final_momentum",
        "object final momentum",
        "kg m/s",
        1.0,
    ),
    q("object_travel", "object travel", "m", 1.0),
    q("max_stroke", "max stroke", "mm", 1e3),
    q("back_stop_hit", "back stop hit", "-", 1.0),
    q("max_gas_pressure", "max gas pressure", "Pa", 1.0),
    q("energy_residual", "energy ledger residual", "-", 1.0),
    q("stats_steps", "solver steps", "-", 1.0),
    q("stats_rejected", "rejected steps", "-", 1.0),
    q("stats_rhs_evals", "right-hand-side evaluations", "-", 1.0),
    q("stats_events", "events", "-", 1.0),
    q("stats_stiff", "stiffness flagged", "-", 1.0),
    q("stats_jacobians", "Jacobians", "-", 1.0),
    q("stats_lu_decompositions", "LU factorizations", "-", 1.0),
    q("stats_method_switches", "method switches", "-", 1.0),
];

/// Scene keys shown in other words or units than their key and SI unit.
pub const AXES: [Quantity; 9] = [
    q("module", "module", "", 1.0),
    q("robot.dead_time", "dead time DT", "ms", 1e3),
    q("robot.approach_speed", "approach speed v_max", "m/s", 1.0),
    q("hydraulic.gas_pressure", "gas pressure p10", "Pa", 1.0),
    q("hydraulic.orifice_radius", "orifice radius R_o", "mm", 1e3),
    q("hydraulic.piston_radius", "piston radius R_p", "mm", 1e3),
    q("object.mass", "object mass m_p", "kg", 1.0),
    q("tool.mass", "tool mass m_t", "kg", 1.0),
    q("stops.stroke", "stroke L", "mm", 1e3),
];

/// The metric or axis `key` as shown, if the table has it.
pub fn quantity(key: &str) -> Option<Quantity> {
    METRICS
        .iter()
        .chain(AXES.iter())
        .find(|q| q.key == key)
        .copied()
}

/// An axis label with its unit: `"peak robot force [N]"`, or with `magnitude`
/// `"|peak robot force| [N]"`; a key the table lacks is shown as it is.
pub fn label(key: &str, magnitude: bool) -> String {
    let (name, unit) = quantity(key).map_or((key, ""), |q| (q.name, q.unit));
    let text = if magnitude {
        format!("|{name}|")
    } else {
        name.to_string()
    };
    if unit.is_empty() {
        text
    } else {
        format!("{text} [{unit}]")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cushion_model::{Scene, Summary};

    #[test]
    fn every_metric_is_a_summary_column_and_every_axis_a_scene_key() {
        for m in METRICS {
            assert!(Summary::COLUMNS.contains(&m.key), "{}", m.key);
        }
        let keys = Scene::keys();
        for a in AXES {
            assert!(keys.contains(&a.key), "{}", a.key);
        }
    }

    #[test]
    fn labels() {
        assert_eq!(label("peak_robot_force", true), "|peak robot force| [N]");
        assert_eq!(label("robot.dead_time", false), "dead time DT [ms]");
        assert_eq!(label("module", false), "module");
        assert_eq!(label("no_such_key", false), "no_such_key");
        assert_eq!(quantity("max_stroke").map(|q| q.factor), Some(1e3));
    }
}
