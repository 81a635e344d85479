"""What every study of the lab shares: its command line (`--tables` to redraw the docs from the
committed results alone), writing and reading its result file, redrawing its blocks in docs/,
and the number formats of the tables.

A study module defines `measure(args) -> dict` (the runs; JSON-ready), `blocks(study)` (the
blocks it draws: `(page, name, body)` or `(page, name, body, source)`) and calls
`study.main(__doc__, RESULTS, measure, blocks)` from its own `main()`.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from typing import Callable

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def sci(x: float, zero: str = "0") -> str:
    """Two significant figures in exponent form without the exponent's padding: 2.6e-7, not
    2.6e-07; `zero` for 0."""
    if x == 0:
        return zero
    m, e = f"{x:.1e}".split("e")
    return f"{m}e{int(e)}"


def rt(rtol: float) -> str:
    """A tolerance as the docs write it: 1e-6, not 1e-06."""
    m, e = f"{rtol:.0e}".split("e")
    return f"{m}e{int(e)}"


def write_blocks(blocks, results: str) -> bool:
    """Redraw each block; False if a page lacks a block's markers."""
    from lab.make_docs import replace_block

    ok = True
    for page, name, body, *source in blocks:
        ok = replace_block(page, name, body, source[0] if source else os.path.relpath(results, ROOT)) and ok
    return ok


def main(doc: str, results: str, measure: Callable[[argparse.Namespace], dict], blocks,
         options: Callable[[argparse.ArgumentParser], None] | None = None) -> None:
    """The study's command: without `--tables`, `measure` and write `results`; then print the
    blocks drawn from `results` and write them into their pages (exit status 1 where a page
    lacks its markers). `options` adds the study's own arguments."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("--tables", action="store_true", help="only redraw the docs' blocks from the results")
    if options is not None:
        options(ap)
    args = ap.parse_args()
    if not args.tables:
        study = measure(args)
        with open(results, "w") as f:
            json.dump(study, f, indent=1, default=lambda x: x.item())  # numpy scalars
            f.write("\n")
    with open(results) as f:
        study = json.load(f)
    drawn = list(blocks(study))
    print("\n\n".join(b[2] for b in drawn))
    sys.exit(0 if write_blocks(drawn, results) else 1)


def release(*bins: str, package: str | None = None) -> None:
    """Build the release binaries a study runs (`cushion` of the root package by default)."""
    import subprocess

    cmd = ["cargo", "build", "--release", "-q"] + (["-p", package] if package else [])
    subprocess.run(cmd + [a for b in bins for a in ("--bin", b)], cwd=ROOT, check=True)


def binary(name: str) -> str:
    """A release binary of this checkout (or of $CARGO_TARGET_DIR)."""
    return os.path.join(ROOT, os.environ.get("CARGO_TARGET_DIR", "target"), "release", name)


def simulate(scene: str, sets=()) -> dict:
    """`cushion simulate SCENE --json` with `--set` for each of `sets` (KEY=VALUE)."""
    import subprocess

    args = [binary("cushion"), "simulate", scene, "--json"] + [a for s in sets for a in ("--set", s)]
    return json.loads(subprocess.run(args, cwd=ROOT, capture_output=True, text=True, check=True).stdout)


def instructions_per_run(args, runs: int) -> int:
    """Instructions per run of `loop_scene` (valgrind's cachegrind): (`runs` runs - 0 runs) /
    `runs`, so start-up and parsing drop out. `args`: the scene and its KEY=VALUE settings."""
    import re
    import subprocess

    def count(n: int) -> int:
        out = subprocess.run(["valgrind", "--tool=cachegrind", "--cache-sim=no", "--cachegrind-out-file=/dev/null",
                              binary("loop_scene"), str(n), *args],
                             cwd=ROOT, capture_output=True, text=True, check=True).stderr
        return int(re.search(r"I\s+refs:\s+([\d,]+)", out).group(1).replace(",", ""))

    return (count(runs) - count(0)) // runs


def design_space_file(folder: str, name: str, sets: dict) -> str:
    """`sweeps/design-space.toml` with its scene's path made absolute and `sets` (key: TOML value
    text) written into its `[set]` table in place of what it held; saved as `folder/name.toml`."""
    import re

    with open(os.path.join(ROOT, "sweeps", "design-space.toml")) as f:
        text = f.read().replace('scene = "scenes/', f'scene = "{ROOT}/sweeps/scenes/', 1)
    for key, value in sets.items():
        text = re.sub(rf'^"{re.escape(key)}" = .*\n', "", text, flags=re.M)
        text = re.sub(r"^\[set\]\n", lambda m: m.group(0) + f'"{key}" = {value}\n', text, count=1, flags=re.M)
    path = os.path.join(folder, f"{name}.toml")
    with open(path, "w") as f:
        f.write(text)
    return path
