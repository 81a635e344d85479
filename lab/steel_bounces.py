#!/usr/bin/env python3
"""The tool's bounces on a steel stop, one by one: what a closed form for them would have to hold.

The paper's hydraulic scene (dead time 70 ms) with steel end-stops (`stops.stiffness` 1e11
N/m^1.5), integrated at rtol 1e-10 (atol 1e-13) by the release binary, every step and event
recorded (each event's point is in the trajectory at full precision: a contact begins at
the first point with `s <= 0` after flight and ends at the first with `s >= 0` after it). For each contact with the forward stop: its time, the tool's speed relative to the
flange at the contact's begin and end, the share of that speed the contact keeps, its duration
against Hertz's for the same impact speed (`2.9432 delta_max / v`, `delta_max = (5 m_t v^2 /
(4 k))^(2/5)`, no preload and no losses), the flight that follows, and the share of the speed
the flight keeps (the next impact's speed over this rebound's). A benchmark of the physics, not
a test; the figures are in docs/performance.md ("Where the engine is behind").

    cargo build --release --bin cushion
    python3 -m lab.steel_bounces            # standard library only; a few seconds
"""

import csv
import os
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = "sweeps/scenes/paper-hydraulic-dt70.toml"
M_T, K = 0.048, 1e11  # the tool's mass (kg, the scene's) and the steel stop's stiffness (N/m^1.5)
# the run is made with the same two numbers Hertz's duration below is computed from
SETTINGS = [f"tool.mass={M_T}", f"stops.stiffness={K}", "solver.rtol=1e-10", "solver.atol=1e-13"]
HERTZ = 2.9432  # contact time of a Hertzian impact, in delta_max / v (Johnson, Contact Mechanics, 11.2)


def trajectory(path):
    """Times, strokes `s` and the tool's speed relative to the flange `sd = v_r - v_t`, at every
    step and event."""
    sets = [a for s in SETTINGS for a in ("--set", s)]
    subprocess.run(
        ["target/release/cushion", "simulate", SCENE, *sets, "--csv", path, "--sample-interval", "0"],
        cwd=ROOT, check=True, capture_output=True)
    with open(path) as f:
        rows = list(csv.DictReader(f))
    t, s = ([float(r[k]) for r in rows] for k in ("t", "s"))
    return t, s, [float(r["v_r"]) - float(r["v_t"]) for r in rows]


def stop_contacts(s):
    """(begin, end) indices of the forward stop's contacts after the first flight: the event
    points where the stroke reaches zero from above and from below."""
    contacts, begin, flown = [], None, False
    for i, si in enumerate(s):
        if begin is None and si > 0.0:
            flown = True
        elif begin is None and flown and si <= 0.0:
            begin = i
        elif begin is not None and si >= 0.0:
            contacts.append((begin, i))
            begin = None
    return contacts


def main():
    with tempfile.TemporaryDirectory() as d:
        t, s, sd = trajectory(os.path.join(d, "steel.csv"))
    contacts = stop_contacts(s)
    print(f"{len(contacts)} contacts with the forward stop\n")
    print("| contact at (ms) | impact speed (m/s) | speed kept by the contact | duration (ms) | "
          "over Hertz's | flight (ms) | speed kept by the flight |")
    print("|---|---|---|---|---|---|---|")
    for k in [0, 1, 2, 5, 10, 20, 40, 60, 80, 100, 120, 140]:
        if k + 1 >= len(contacts):
            break
        (i0, i1), (i2, _) = contacts[k], contacts[k + 1]
        (t0, t1, t2), (v_in, v_out, v_next) = (t[i0], t[i1], t[i2]), (-sd[i0], sd[i1], -sd[i2])
        delta = (5.0 * M_T * v_in ** 2 / (4.0 * K)) ** 0.4
        hertz = HERTZ * delta / v_in
        print(f"| {t0 * 1e3:.1f} | {v_in:.4f} | {v_out / v_in:.5f} | {(t1 - t0) * 1e3:.4f} | "
              f"{(t1 - t0) / hertz:.3f} | {(t2 - t1) * 1e3:.3f} | {v_next / v_out:.5f} |")


if __name__ == "__main__":
    main()
