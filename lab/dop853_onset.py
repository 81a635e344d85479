#!/usr/bin/env python3
"""How well DOP853's error estimates see a force that sets in or vanishes inside a step.

One step of length 1 on the quadrature `y' = (t - s)^p` after `s` (zero before: a force that
sets in at `s`) or `(s - t)^p` before `s` (zero after: a force that vanishes there): a
Hertzian contact force `delta^1.5` with `delta` linear in time (p = 1.5), and its integral
(p = 2.5). For `s` across the step, prints the true error of DOP853's eighth-order solution,
its fifth-order estimate `err5` (the eighth- minus the fifth-order solution), its third-order
estimate `err3`, the combined estimate the step size is judged by,
`err5^2 / sqrt(err5^2 + 0.01 err3^2)` (Hairer's DOP853), and the two ratios estimate / truth.
A ratio below 1 means the step passes with more error than it reports.

    python3 -m lab.dop853_onset [S ...]    # standard library only; S: the points s
                                             # (default 0 0.1 0.3 0.5 0.7 0.9 0.99)

The coefficients are read from `crates/cushion-ode/src/dop853/coefficients.rs`, the ones the
engine runs. The figures are quoted in docs/accuracy.md, section 7 ("DOP853 at contact onsets
and lift-offs"), and in `events.rs` (`REDO_BEFORE`, `REDO_AFTER`: `0.01 0.9 0.93 0.95 0.97
0.99`).
"""

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
COEFFICIENTS = ROOT / "crates/cushion-ode/src/dop853/coefficients.rs"


def read_coefficients():
    text = COEFFICIENTS.read_text()
    return {m[1]: float(m[2]) for m in re.finditer(r"const (\w+): f64 = ([-0-9.eE+]+);", text)}


def weights(k):
    """Nodes of stages 1..12 and, over them, the weights of the solution and the two estimates."""
    nodes = [0.0] + [k[f"C{i}"] for i in range(2, 12)] + [1.0]
    b = [k.get(f"B{i}", 0.0) for i in range(1, 13)]
    err5 = [k.get(f"ER{i}", 0.0) for i in range(1, 13)]
    # the third-order solution uses stages 1, 9 and 12 only
    b3 = [0.0] * 12
    b3[0], b3[8], b3[11] = k["BHH1"], k["BHH2"], k["BHH3"]
    err3 = [bi - b3i for bi, b3i in zip(b, b3)]
    # a weight the pattern above failed to read would be taken as zero: the sums tell
    if abs(sum(b) - 1.0) > 1e-12 or abs(sum(err5)) > 1e-12 or abs(sum(err3)) > 1e-12:
        raise SystemExit(f"{COEFFICIENTS}: weights not read in full")
    return nodes, b, err5, err3


def row(kind, p, s, nodes, b, w5, w3):
    """One step of `y' = (t - s)^p` after `s` ("sets in") or `(s - t)^p` before it ("vanishes")."""
    if kind == "sets in":
        f = [max(c - s, 0.0) ** p for c in nodes]
        exact = (1.0 - s) ** (p + 1) / (p + 1)
    else:
        f = [max(s - c, 0.0) ** p for c in nodes]
        exact = s ** (p + 1) / (p + 1)
    if exact == 0.0:  # nothing in the step
        return
    true = sum(bi * fi for bi, fi in zip(b, f)) - exact
    e5 = sum(wi * fi for wi, fi in zip(w5, f))
    e3 = sum(wi * fi for wi, fi in zip(w3, f))
    combined = e5 * e5 / (e5 * e5 + 0.01 * e3 * e3) ** 0.5
    print(f"{kind:8s}  {p:3.1f}  {s:4.2f}  {abs(true):11.2e} {abs(e5):9.2e} {abs(e3):9.2e} "
          f"{combined:9.2e}  {abs(e5 / true):9.2f}  {combined / abs(true):10.2f}")


def main():
    nodes, b, w5, w3 = weights(read_coefficients())
    points = [float(a) for a in sys.argv[1:]] or [0.0, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99]
    print("force       p     s   true error      err5      err3  combined  err5/true  comb./true")
    for kind in ("sets in", "vanishes"):
        for p in (1.5, 2.5):
            for s in points:
                row(kind, p, s, nodes, b, w5, w3)


if __name__ == "__main__":
    main()
