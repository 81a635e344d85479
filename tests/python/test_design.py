"""cushion.design: the same answer and files as `cushion design`, the refined map's
classification, bad input raising ConfigError naming the key, the design map drawn, Ctrl-C
raising KeyboardInterrupt with nothing written."""

from __future__ import annotations

import json

import pandas as pd
import pytest

import cushion
from conftest import ROOT, interrupt

SCENE = str(ROOT / "sweeps" / "scenes" / "paper-hydraulic-dt70.toml")


def small(**over) -> dict:
    """The paper's design question at a coarse design resolution (1/8) and a 5 x 5 verification."""
    q = {
        "name": "small",
        "scene": SCENE,
        "set": {"solver.rtol": 1e-6},
        "design": [
            {"key": "hydraulic.gas_pressure", "range": [300.0, 1e5], "scale": "log"},
            {"key": "hydraulic.orifice_radius", "range": [0.002, 0.012]},
        ],
        "for_all": [
            {"key": "object.mass", "range": [0.05, 1.0]},
            {"key": "robot.dead_time", "range": [0.0, 0.1]},
        ],
        "limit": [
            {"metric": "peak_robot_force", "max": 40.0, "abs": True},
            {"metric": "object_final_velocity", "max": 1.3},
        ],
        "search": {"resolution": 0.125, "verify": 5},
    }
    q.update(over)
    return q


def write_toml(path, q: dict) -> None:
    lines = [f'name = "{q["name"]}"', f'scene = "{q["scene"]}"', "[set]"]
    lines += [f'"{k}" = {v!r}' for k, v in q["set"].items()]
    for table in ("design", "for_all"):
        for a in q[table]:
            lines += [f"[[{table}]]", f'key = "{a["key"]}"', f"range = {a['range']!r}"]
            if "scale" in a:
                lines.append(f'scale = "{a["scale"]}"')
    for lim in q["limit"]:
        lines += ["[[limit]]", f'metric = "{lim["metric"]}"', f"max = {lim['max']!r}"]
        if lim.get("abs"):
            lines.append("abs = true")
    lines += ["[search]", f"resolution = {q['search']['resolution']}", f"verify = {q['search']['verify']}"]
    path.write_text("\n".join(lines) + "\n")


@pytest.fixture(scope="module")
def answered(tmp_path_factory, cli):
    tmp = tmp_path_factory.mktemp("design")
    f = tmp / "small.toml"
    write_toml(f, small())
    cli("design", f, "--out", tmp / "cli", "--threads", "2", "--quiet")
    d = cushion.design(f, threads=1, progress=False, out=tmp / "py")
    return tmp, d


def test_the_answer_equals_the_commands_files(answered):
    tmp, d = answered
    cli_points = pd.read_parquet(tmp / "cli" / "design.parquet")
    pd.testing.assert_frame_equal(d.points, cli_points)
    pd.testing.assert_frame_equal(pd.read_parquet(tmp / "py" / "design.parquet"), cli_points)
    pd.testing.assert_frame_equal(d.runs, pd.read_parquet(tmp / "cli" / "runs.parquet"))
    ours, theirs = dict(d.best), json.loads((tmp / "cli" / "answer.json").read_text())
    for a in (ours, theirs):
        a.pop("wall_seconds")
        a.pop("threads")
    assert ours == theirs
    assert (tmp / "py" / "design-map.svg").exists() and d.out_dir == str(tmp / "py")


def test_the_answer_is_verified_and_its_witness_reproduces(answered):
    _, d = answered
    b = d.best
    assert b["feasible"] and b["verification"]["all_met"] and b["margin"] > 0
    assert b["runs"]["verify"] == 25 and len(d.runs) == b["runs"]["total"]
    for w in b["worst"]:
        sets = {**b["design"], **w["at"], "solver.rtol": 1e-6}
        run = cushion.simulate(SCENE, set=sets, trajectory=False)
        assert run.summary[w["metric"]] == w["value"]  # to the bit


def test_classify_agrees_with_the_design_points(answered):
    _, d = answered
    pts = d.points
    assert (d.classify(pts) == pts["feasible"]).all()
    assert (d.map_margin(pts) - pts["margin"]).abs().max() < 1e-12
    # a dict of columns works too, and a point off the box is refused naming its key
    assert d.classify({k: [pts[k].iloc[0]] for k in d.design_keys}).iloc[0] == pts["feasible"].iloc[0]
    with pytest.raises(cushion.ConfigError, match="hydraulic.orifice_radius"):
        d.classify({"hydraulic.gas_pressure": [1000.0], "hydraulic.orifice_radius": [0.5]})
    with pytest.raises(cushion.ConfigError, match="orifice"):
        d.classify({"hydraulic.gas_pressure": [1000.0]})


@pytest.mark.parametrize(
    "over, key",
    [
        ({"limit": [{"metric": "peak_robot_forse", "max": 40.0}]}, "peak_robot_forse"),
        ({"limit": [{"metric": "status", "max": 1.0}]}, "status"),
        ({"limit": [{"metric": "object_final_velocity", "max": 1.0, "min": 2.0}]}, "min"),
        ({"for_all": [{"key": "hydraulic.gas_pressure", "range": [300.0, 1e3]}]}, "hydraulic.gas_pressure"),
        ({"for_all": [{"key": "object.mass", "range": [1.0, 0.5]}]}, "object.mass"),
        ({"objective": {"minimize": "max_stroke"}}, "max_stroke"),
    ],
)
def test_bad_input_raises_config_error_naming_the_key(over, key, tmp_path):
    with pytest.raises(cushion.ConfigError, match=key.replace(".", r"\.")):
        cushion.design(small(**over), progress=False, out=tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_a_missing_design_file_is_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError):
        cushion.design(tmp_path / "nope.toml")


def test_design_map(answered, tmp_path):
    pytest.importorskip("matplotlib")
    import cushion.plot

    _, d = answered
    fig = cushion.plot.design_map(d, tmp_path / "map.png")
    assert (tmp_path / "map.png").stat().st_size > 10_000
    ax = fig.axes[0]
    assert "gas pressure" in ax.get_xlabel() and "orifice" in ax.get_ylabel()
    # one design axis: the worst cases against it, one panel per limited metric
    one = cushion.design(
        small(design=[{"key": "hydraulic.gas_pressure", "range": [300.0, 1e5], "scale": "log"}]),
        progress=False,
    )
    fig = one.plot(tmp_path / "one.png")
    assert len(fig.axes) == 2


def test_ctrl_c_stops_a_question_and_writes_nothing(tmp_path):
    # The paper's question at the default resolution (1/64) and verification: about 22,000
    # runs, some seconds on one thread; Ctrl-C once the first runs are reported.
    config = small(search={"resolution": 1 / 64, "verify": 41})
    out = tmp_path / "out"
    status, rest, err = interrupt("design", config, out, after=1)
    assert status == 3 and "interrupted" in rest, (status, rest, err)
    assert not out.exists(), sorted(p.name for p in out.iterdir())
