"""The lab: benchmarks and studies of the engine, run from the repository root as modules,
`python -m lab.work_precision` and so on (lab/README.md lists them). The scripts import one
another as `from lab import scene_scipy as ss`; their results are in lab/results/, and
`python -m lab.make_docs` writes the tables the docs show from them."""
