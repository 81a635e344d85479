"""cushion.plot: every figure is drawn from real runs and sweeps, written as a PNG, and its
numbers (marker positions, medians, worst-case cells) are checked against the summary or an
independent pandas computation."""

import os
import re

os.environ["MPLBACKEND"] = "Agg"  # headless: set before matplotlib is imported

import subprocess
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest

import cushion
import cushion.plot as cplot
from cushion._run import COLUMNS

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "sweeps" / "scenes"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def assert_png(path: Path, min_kb: float = 15) -> None:
    """A real PNG of some substance: the file's signature, and more than ``min_kb`` kB."""
    data = Path(path).read_bytes()
    assert data[:8] == PNG_MAGIC, f"{path} is not a PNG"
    assert len(data) > min_kb * 1024, f"{path} is only {len(data)} bytes"


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def hydraulic():
    return cushion.simulate(SCENES / "paper-hydraulic-dt70.toml")


@pytest.fixture(scope="module")
def bistable():
    return cushion.simulate(SCENES / "paper-bistable-dt10.toml")


@pytest.fixture(scope="module")
def grid():
    """Dead time (5 values) x object mass (4) x module (2): 4 runs per dead time and module,
    so medians and quartiles are not single values."""
    return cushion.sweep(
        {
            "name": "plot-grid",
            "scene": str(SCENES / "paper-hydraulic-dt70.toml"),
            "sampling": {"mode": "grid"},
            "axis": [
                {"key": "robot.dead_time", "linspace": [0.0, 0.1, 5]},
                {"key": "object.mass", "values": [0.1, 0.3, 0.6, 1.0]},
                {"key": "module", "values": ["hydraulic", "bistable"]},
            ],
        },
        progress=False,
    )


@pytest.fixture(scope="module")
def design_grid():
    """Gas pressure (4, log) x orifice radius (3) x object mass (3): 3 runs per cell."""
    return cushion.sweep(
        {
            "name": "plot-design-grid",
            "scene": str(SCENES / "paper-hydraulic-dt70.toml"),
            "sampling": {"mode": "grid"},
            "axis": [
                {"key": "hydraulic.gas_pressure", "logspace": [300.0, 1e5, 4]},
                {"key": "hydraulic.orifice_radius", "values": [0.005, 0.008, 0.011]},
                {"key": "object.mass", "values": [0.1, 0.5, 1.0]},
            ],
        },
        progress=False,
    )


@pytest.fixture(scope="module")
def sobol():
    """The design question's four axes, 512 Sobol samples (many distinct values per axis)."""
    return cushion.sweep(
        {
            "name": "plot-sobol",
            "scene": str(SCENES / "paper-hydraulic-dt70.toml"),
            "sampling": {"mode": "sobol", "samples": 512, "seed": 3},
            "axis": [
                {"key": "hydraulic.gas_pressure", "range": [300.0, 1e5], "scale": "log"},
                {"key": "hydraulic.orifice_radius", "range": [0.002, 0.012]},
                {"key": "object.mass", "range": [0.05, 1.0]},
                {"key": "robot.dead_time", "range": [0.0, 0.1]},
            ],
        },
        progress=False,
    )


def mark_x(ax, name):
    """The x positions (ms) of the vertical marker line ``name`` in ``ax``."""
    lines = [ln for ln in ax.lines if ln.get_gid() == name]
    assert len(lines) == 1, f"expected one {name!r} line, found {len(lines)}"
    return np.asarray(lines[0].get_xdata(), dtype=float)


# ---------------------------------------------------------------------------------------------
# run: the paper's figure 3
# ---------------------------------------------------------------------------------------------


def test_run_draws_four_panels_with_detection_and_brake_on_each(hydraulic, tmp_path):
    path = tmp_path / "fig3.png"
    fig = cplot.run(hydraulic, path=path, title="hydraulic, dead time 70 ms")
    assert_png(path)
    panels = [ax for ax in fig.axes if ax.get_ylabel()]
    assert [ax.get_title(loc="left") for ax in panels] == ["Positions", "Velocities", "Gas pressure", "Forces"]
    t_detect, t_brake = hydraulic.summary["t_detect"], hydraulic.summary["t_brake"]
    for ax in panels:
        np.testing.assert_allclose(mark_x(ax, "detection"), t_detect * 1e3, rtol=1e-12)
        np.testing.assert_allclose(mark_x(ax, "brake start"), t_brake * 1e3, rtol=1e-12)
    assert panels[-1].get_xlabel() == "time [ms]"
    # Gas pressure panel in kPa: its curve is p1 / 1000.
    gas = panels[2].lines[0]
    np.testing.assert_allclose(gas.get_ydata(), hydraulic.p1 * 1e-3)
    assert "[kPa]" in panels[2].get_ylabel()


def test_run_and_the_commands_svg_draw_the_same_layout(hydraulic, cli, tmp_path):
    """Figure 3 in matplotlib and the command's SVG come from one layout (the extension's
    FIGURE3): the same panels, y labels, curves and colours, the math text aside."""
    from matplotlib.colors import to_hex

    from cushion._cushion import FIGURE3

    svg_path = tmp_path / "fig3.svg"
    done = cli("simulate", str(SCENES / "paper-hydraulic-dt70.toml"), "--plot", str(svg_path))
    assert done.returncode == 0, done.stderr
    svg = svg_path.read_text().lower()
    texts = {t.strip() for t in re.findall(r"<text[^>]*>(.*?)</text>", svg_path.read_text(), flags=re.S)}
    fig = cplot.run(hydraulic)
    panels = [ax for ax in fig.axes if ax.get_ylabel()]
    assert [ax.get_title(loc="left") for ax in panels] == [p["title"] for p in FIGURE3]
    plain = lambda text: text.replace("$", "")  # noqa: E731
    for ax, spec in zip(panels, FIGURE3):
        assert plain(ax.get_ylabel()) in texts, ax.get_ylabel()
        drawn = [ln for ln in ax.lines if ln.get_gid() is None]
        assert [plain(ln.get_label()) for ln in drawn] == [f"{c['name']} {c['symbol']}" for c in spec["curves"]]
        assert [to_hex(ln.get_color()) for ln in drawn] == [c["color"] for c in spec["curves"]]
        for c in spec["curves"]:
            assert f"{c['name']} {c['symbol']}" in texts
            np.testing.assert_allclose(drawn[spec["curves"].index(c)].get_ydata(), getattr(hydraulic, c["column"]) * spec["factor"])
            assert c["color"] in svg


def test_run_method_writes_the_same_figure(hydraulic, tmp_path):
    path = tmp_path / "method.png"
    fig = hydraulic.plot(path)
    assert_png(path)
    assert len(fig.axes) == 4


def test_run_of_a_bistable_run_leaves_out_the_gas_panel_and_says_so(bistable, tmp_path):
    assert np.isnan(bistable.p1).all()
    path = tmp_path / "bistable.png"
    fig = cplot.run(bistable, path=path)
    assert_png(path)
    assert len(fig.axes) == 3
    assert not any("gas" in ax.get_ylabel() for ax in fig.axes)
    assert "no gas" in fig.get_suptitle()


def test_run_of_a_recorded_run_without_summary_marks_the_sensor_and_brake_events(hydraulic, tmp_path):
    ev = hydraulic.events
    events = {"t": ev["t"].to_numpy(), "event": list(ev["event"])}
    events.update({c: ev[c].to_numpy() for c in COLUMNS[1:]})
    columns = {c: getattr(hydraulic, c).copy() for c in COLUMNS}
    recorded = cushion.Run(None, columns, events)
    assert recorded.summary is None
    path = tmp_path / "recorded.png"
    fig = cplot.run(recorded, path=path)
    assert_png(path)
    sensor = ev.loc[ev["event"] == "sensor", "t"].iloc[0]
    brake = ev.loc[ev["event"] == "brake", "t"].iloc[0]
    for ax in fig.axes:
        np.testing.assert_allclose(mark_x(ax, "detection"), sensor * 1e3)
        np.testing.assert_allclose(mark_x(ax, "brake start"), brake * 1e3)
    # The sensor event is the summary's detection, to rounding.
    assert sensor == pytest.approx(hydraulic.summary["t_detect"], rel=1e-12)
    assert fig.get_suptitle() == "recorded run"


def test_run_t_max_ends_the_time_axis_and_fits_the_y_limits_to_what_is_shown(hydraulic):
    fig = cplot.run(hydraulic, t_max=0.05)
    positions = fig.axes[0]
    assert positions.get_xlim() == pytest.approx((0.0, 50.0))
    # Up to 50 ms the object has moved some 50 mm, not the ~320 mm of the whole run.
    assert positions.get_ylim()[1] < 100.0


def test_run_draws_into_a_given_figure(hydraulic):
    fig = plt.figure()
    assert cplot.run(hydraulic, fig=fig) is fig
    assert len(fig.axes) == 4


def test_run_without_trajectory_is_an_error():
    summary_only = cushion.simulate(trajectory=False)
    with pytest.raises(ValueError, match="trajectory"):
        cplot.run(summary_only)


# ---------------------------------------------------------------------------------------------
# compare: figures 4-6
# ---------------------------------------------------------------------------------------------


def test_compare_shares_each_rows_limits_and_marks_each_runs_times(hydraulic, bistable, tmp_path):
    path = tmp_path / "compare.png"
    fig = cplot.compare(hydraulic, bistable, path=path, title="compare")
    assert_png(path)
    axes = np.array([ax for ax in fig.axes if ax.get_xlabel() or ax.get_ylabel() or ax.lines]).reshape(2, 2)
    for row in range(2):
        assert axes[row, 0].get_ylim() == axes[row, 1].get_ylim()
    # The shared force row holds both peaks.
    lo, hi = axes[1, 0].get_ylim()
    for r in (hydraulic, bistable):
        assert lo <= r.summary["peak_robot_force"] <= hi
    for col, r in enumerate((hydraulic, bistable)):
        for row in range(2):
            np.testing.assert_allclose(mark_x(axes[row, col], "detection"), r.summary["t_detect"] * 1e3)
            np.testing.assert_allclose(mark_x(axes[row, col], "brake start"), r.summary["t_brake"] * 1e3)
    assert axes[0, 0].get_title().startswith("hydraulic: peak")
    assert axes[0, 1].get_title().startswith("bistable: peak")
    assert axes[1, 0].get_ylabel() == "force on the robot $F_r$ [N]"


# ---------------------------------------------------------------------------------------------
# metric_vs_axis
# ---------------------------------------------------------------------------------------------


def median_lines(ax):
    return {ln.get_gid().removeprefix("median "): ln for ln in ax.lines if (ln.get_gid() or "").startswith("median ")}


def test_metric_vs_axis_medians_equal_pandas_medians_per_axis_value(grid, tmp_path):
    # A failed run with an absurd value must be left out.
    failed = grid.iloc[[0]].copy()
    failed["status"] = "max_steps"
    failed["object_final_velocity"] = 1e6
    frame = pd.concat([grid, failed], ignore_index=True)
    path = tmp_path / "speed-vs-dt.png"
    fig = cplot.metric_vs_axis(frame, "object_final_velocity", "robot.dead_time", by="module", path=path)
    assert_png(path)
    ax = fig.axes[0]
    lines = median_lines(ax)
    assert list(lines) == ["hydraulic", "bistable"]  # the paper's order
    expected = grid.groupby(["module", "robot.dead_time"])["object_final_velocity"].median()
    for module, line in lines.items():
        want = expected[module]
        np.testing.assert_allclose(line.get_xdata(), want.index.to_numpy() * 1e3)  # dead time in ms
        np.testing.assert_allclose(line.get_ydata(), want.to_numpy(), rtol=1e-12)
    assert ax.get_xscale() == "linear"
    assert ax.get_xlabel() == "dead time DT [ms]"
    assert ax.get_ylabel() == "object final velocity [m/s]"
    assert "1 failed runs left out" in ax.get_title()
    # The quartile bands: one per module, spanning the pandas quartiles.
    q1 = grid.groupby(["module", "robot.dead_time"])["object_final_velocity"].quantile(0.25)
    band = ax.collections[0].get_paths()[0].vertices[:, 1]
    assert band.min() == pytest.approx(q1["hydraulic"].min(), rel=1e-12)


def test_metric_vs_axis_magnitude_plots_the_size_of_a_signed_force(grid):
    fig = cplot.metric_vs_axis(grid, "peak_robot_force", "object.mass", magnitude=True)
    ax = fig.axes[0]
    (line,) = median_lines(ax).values()
    want = grid.groupby("object.mass")["peak_robot_force"].apply(lambda v: v.abs().median())
    np.testing.assert_allclose(line.get_ydata(), want.to_numpy())
    assert ax.get_ylabel() == "|peak robot force| [N]"


def test_metric_vs_axis_bins_many_values_and_uses_log_x_only_for_log_spread_axes(sobol, tmp_path):
    fig, (left, right) = plt.subplots(1, 2)
    cplot.metric_vs_axis(sobol, "peak_robot_force", "hydraulic.gas_pressure", by="object.mass", ax=left, magnitude=True)
    cplot.metric_vs_axis(sobol, "object_final_velocity", "robot.dead_time", ax=right, path=tmp_path / "two.png")
    assert_png(tmp_path / "two.png")
    assert left.get_xscale() == "log"  # 300 Pa to 100 kPa, drawn in log
    assert right.get_xscale() == "linear"  # 0 to 100 ms, drawn evenly (its smallest draw is tiny)
    lines = median_lines(left)
    assert len(lines) == 4  # object mass cut into four classes
    for line in lines.values():
        assert 8 <= len(line.get_xdata()) <= 12  # about 12 quantile bins
    (line,) = median_lines(right).values()
    assert len(line.get_xdata()) == 12
    # Quantile bins of equal counts: the medians per bin, recomputed with pandas.
    bins = pd.qcut(sobol["robot.dead_time"], 12, labels=False)
    want = sobol.groupby(bins)["object_final_velocity"].median().to_numpy()
    np.testing.assert_allclose(line.get_ydata(), want)


# ---------------------------------------------------------------------------------------------
# heatmap
# ---------------------------------------------------------------------------------------------


def test_heatmap_worst_cells_equal_a_pandas_groupby(design_grid, tmp_path):
    path = tmp_path / "heatmap.png"
    fig = cplot.heatmap(design_grid, "peak_robot_force", "hydraulic.gas_pressure", "hydraulic.orifice_radius", path=path)
    assert_png(path)
    ax = fig.axes[0]
    cells = ax.collections[0].get_array()
    want = (
        design_grid.assign(f=design_grid["peak_robot_force"].abs())
        .groupby(["hydraulic.orifice_radius", "hydraulic.gas_pressure"])["f"]
        .max()
        .unstack()  # rows: orifice radius (y), columns: gas pressure (x)
    )
    assert cells.shape == want.shape == (3, 4)
    np.testing.assert_allclose(np.asarray(cells), want.to_numpy(), rtol=1e-12)
    assert ax.get_xscale() == "log"
    assert ax.get_xlabel() == "gas pressure p10 [Pa]"
    assert ax.get_ylabel() == "orifice radius R_o [mm]"
    colorbar = fig.axes[1]
    assert colorbar.get_ylabel() == "max |peak robot force| [N]"
    # 12 cells: each shows its value.
    assert len(ax.texts) == 12


def test_heatmap_other_reductions(design_grid):
    for reduce, how in (("median", "median"), ("min", "min"), ("max", "max")):
        fig = cplot.heatmap(design_grid, "max_stroke", "hydraulic.gas_pressure", "hydraulic.orifice_radius", reduce=reduce)
        cells = np.asarray(fig.axes[0].collections[0].get_array())
        want = design_grid.groupby(["hydraulic.orifice_radius", "hydraulic.gas_pressure"])["max_stroke"].agg(how).unstack()
        np.testing.assert_allclose(cells, want.to_numpy() * 1e3, rtol=1e-12)  # shown in mm
        assert fig.axes[1].get_ylabel() == f"{reduce} max stroke [mm]"


def test_heatmap_bins_continuous_axes_and_keeps_the_worst_run(sobol, tmp_path):
    path = tmp_path / "sobol-heatmap.png"
    fig = cplot.heatmap(sobol, "object_final_velocity", "hydraulic.gas_pressure", "hydraulic.orifice_radius", bins=6, path=path)
    assert_png(path)
    cells = fig.axes[0].collections[0].get_array()
    assert cells.shape == (6, 6)
    assert cells.max() == pytest.approx(sobol["object_final_velocity"].abs().max(), rel=1e-12)
    assert cells.min() >= sobol["object_final_velocity"].abs().min()
    # Log-spaced gas pressure cells: equal widths in log10 from the smallest to the largest draw.
    edges = fig.axes[0].collections[0].get_coordinates()[0, :, 0]
    p = sobol["hydraulic.gas_pressure"]
    np.testing.assert_allclose(np.log10(edges), np.linspace(np.log10(p.min()), np.log10(p.max()), 7))


def test_heatmap_refuses_an_unknown_reduction(design_grid):
    with pytest.raises(ValueError, match="reduce"):
        cplot.heatmap(design_grid, "peak_robot_force", "hydraulic.gas_pressure", "hydraulic.orifice_radius", reduce="mean")


# ---------------------------------------------------------------------------------------------
# names, units, backend
# ---------------------------------------------------------------------------------------------


def test_units_and_labels():
    assert cplot.quantity("robot.dead_time") == ("dead time DT", "ms", 1e3)
    assert cplot.label("peak_robot_force") == "peak robot force [N]"
    assert cplot.label("peak_robot_force", magnitude=True) == "|peak robot force| [N]"
    assert cplot.label("hydraulic.orifice_radius") == "orifice radius R_o [mm]"
    # Keys not in AXES take their SI unit from cushion.keys().
    assert cplot.quantity("tool.viscous_friction") == ("tool.viscous_friction", "kg/s", 1.0)
    # Every summary field of a run is known.
    run = cushion.simulate(trajectory=False)
    assert set(run.summary) - {"status", "message", "stats"} <= set(cplot.METRICS)


def _backend_in_fresh_python(env_backend):
    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}
    if env_backend:
        env["MPLBACKEND"] = env_backend
    code = "import cushion.plot, matplotlib; print(matplotlib.get_backend())"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    return out.stdout.strip().lower()


def test_agg_is_chosen_only_when_no_backend_is_set():
    assert _backend_in_fresh_python(None) == "agg"
    assert _backend_in_fresh_python("svg") == "svg"
