#!/usr/bin/env python3
"""How well an n-point Gauss-Legendre rule integrates the ringing tail's powers over a half
period, when the half period begins where the tool turns (aligned) and where it does not
(the worst of 361 phases): the question behind `early_end/ledger.rs`'s quadrature, whether half periods
that begin at the turns would let fewer nodes do the work of six.

    .venv/bin/python -m lab.tail_quadrature      # needs numpy (lab/requirements.txt)

The powers over one undamped half period, relative to the tool's speed `sd = sin(t)`:
viscous friction `b sd^2` (p = 2), the orifice `c |sd|^3` (p = 3), dry friction `d |sd|`
(p = 1, off in the paper's scenes). Prints the relative error of each rule against the exact
integrals 2, pi/2 and 4/3.
"""

import numpy as np

EXACT = {1: 2.0, 2: np.pi / 2, 3: 4.0 / 3.0}


def rule(n, p, phase):
    x, w = np.polynomial.legendre.leggauss(n)
    t = np.pi / 2 * (x + 1) + phase
    return np.pi / 2 * np.sum(w * np.abs(np.sin(t)) ** p)


def main():
    print("power  nodes  aligned   worst phase")
    for p in (1, 2, 3):
        for n in (3, 4, 5, 6):
            aligned = abs(rule(n, p, 0.0) / EXACT[p] - 1)
            worst = max(abs(rule(n, p, ph) / EXACT[p] - 1) for ph in np.linspace(0, np.pi, 361))
            print(f"|sd|^{p}  {n:5d}  {aligned:.2e}  {worst:.2e}")


if __name__ == "__main__":
    main()
