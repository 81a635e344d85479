"""The training runs of the profile-guided build's Python package (scripts/build_pgo.sh
--wheel), the same as scripts/pgo/train.sh's through the instrumented package: the design
space at the defaults, scripts/pgo/training.toml, the paper scenes with their
trajectories, and the compressible liquid under rodas and auto; and each paper scene 200 times
from a `cushion.Scene`, the binding's path for a notebook's loop of single runs."""

import glob
import os

import cushion

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

cushion.sweep(os.path.join(ROOT, "sweeps/design-space.toml"), progress=False)
cushion.sweep(os.path.join(ROOT, "scripts/pgo/training.toml"), progress=False)
for scene in sorted(glob.glob(os.path.join(ROOT, "sweeps/scenes/paper-*.toml"))):
    cushion.simulate(scene)
    loaded = cushion.Scene(scene)
    for _ in range(200):
        cushion.simulate(loaded, trajectory=False)
for method in ("rodas", "auto"):
    cushion.simulate(os.path.join(ROOT, "sweeps/scenes/paper-hydraulic-dt70.toml"),
                     set={"hydraulic.bulk_modulus": 1.5e9}, method=method)
