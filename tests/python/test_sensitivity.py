"""cushion.sensitivity: the same long frame as `cushion sensitivity`'s sensitivity.parquet (in
memory or with out=), SALib's own estimators on the engine's saltelli sample and outputs giving
the engine's point estimates to 1e-10 (the intervals only statistically), the chart drawn, and
bad input raising ConfigError before any run."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import cushion
import cushion.plot
from conftest import ROOT

SCENE = str(ROOT / "sweeps" / "scenes" / "paper-hydraulic-dt70.toml")
INPUTS = ["robot.dead_time", "hydraulic.gas_pressure", "hydraulic.orifice_radius", "object.mass"]
RESAMPLES = 400


def study_dict(samples: int = 32, second_order: bool = True, **sensitivity) -> dict:
    return {
        "name": "small",
        "scene": SCENE,
        "set": {"solver.rtol": 1e-6},
        "sampling": {"mode": "saltelli", "samples": samples, "second_order": second_order, "seed": 1},
        "axis": [
            {"key": INPUTS[0], "range": [0.0, 0.1]},
            {"key": INPUTS[1], "range": [300.0, 1e5], "dist": "loguniform"},
            {"key": INPUTS[2], "range": [0.002, 0.012]},
            {"key": INPUTS[3], "range": [0.05, 1.0], "dist": "triangular", "mode": 0.25},
        ],
        "sensitivity": {"resamples": RESAMPLES, **sensitivity},
    }


def write_toml(path, q: dict) -> None:
    s = q["sampling"]
    lines = [f'name = "{q["name"]}"', f'scene = "{q["scene"]}"', "[set]", '"solver.rtol" = 1e-6', "[sampling]"]
    lines += ['mode = "saltelli"', f"samples = {s['samples']}", f"second_order = {str(s['second_order']).lower()}", f"seed = {s['seed']}"]
    for a in q["axis"]:
        lines += ["[[axis]]", f'key = "{a["key"]}"', f"range = {a['range']!r}"]
        if "dist" in a:
            lines.append(f'dist = "{a["dist"]}"')
        if "mode" in a:
            lines.append(f"mode = {a['mode']!r}")
    lines += ["[sensitivity]", f"resamples = {q['sensitivity']['resamples']}"]
    path.write_text("\n".join(lines) + "\n")


@pytest.fixture(scope="module")
def studied(tmp_path_factory, cli):
    tmp = tmp_path_factory.mktemp("sensitivity")
    f = tmp / "small.toml"
    write_toml(f, study_dict())
    cli("sensitivity", f, "--out", tmp / "cli", "--threads", "2", "--quiet")
    frame = cushion.sensitivity(f, threads=1, progress=False, out=tmp / "py")
    return tmp, f, frame


def test_the_frame_equals_the_commands_file(studied):
    tmp, f, frame = studied
    theirs = pd.read_parquet(tmp / "cli" / "sensitivity.parquet")
    pd.testing.assert_frame_equal(frame, theirs)
    pd.testing.assert_frame_equal(pd.read_parquet(tmp / "py" / "sensitivity.parquet"), theirs)
    # In memory, from the file or from a dict of its shape: the same frame.
    pd.testing.assert_frame_equal(cushion.sensitivity(f, progress=False), theirs)
    pd.testing.assert_frame_equal(cushion.sensitivity(study_dict(), threads=2, progress=False), theirs)
    assert list(frame.columns) == ["output", "input", "input_1", "input_2", "index", "value", "conf"]
    assert set(frame["index"]) <= {"S1", "ST", "S2", "constant", "not_finite"}
    for f_ in ("summary.parquet", "provenance.json", "sensitivity.csv", "sensitivity.svg"):
        assert (tmp / "py" / f_).exists()


def test_outputs_chooses_what_is_analysed(studied):
    _, f, frame = studied
    some = cushion.sensitivity(f, outputs=["peak_robot_force", "max_stroke"], progress=False)
    assert list(dict.fromkeys(some["output"])) == ["peak_robot_force", "max_stroke"]
    pd.testing.assert_frame_equal(
        some.reset_index(drop=True),
        frame[frame["output"].isin(["peak_robot_force", "max_stroke"])].reset_index(drop=True),
    )


def salib_problem() -> dict:
    # The bounds do not enter the estimators: SALib's analyze reads Y only.
    return {"num_vars": 4, "names": INPUTS, "bounds": [[0.0, 1.0]] * 4}


def compare_with_salib(frame: pd.DataFrame, summary: pd.DataFrame, second_order: bool) -> int:
    from SALib.analyze import sobol

    analysed = 0
    conf_ratios = []
    for output, f in frame.groupby("output", sort=False):
        if not (f["index"] == "ST").any():
            continue
        y = summary[output].to_numpy(dtype=float)
        r = sobol.analyze(
            salib_problem(),
            y,
            calc_second_order=second_order,
            num_resamples=RESAMPLES,
            conf_level=0.95,
            print_to_console=False,
            seed=7,
        )
        s1 = f[f["index"] == "S1"].set_index("input").loc[INPUTS]
        st = f[f["index"] == "ST"].set_index("input").loc[INPUTS]
        np.testing.assert_allclose(s1["value"], r["S1"], rtol=0, atol=1e-10, err_msg=f"{output} S1")
        np.testing.assert_allclose(st["value"], r["ST"], rtol=0, atol=1e-10, err_msg=f"{output} ST")
        conf_ratios += list(st["conf"] / r["ST_conf"]) + list(s1["conf"] / r["S1_conf"])
        s2 = f[f["index"] == "S2"]
        if second_order:
            assert len(s2) == 6
            for _, row in s2.iterrows():
                j, k = INPUTS.index(row["input_1"]), INPUTS.index(row["input_2"])
                assert j < k
                assert abs(row["value"] - r["S2"][j, k]) <= 1e-10, f"{output} S2 {j}{k}"
        else:
            assert s2.empty
        analysed += 1
    # The intervals: other random draws, the same spread. Their ratio to SALib's scatters
    # around 1; its median stays well inside [0.75, 1.33] at 400 resamples.
    ratios = np.array([x for x in conf_ratios if np.isfinite(x) and x > 0])
    assert 0.75 < np.median(ratios) < 1.33, np.median(ratios)
    return analysed


def test_salib_gives_the_engines_point_estimates(studied):
    tmp, _, frame = studied
    summary = pd.read_parquet(tmp / "cli" / "summary.parquet")
    assert len(summary) == 32 * 10
    assert compare_with_salib(frame, summary, second_order=True) >= 5


def test_salib_agrees_without_second_order(tmp_path):
    q = study_dict(samples=16, second_order=False)
    frame = cushion.sensitivity(q, progress=False, out=tmp_path / "first")
    summary = pd.read_parquet(tmp_path / "first" / "summary.parquet")
    assert len(summary) == 16 * 6
    assert compare_with_salib(frame, summary, second_order=False) >= 5


def test_drop_base_point_equals_salib_on_the_kept_blocks(tmp_path):
    # A step limit only the runs with the most steps reach: some base points hold a failed run.
    q = study_dict(on_failed="drop_base_point")
    q["set"]["solver.max_steps"] = 350
    frame = cushion.sensitivity(q, progress=False, out=tmp_path / "dropped")
    summary = pd.read_parquet(tmp_path / "dropped" / "summary.parquet")
    block = 2 * len(INPUTS) + 2
    failed = (summary["status"] != "ok").to_numpy().reshape(-1, block).any(axis=1)
    assert 0 < failed.sum() < len(failed) // 2
    kept = summary[np.repeat(~failed, block)]
    assert compare_with_salib(frame, kept, second_order=True) >= 5


def test_constant_and_missing_outputs_are_reported_as_such():
    # The bistable module never turns stiff here, and has no gas: stats_stiff is 0 on every
    # run, max_gas_pressure is missing on every run.
    q = {
        "scene": str(ROOT / "sweeps" / "scenes" / "paper-bistable-dt70.toml"),
        "sampling": {"mode": "saltelli", "samples": 8},
        "axis": [
            {"key": "robot.dead_time", "dist": "normal", "mean": 0.07, "sd": 0.01, "range": [0.04, 0.1]},
            {"key": "object.mass", "dist": "lognormal", "median": 0.25, "sigma": 0.5},
        ],
        "sensitivity": {"resamples": 10},
    }
    frame = cushion.sensitivity(q, outputs=["stats_stiff", "max_gas_pressure", "peak_robot_force"], progress=False)
    head = frame.iloc[:2]
    assert list(head["index"]) == ["constant", "not_finite"]
    assert list(head["value"]) == [0.0, 8 * 6]
    assert head["input"].isna().all() and head["conf"].isna().all()
    force = frame[frame["output"] == "peak_robot_force"]
    assert list(force["index"]) == ["S1", "S1", "ST", "ST", "S2"]


def test_the_chart(studied, tmp_path):
    _, _, frame = studied
    fig = cushion.plot.sensitivity(frame, tmp_path / "s.png")
    assert (tmp_path / "s.png").stat().st_size > 10_000
    assert len(fig.axes) >= 4


def test_bad_input_raises_config_error(tmp_path):
    q = study_dict()
    q["sampling"] = {"mode": "sobol", "samples": 16}
    with pytest.raises(cushion.ConfigError, match='needs mode = "saltelli"'):
        cushion.sensitivity(q, progress=False, out=tmp_path / "x")
    with pytest.raises(cushion.ConfigError, match="peak_force"):
        cushion.sensitivity(study_dict(), outputs=["peak_force"], progress=False, out=tmp_path / "x")
    q = study_dict()
    q["axis"][0] = {"key": "robot.dead_time", "dist": "normal", "mean": 0.07, "sd": 0.0, "range": [0.0, 0.1]}
    with pytest.raises(cushion.ConfigError, match="sd = 0: must be > 0"):
        cushion.sensitivity(q, progress=False)
    with pytest.raises(cushion.ConfigError, match="resume=True needs out"):
        cushion.sensitivity(study_dict(), resume=True, progress=False)
    assert not (tmp_path / "x").exists()
