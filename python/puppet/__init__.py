"""The procedural articulated-body solver of Bae et al. (2001), its family of rules, and the
testbed that measures them against reference engines (docs/python.md).

    model = puppet.load_model("pinocchio")
    solver = puppet.Solver(model, "xpbd")
    solver.step(1 / 240)
    solver.positions            # (n, 3), a read-only view of the solver's state
    engine = puppet.Engine(model, "mujoco")   # any engine, stepped as the testbed steps it

    rows = puppet.run(scenario="hang", rule="xpbd", dt="1/240")   # the testbed's summary rows
"""
import os

from . import _puppet
from ._puppet import (  # noqa: F401
    Crowd,
    Engine,
    Environment,
    GrabSpring,
    Model,
    Pin,
    Snapshot,
    Solver,
    grab_spring,
    load_model,
)
from .studies import read_table, robustness, run, verdict  # noqa: F401

# "pinocchio" is the package's own copy of models/pinocchio.json, so that an installed package
# does not need the source tree
_puppet._use_builtin_model(os.path.join(os.path.dirname(__file__), "models", "pinocchio.json"))

__all__ = [
    "Crowd",
    "Engine",
    "Environment",
    "GrabSpring",
    "Model",
    "Pin",
    "Snapshot",
    "Solver",
    "grab_spring",
    "load_model",
    "read_table",
    "robustness",
    "run",
    "verdict",
]
