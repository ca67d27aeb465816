"""The Python module `puppet` (python/src/module.cpp): the state as arrays, its round trip, and
bad input as exceptions with one-line messages. Run by pytest with the built module on
sys.path (PUPPET_PYTHON_DIR)."""
import math
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.environ.get("PUPPET_PYTHON_DIR", "build/release/python"))
import puppet  # noqa: E402


def test_the_state_is_a_live_read_only_view():
    solver = puppet.Solver(puppet.load_model("pinocchio"), rule="xpbd")
    x = solver.positions
    before = x.copy()
    solver.step(1 / 240)
    assert not np.array_equal(x, before)  # the view follows the solver
    assert not x.flags.writeable
    with pytest.raises(ValueError):
        x[0, 0] = 1.0


def test_the_state_round_trips_through_the_arrays():
    model = puppet.load_model("pinocchio")
    a = puppet.Solver(model, rule="xpbd")
    for _ in range(60):
        a.step(1 / 240)
    b = puppet.Solver(model, rule="xpbd")
    b.set_state(a.positions, a.rotations, a.velocities, a.angular_velocities)
    for name in ("positions", "rotations", "velocities", "angular_velocities"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


def test_bad_input_is_an_exception_with_one_line():
    model = puppet.load_model("pinocchio")
    solver = puppet.Solver(model)
    n = model.segment_count
    good = [solver.positions.copy(), solver.rotations.copy(), solver.velocities.copy(),
            solver.angular_velocities.copy()]
    cases = [
        (lambda: puppet.load_model("/nonexistent.json"), "cannot open"),
        (lambda: puppet.Solver(model, rule="nope"), 'unknown value "nope"'),
        (lambda: solver.step(0.0), "dt"),
        (lambda: solver.step(math.nan), "dt"),
        (lambda: solver.set_state(np.zeros((n, 2)), *good[1:]), "positions: expected shape"),
        (lambda: solver.set_state(good[0], np.zeros((n, 4)), *good[2:]), "not a unit quaternion"),
    ]
    bad_v = good[2].copy()
    bad_v[3, 1] = math.nan
    cases.append((lambda: solver.set_state(good[0], good[1], bad_v, good[3]), "not finite"))
    for call, words in cases:
        with pytest.raises(ValueError) as raised:
            call()
        message = str(raised.value)
        assert words in message and "\n" not in message and len(message) < 300, message
