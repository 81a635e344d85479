#!/usr/bin/env python3
"""cushion sweep against the compiled peer on the design space's hydraulic runs.

The peer is the one of the work-precision study (`cyrk_peer.py`): the hydraulic scene's
right-hand side compiled by numba, integrated by CyRK's DOP853 and RK45, the whole run compiled,
no contact events, the robot's kinks as segment ends. It has the hydraulic module only, so this
takes every k-th hydraulic run of sweeps/design-space.toml (as `sweep_scipy.py` does) and runs
them

- in `cushion sweep` (a zip sweep of the same runs, the design space's rtol 1e-6, 1 thread, the
  whole command, best of 3), and at rtol 1e-10 (atol 1e-13) as the reference;
- in the peer at rtol 1e-6 and 1e-7 (atol rtol / 1000), in-process, best of 3 passes over the
  runs (the preload equilibrium is solved outside the timing).

It prints the time per run and the error of the object's final speed against the reference
(median, 90th percentile, largest) for each, so that the two are compared at equal accuracy.

    bash lab/setup_venv.sh && cargo build --release
    .venv/bin/python -m lab.sweep_cyrk [--sample 500]
"""

import argparse
import math
import os
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
from lab import cyrk_peer  # noqa: E402
from lab import scene_scipy as ss  # noqa: E402
from sweep_scipy import cushion_sweep, design_runs  # noqa: E402

PEER_RTOLS = (1e-6, 1e-7)


def peer_inputs(row):
    """(y0, args, dead time, counter) of one design run in the peer."""
    p10 = float(row["hydraulic.gas_pressure"])
    ss.P10 = p10  # preload_stroke reads the module's gas pressure
    y0 = ss.initial_state(ss.preload_stroke())
    counter = np.zeros(1, np.int64)
    args = cyrk_peer.args_for(counter, p10=p10, r_o=float(row["hydraulic.orifice_radius"]),
                              m_p=float(row["object.mass"]))
    return y0, args, float(row["robot.dead_time"]), counter


def peer_pass(peer, method, inputs, rtol):
    """One pass over the runs: (seconds of each run, object final speeds, evaluations)."""
    addr = peer.addr["scene"]
    speeds, evals, seconds = [], [], []
    for y0, args, dead_time, counter in inputs:
        counter[0] = 0
        args[0] = 0.0  # the run starts cruising (`run` moves the mode on)
        t0 = time.perf_counter()
        ok, v, _ = peer.run(addr, method, y0, args, rtol, rtol / 1000.0, dead_time, cyrk_peer.CHUNK, ss.T_END)
        seconds.append(time.perf_counter() - t0)
        speeds.append(v if ok else math.nan)
        evals.append(int(counter[0]))
    return seconds, speeds, evals


def errors(values, reference):
    e = sorted(abs(v - r) for v, r in zip(values, reference))
    n = len(e)
    return e[n // 2], e[int(0.9 * (n - 1))], e[-1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sample", type=int, default=500, help="hydraulic runs (of the 1/16 shard's)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--binary", default=os.path.join(ROOT, "target/release/cushion"))
    args = ap.parse_args()
    peer, reason = cyrk_peer.setup(1.0, 0.0)
    if peer is None:
        sys.exit(f"the compiled peer is {reason}: bash lab/setup_venv.sh installs numba and CyRK")
    with tempfile.TemporaryDirectory() as tmp:
        rows = design_runs(args.binary, tmp)
        step = max(1, len(rows) // args.sample)
        sample = rows[::step][: args.sample]
        n = len(sample)
        _, ref_rows = cushion_sweep(args.binary, tmp, sample, 1e-10, 1e-13, 1)
        reference = [float(r["object_final_velocity"]) for r in ref_rows]
        wall, rows6 = cushion_sweep(args.binary, tmp, sample, 1e-6, 1e-9, args.repeat)
        ours = [float(r["object_final_velocity"]) for r in rows6]
        our_evals = sorted(int(r["stats_rhs_evals"]) for r in rows6)
        inputs = [peer_inputs(r) for r in sample]
        print(f"{n} hydraulic runs of sweeps/design-space.toml, 1 thread; object final speed's error "
              "against cushion at rtol 1e-10 (m/s): median / 90th percentile / largest")
        med, p90, top = errors(ours, reference)
        print(f"cushion sweep, rtol 1e-6:  {wall / n * 1e6:7.1f} µs/run (whole command, best of "
              f"{args.repeat}), median {our_evals[n // 2]} evaluations; error {med:.1e} / {p90:.1e} / {top:.1e}")
        for method in ("DOP853", "RK45"):
            peer_pass(peer, method, inputs[:2], 1e-6)  # compiled already; warm the caches
            for rtol in PEER_RTOLS:
                best, speeds, evals, each = math.inf, None, None, None
                for _ in range(args.repeat):
                    secs, speeds, evals = peer_pass(peer, method, inputs, rtol)
                    if sum(secs) < best:
                        best, each = sum(secs), sorted(secs)
                failed = sum(math.isnan(v) for v in speeds)
                med, p90, top = errors(speeds, reference)
                print(f"CyRK {method:6s}, rtol {rtol:.0e}: {best / n * 1e6:7.1f} µs/run (in-process, best of "
                      f"{args.repeat}; the median run {each[n // 2] * 1e6:.0f} µs), median {sorted(evals)[n // 2]} evaluations; error {med:.1e} / "
                      f"{p90:.1e} / {top:.1e}" + (f"; {failed} failed" if failed else ""))


if __name__ == "__main__":
    main()
