#!/usr/bin/python3
"""A tour of the Python package `puppet`, in cells (# %%) that a notebook or an editor runs one at a
time, or run whole:

    PYTHONPATH=build/release/python examples/python/tour.py [OUTPUT_FOLDER]

It steps the procedural solver by hand (a figure hanging from its head, then a hand dragged in a
circle by a grab), reads its state as NumPy arrays, steps a crowd, and runs the testbed's studies
to get their rows. It draws tour.png in OUTPUT_FOLDER (default: the current folder).
"""
# %% the model and a solver
import os
import sys
import time

import matplotlib

matplotlib.use("Agg")  # draws to a file; a notebook shows the figure instead
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import puppet  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else "."
os.makedirs(out, exist_ok=True)
model = puppet.load_model("pinocchio")
print(model, "segments:", ", ".join(model.segments))
dt = 1 / 240

# %% hang it by the head, tilted 20 degrees: set_state places the figure, positions is a live view
solver = puppet.Solver(model, "xpbd", environment=puppet.Environment(air_drag=0.1))
head, foot = model.segment_index("head"), model.segment_index("l_foot")
pin_target = solver.positions[head].copy()
tilt = np.radians(20.0)
turn = np.array([[np.cos(tilt), 0, np.sin(tilt)], [0, 1, 0], [-np.sin(tilt), 0, np.cos(tilt)]])
q_turn = np.array([0.0, np.sin(tilt / 2), 0.0, np.cos(tilt / 2)])  # (x, y, z, w) about y


def times(a, b):
    """The quaternion product a b, each as (x, y, z, w)."""
    x1, y1, z1, w1 = a
    x2, y2, z2, w2 = b
    return np.array([w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2, w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
                     w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2, w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2])


zero = np.zeros((model.segment_count, 3))
solver.set_state((solver.positions - pin_target) @ turn.T + pin_target,
                 np.array([times(q_turn, q) for q in solver.rotations]), zero, zero)
solver.set_pins([puppet.Pin(head, target=pin_target)])
feet = []
for _ in range(480):
    solver.step(dt)
    feet.append(solver.positions[foot].copy())  # the view follows the solver: copy to keep
feet = np.array(feet)
gap = np.linalg.norm(solver.positions[head] - pin_target)
print(f"after {solver.time:.2f} s the head is {1e3 * gap:.3f} mm "
      f"from its pin; the foot swung {np.ptp(feet[:, 0]):.2f} m in x")

# %% drag the right forearm in a circle with the testbed's grab, in three rules
hand = model.segment_index("r_forearm")
lag = {}
for rule in ("relaxed", "xpbd", "tree"):
    s = puppet.Solver(model, rule)
    centre = s.positions[hand].copy()
    s.set_pins([puppet.Pin(head, target=s.positions[head]),
                puppet.Pin(hand, target=centre, grab=puppet.grab_spring(model))])
    distance = []
    for k in range(480):
        angle = 2 * np.pi * 0.5 * (k + 1) * dt
        target = centre + 0.2 * np.array([np.sin(angle), 0.0, 1.0 - np.cos(angle)])
        s.set_pin_targets([s.positions[head], target])
        s.step(dt)
        distance.append(np.linalg.norm(s.positions[hand] - target))
    lag[rule] = np.array(distance)
    print(f"{rule:8s} the hand trails its target by {1e3 * lag[rule][240:].mean():.0f} mm "
          "on average")

# %% a snapshot puts a run back bit for bit
snapshot = solver.snapshot()
solver.step(dt)
after = solver.positions.copy()
solver.restore(snapshot)
solver.step(dt)
print("the same step from a snapshot gives the same bits:", np.array_equal(after, solver.positions))

# %% a crowd: 64 puppets on 2 threads, xpbd's in SIMD lanes
crowd = puppet.Crowd(model, 64, "xpbd", threads=2)
begin = time.perf_counter()
for _ in range(60):
    crowd.step(dt)
seconds = time.perf_counter() - begin
print(f"crowd of {len(crowd)} in lanes of {crowd.lanes}: {1e6 * seconds / 60 / len(crowd):.1f} us "
      "per puppet-step (wall clock, this machine)")

# %% the testbed's studies as rows: hang in two rules and MuJoCo, judged by nothing but itself
rows = puppet.run(scenario="hang", solver="procedural,mujoco", rule="relaxed,xpbd", dt="1/240",
                  duration=1, no_accuracy=True, no_timing=True)
for row in rows:
    if row["metric"] == "joint_gap_m" and row["stat"] == "max":
        print(f"{row['solver']:10s} {row['rule'] or '':8s} largest joint gap "
              f"{1e3 * row['value']:.4f} mm")
rates = puppet.robustness(scenario="drag", solver="procedural", rule="xpbd", dt="1/60", starts=8,
                          duration=1)
print("xpbd at 1/60 s in drag diverged in", rates[0]["diverged"], "of", rates[0]["runs"],
      f"random starts (95 % interval up to {rates[0]['ci95_high']:.2f})")

# %% draw what was measured
figure, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
left.plot(np.arange(len(feet)) * dt, feet[:, 0], label="x")
left.plot(np.arange(len(feet)) * dt, feet[:, 2], label="z")
left.set(title="left foot, hanging from the head, let go at 20 degrees", xlabel="t (s)",
         ylabel="position (m)")
left.legend()
for rule, distance in lag.items():
    right.plot(np.arange(len(distance)) * dt, 1e3 * distance, label=rule)
right.set(title="right forearm dragged in a 0.2 m circle at 0.5 Hz", xlabel="t (s)",
          ylabel="distance to the target (mm)")
right.legend()
figure.tight_layout()
figure.savefig(os.path.join(out, "tour.png"), dpi=100)
print("drew", os.path.join(out, "tour.png"))
