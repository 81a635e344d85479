"""cushion: collisions of a robot's end-effector with small objects, and the compliance modules
that soften them (a hydraulic cylinder with an orifice and a gas spring, a snap-through bistable
spring, or none).

The engine is compiled Rust; this package hands its results over as numpy arrays and pandas
frames. SI units throughout (m, s, kg, N, Pa). Scene keys are ``"section.key"`` names, the same
as in scene files, ``cushion simulate --set`` and sweep axes; :func:`keys` lists them.

>>> import cushion
>>> run = cushion.simulate(set={"module": "bistable", "robot.dead_time": 0.01})
>>> run.summary["object_final_velocity"]          # m/s
>>> frame = cushion.sweep("sweeps/paper.toml")    # one row per run
>>> answer = cushion.design("sweeps/design-question.toml")   # which design is safe?
>>> indices = cushion.sensitivity("sweeps/sensitivity.toml")   # which input drives what?

Bad input raises :class:`ConfigError` (a :class:`ValueError`) naming the key, the value and
what is allowed; a file that cannot be read, Python's own :class:`FileNotFoundError` (or another
:class:`OSError`). A run that fails numerically is not an exception: its ``status`` says so.
The ``cushion`` command line comes with the package (``cushion --help``, ``python -m cushion``).
"""

from ._cushion import ConfigError, Scene, __version__
from ._design import Design, design
from ._run import Run, read_mcap, simulate
from ._scene import defaults, keys, load_scene
from ._sensitivity import sensitivity
from ._sweep import sweep

__all__ = [
    "ConfigError",
    "Design",
    "Run",
    "Scene",
    "__version__",
    "defaults",
    "design",
    "keys",
    "load_scene",
    "read_mcap",
    "sensitivity",
    "simulate",
    "sweep",
]
