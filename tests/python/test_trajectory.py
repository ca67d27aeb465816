"""The same trajectory from Python as from C++, bit for bit (tests/python/trajectory.cpp is the C++
side): every rule, with air drag and a slanted gravity, a grab moving along a line, and the head
held by a hard pin or free. (The literal rule does not move with the head held: its turn
theta = phi exp(-1/(I |r x s|)) is 0 in double precision for Pinocchio, docs/solver.md.)"""
import os
import subprocess
import sys

import pytest

sys.path.insert(0, os.environ.get("PUPPET_PYTHON_DIR", "build/release/python"))
import puppet  # noqa: E402

STEPS = 120
RULES = ["literal", "smoothed", "weighted", "subtree", "relaxed", "xpbd", "tree"]


def python_trajectory(rule, hold):
    model = puppet.load_model("pinocchio")
    solver = puppet.Solver(model, rule, environment=puppet.Environment(
        air_drag=0.3, gravity=(1.5, 0.5, -9.81)))
    head, forearm = model.segment_index("head"), model.segment_index("l_forearm")
    held = solver.positions[head].copy()
    pulled = solver.positions[forearm].copy()
    grab = puppet.Pin(forearm, target=pulled, grab=puppet.grab_spring(model))
    solver.set_pins([puppet.Pin(head, target=held), grab] if hold == "held" else [grab])
    lines = []
    for k in range(1, STEPS + 1):
        # k * (0.001, 0, 0.0005) added to each coordinate as C++'s Vector3d sum does
        moved = [pulled[0] + k * 0.001, pulled[1] + k * 0.0, pulled[2] + k * 0.0005]
        solver.set_pin_targets([held, moved] if hold == "held" else [moved])
        solver.step(1.0 / 240.0)
        if k % 10:
            continue
        for x, q in zip(solver.positions, solver.rotations):
            lines.append(" ".join(float(v).hex() for v in list(x) + list(q)))
    return lines


def cxx_trajectory(rule, hold):
    binary = os.environ.get("PUPPET_TRAJECTORY", "build/release/tests/python_trajectory")
    out = subprocess.run([binary, rule, str(STEPS), hold], check=True, capture_output=True,
                         text=True)
    # C's %a and Python's float.hex spell the same double differently: compare the numbers
    return [" ".join(float.fromhex(v).hex() for v in line.split())
            for line in out.stdout.splitlines()]


@pytest.mark.parametrize("hold", ["held", "free"])
@pytest.mark.parametrize("rule", RULES)
def test_python_steps_the_cxx_trajectory_bit_for_bit(rule, hold):
    cxx = cxx_trajectory(rule, hold)
    assert len(cxx) == STEPS // 10 * 14
    assert cxx[-14:] != cxx[:14]  # it moved
    assert python_trajectory(rule, hold) == cxx
