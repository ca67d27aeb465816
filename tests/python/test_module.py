"""The Python package `puppet` (python/): the state as arrays and its round trip, the environment
and pins checked against analytic answers, snapshots, the crowd, no leak over 10^6 steps, and bad
input as exceptions with one-line messages. Run by pytest with the built package on sys.path
(PUPPET_PYTHON_DIR)."""
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


def test_bad_input_is_an_exception_with_one_line(tmp_path):
    global BAD_JSON
    BAD_JSON = tmp_path / "cut.json"
    BAD_JSON.write_text('{"name": "cut", "segments": [' + "x" * 1000)
    model = puppet.load_model("pinocchio")
    solver = puppet.Solver(model)
    n = model.segment_count
    good = [solver.positions.copy(), solver.rotations.copy(), solver.velocities.copy(),
            solver.angular_velocities.copy()]
    cases = [
        (lambda: puppet.load_model("/nonexistent.json"), "cannot open"),
        (lambda: puppet.Solver(model, rule="nope"), 'unknown value "nope"'),
        (lambda: puppet.Solver(model, iterations=-3), "iterations"),
        (lambda: puppet.Solver(model, bogus=1), "bogus: not a setting"),
        (lambda: puppet.Solver(model, limit_functions=1), "expected True or False"),
        (lambda: puppet.Solver(model, limit_restitution=2.0), "restitution must be in [0, 1]"),
        (lambda: puppet.Crowd(model, 4, joint_compliance=math.nan), "joint_compliance: not a"),
        (lambda: puppet.Environment(air_drag=-1.0), "air_drag"),
        (lambda: puppet.Environment(gravity=(0, math.inf, 0)), "gravity: not a finite"),
        (lambda: puppet.Environment(gravity=(0, 1)), "gravity: expected three numbers"),
        (lambda: puppet.Environment(water_density=math.nan), "water_density"),
        (lambda: puppet.GrabSpring(hz=0.0, max_force=1.0), "hz: must be positive"),
        (lambda: puppet.Pin("head", target=(0, 0, math.nan)), "target: not a finite"),
        (lambda: puppet.Pin("head", target=(0, 0, 1), compliance=-1.0), "compliance"),
        (lambda: solver.set_pins([puppet.Pin("tail", target=(0, 0, 1))]), 'no segment "tail"'),
        (lambda: solver.set_pins([puppet.Pin(14, target=(0, 0, 1))]), "segment: must be in [0, 13]"),
        (lambda: solver.set_pins([puppet.Pin(10**30, target=(0, 0, 1))]), "must be in [0, 13]"),
        (lambda: puppet.Pin(True, target=(0, 0, 1)), "name or index"),
        (lambda: puppet.Solver(model, iterations=10**12), "iterations: must be in [0, 1000]"),
        (lambda: puppet.Solver(model, substeps=2.5), "substeps: expected a whole number"),
        (lambda: puppet.Environment(tremble_seed=-1), "tremble_seed: must be in"),
        (lambda: puppet.load_model(str(BAD_JSON)), "malformed JSON"),
        (lambda: puppet.load_model("chain:0"), "chain length"),
        (lambda: solver.set_pins([puppet.Pin(0, target=(0, 0, 1))] * 5), "at most 4"),
        (lambda: solver.set_pin_targets(np.zeros((2, 3))), "targets: expected shape (0, 3)"),
        (lambda: solver.restore(puppet.Solver(puppet.load_model("chain:3")).snapshot()),
         "another model"),
        (lambda: puppet.Crowd(model, 0), "puppets"),
        (lambda: puppet.Crowd(model, 4, lanes="sixteen"), 'lanes: unknown value "sixteen"'),
        (lambda: puppet.Crowd(model, 4).puppet(4), "k: must be in [0, 3]"),
        (lambda: puppet.Crowd(model, 10**12), "puppets: must be in [1, 1000000]"),
        (lambda: puppet.Crowd(model, 2, threads=0), "threads: must be in [1, 256]"),
        (lambda: model.segment_index("tail"), 'no segment "tail"'),
        # cut at 400 bytes between characters, whatever their width
        (lambda: solver.set_pins([puppet.Pin("a" + "é" * 300, target=(0, 0, 1))]), "éé..."),
        (lambda: solver.set_pins([puppet.Pin("é" * 300, target=(0, 0, 1))]), "éé..."),
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
        assert words in message and "\n" not in message, message
        assert len(message.encode()) <= 400, message



def com(solver):
    masses = np.array(solver.model.masses)
    return masses @ solver.positions / masses.sum()


def test_a_free_figure_falls_as_gravity_says():
    # no pins: the joints are internal forces, so the centre of mass moves as one body in the
    # environment's gravity; positions integrate the updated velocities once per step
    # (symplectic Euler), so after N substeps of h the fall is g h^2 N (N + 1) / 2
    model = puppet.load_model("pinocchio")
    gravity = np.array([0.5, 0.0, -3.0])
    for rule in ("relaxed", "xpbd", "tree"):
        solver = puppet.Solver(model, rule, environment=puppet.Environment(gravity=gravity))
        n = 240 * solver.substeps
        fall = 0.5 * n * (n + 1) / n ** 2
        before = com(solver)
        for _ in range(240):
            solver.step(1 / 240)
        assert np.allclose(com(solver) - before, gravity * fall, rtol=0, atol=1e-9), rule


def test_air_drag_decays_a_free_figure_exactly():
    # no gravity, every segment moving at 1 m/s: the testbed's drag decays a velocity by exactly
    # e^(-k h) per step (environment.h: drag_rate), so the centre of mass moves at e^(-k t)
    model = puppet.load_model("pinocchio")
    solver = puppet.Solver(model, "xpbd",
                           environment=puppet.Environment(gravity=(0, 0, 0), air_drag=2.0))
    v = np.tile([1.0, 0.0, 0.0], (model.segment_count, 1))
    solver.set_state(solver.positions, solver.rotations, v, solver.angular_velocities)
    for _ in range(240):
        solver.step(1 / 240)
    masses = np.array(model.masses)
    velocity = masses @ solver.velocities / masses.sum()
    assert velocity[0] == pytest.approx(math.exp(-2.0), rel=1e-9)


def test_a_hard_pin_holds_and_a_grab_pulls():
    model = puppet.load_model("pinocchio")
    head, hand = model.segment_index("head"), model.segment_index("r_forearm")
    solver = puppet.Solver(model, "xpbd")
    target = solver.positions[head].copy()
    reach = solver.positions[hand] + [0.0, -0.3, 0.3]
    solver.set_pins([puppet.Pin("head", target=target),
                     puppet.Pin(hand, target=reach, grab=puppet.grab_spring(model))])
    for _ in range(480):
        solver.step(1 / 240)
    assert not solver.diverged
    assert np.linalg.norm(solver.positions[head] - target) < 1e-3  # measured 5e-5 m in hang
    # the grab is a capped spring-damper at 2 Hz: after 2 s it has taken the hand most of the
    # 0.42 m to its target (it sags below it: the spring holds the arm's weight, g / (2 pi 2 Hz)^2
    # = 6 cm per unit of effective mass over the hand's own)
    assert np.linalg.norm(solver.positions[hand] - reach) < 0.5 * math.hypot(0.3, 0.3)
    force = solver.user_forces[hand, :3]
    assert 0.0 < np.linalg.norm(force) <= puppet.grab_spring(model).max_force * (1 + 1e-12)
    solver.set_pin_targets([target + [0, 0, 0.2], reach])
    for _ in range(240):
        solver.step(1 / 240)
    assert np.linalg.norm(solver.positions[head] - target - [0, 0, 0.2]) < 1e-3


def test_a_snapshot_restores_the_run_bit_for_bit():
    model = puppet.load_model("pinocchio")
    solver = puppet.Solver(model, "relaxed", environment=puppet.Environment(tremble=True))
    solver.set_pins([puppet.Pin("l_forearm", target=(0.3, 0.2, 1.0),
                                grab=puppet.grab_spring(model))])
    for _ in range(30):
        solver.step(1 / 240)
    snapshot = solver.snapshot()
    for _ in range(60):
        solver.step(1 / 240)
    first = solver.positions.copy()
    solver.restore(snapshot)
    for _ in range(60):
        solver.step(1 / 240)
    assert np.array_equal(solver.positions, first)


def test_a_crowds_puppets_step_as_lone_solvers_do():
    # one by one (relaxed) a crowd's puppet is a lone Solver bit for bit; in SIMD lanes (xpbd)
    # to rounding (crowd.h; tests/crowd measured at most 5.8e-12 m after 0.5 s of a marionette,
    # and a wrong term moves a puppet by millimetres). Puppet 4's head is pinned and its pin moved
    # each step through a Solver made anew each time: it keeps its pins
    model = puppet.load_model("pinocchio")
    for rule, tolerance in (("relaxed", 0.0), ("xpbd", 1e-9)):
        crowd = puppet.Crowd(model, 6, rule, threads=2)
        lone = puppet.Solver(model, rule)
        start = lone.positions[3].copy()
        for solver in (crowd.puppet(4), lone):
            solver.set_pins([puppet.Pin("head", target=start)])
        for k in range(1, 121):
            target = start + [0.0005 * k, 0.0, 0.0002 * k]
            crowd.puppet(4).set_pin_targets([target])
            lone.set_pin_targets([target])
            crowd.step(1 / 240)
            lone.step(1 / 240)
        assert not any(crowd.diverged())
        assert np.max(np.abs(crowd.puppet(4).positions - lone.positions)) <= tolerance, rule
        assert np.linalg.norm(lone.positions[3] - target) < 1e-3
        assert np.array_equal(crowd.positions()[4], crowd.puppet(4).positions)
        # the others had no pin: they fell
        assert crowd.positions()[0][3][2] < lone.positions[3][2] - 0.5


def resident_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def test_a_million_steps_leak_nothing():
    # every call a loop makes: targets in, a step, the state out as views, and now and then a
    # snapshot, a restore and the user's forces. A leak of one small object per step would be
    # tens of MB over 10^6 steps; the resident size may grow by at most 1 MiB
    model = puppet.load_model("pinocchio")
    solver = puppet.Solver(model, "literal")
    hand = model.segment_index("l_forearm")
    start = solver.positions[hand].copy()
    solver.set_pins([puppet.Pin(hand, target=start, grab=puppet.grab_spring(model))])
    snapshots = [solver.snapshot()]
    targets = np.zeros((1, 3))

    def steps(count):
        for k in range(count):
            targets[0] = start + [0.0, 0.0, 0.1 * (k % 100) / 100]
            solver.set_pin_targets(targets)
            solver.step(1 / 240)
            solver.positions  # a view made and dropped each step
            if k % 1000 == 0:
                solver.restore(snapshots[0])
                snapshots[0] = solver.snapshot()
                solver.user_forces

    steps(100_000)
    before = resident_bytes()
    steps(900_000)
    assert resident_bytes() - before <= 1 << 20
    assert not solver.diverged


MODELS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "models")


@pytest.mark.parametrize("name, segments", [
    ("pinocchio", 14), ("chain:8", 8), (os.path.join(MODELS, "humanoid.xml"), 17),
    (os.path.join(MODELS, "pinocchio-swing-twist.json"), 14)])
def test_every_kind_of_model_loads_and_steps(name, segments):
    model = puppet.load_model(name)
    assert model.segment_count == segments == len(model.segments) == len(model.masses)
    solver = puppet.Solver(model, "xpbd", iterations=2, substeps=4, limit_functions=False)
    assert (solver.iterations, solver.substeps) == (2, 4)
    for _ in range(60):
        solver.step(1 / 240)
    assert not solver.diverged and solver.positions.shape == (segments, 3)


def test_the_model_shows_its_segments_and_joints_by_index_or_name():
    model = puppet.load_model("pinocchio")
    head = model.segment("head")
    assert head == model.segment(model.segment_index("head"))
    assert head["parent"] == "chest" and model.segment(0)["parent"] is None
    assert sum(model.segment(k)["mass"] for k in range(model.segment_count)) == pytest.approx(
        sum(model.masses), rel=1e-15)
    assert head["shapes"][0]["type"] in {"sphere", "capsule", "box", "cylinder", "ellipsoid"}
    assert len(head["rest_orientation_xyzw"]) == 4
    joints = model.joints
    assert len(joints) == model.segment_count - 1
    elbow = model.joint("r_elbow")
    assert elbow == joints[[j["name"] for j in joints].index("r_elbow")]
    assert elbow["type"] == "hinge" and elbow["child"] == "r_forearm"
    lo, hi = elbow["range_deg"]
    assert lo <= 0.0 <= hi and abs(np.linalg.norm(elbow["axis"]) - 1.0) < 1e-12
    # every child's rest place is its parent's and the joint's: the anchor on both shapes' side
    for j in joints:
        assert j["type"] in {"ball", "hinge", "slide", "fixed"}
        assert len(j["passive"]) == 3
    slides = puppet.load_model(os.path.join(os.path.dirname(__file__), "..", "data", "mjcf",
                                            "slides.xml"))
    reach, stroke = slides.joint("reach"), slides.joint("stroke")
    assert reach["type"] == "slide" and reach["range_m"] == pytest.approx((-0.45, 0.55))
    assert stroke["range_m"] is None
    for bad in ("nose", 99, -1, 1.5, True):
        with pytest.raises(ValueError) as error:
            model.segment(bad)
        assert "\n" not in str(error.value)
        with pytest.raises(ValueError):
            model.joint(bad)


def test_one_pin_moves_and_the_others_stay():
    model = puppet.load_model("pinocchio")
    solver = puppet.Solver(model)
    assert solver.rule == "xpbd"  # the default rule
    head, arm = model.segment_index("head"), model.segment_index("r_forearm")
    held = solver.positions[head].copy()
    solver.set_pins([puppet.Pin(head, target=held),
                     puppet.Pin("r_forearm", target=solver.positions[arm].copy(),
                                grab=puppet.grab_spring(model))])
    raised = solver.positions[arm] + (0.0, 0.0, 0.2)
    other = puppet.Solver(model)
    other.set_pins([puppet.Pin(head, target=held),
                    puppet.Pin("r_forearm", target=solver.positions[arm].copy(),
                               grab=puppet.grab_spring(model))])
    solver.set_pin_target(1, raised)
    other.set_pin_targets([held, raised])
    for _ in range(120):
        solver.step(1 / 240)
        other.step(1 / 240)
    assert np.array_equal(solver.positions, other.positions)  # the head's target was kept
    for bad in (2, -1, "1", True):
        with pytest.raises(ValueError):
            solver.set_pin_target(bad, raised)
    with pytest.raises(ValueError):
        solver.set_pin_target(0, (0.0, float("nan"), 1.0))
    with pytest.raises(ValueError):
        puppet.Solver(model).set_pin_target(0, held)  # no pins


def test_every_engine_steps_from_python_as_the_testbed_does():
    """puppet.Engine: each engine of this build hangs Pinocchio from its head under a gravity
    tilted 17° and swings it for half a second; its feet swing 33 cm, every engine within 1 cm
    of MuJoCo (measured: 7.6e-5 m bullet-multibody, 6e-4 ode, 7e-4 jolt, 2.2e-3 bullet-rigid,
    2.8e-3 xpbd at 1/240 s), the head held within 1 mm; the procedural engine is the Solver's
    step bit for bit; and what it cannot be given is refused in one line"""
    model = puppet.load_model("pinocchio")
    env = puppet.Environment(gravity=(3.0, 0.0, -9.5))
    head, foot = model.segment_index("head"), model.segment_index("r_foot")
    reference = None
    for name in ("mujoco", "bullet-multibody", "bullet-rigid", "ode", "jolt", "procedural"):
        try:
            engine = puppet.Engine(model, name, environment=env)
        except ValueError as error:  # an engine this build does not have
            assert "unknown solver" in str(error) or "not built" in str(error), error
            continue
        held = engine.positions[head].copy()
        engine.set_pins([puppet.Pin("head", target=held)])
        rest_foot = engine.positions[foot].copy()
        for _ in range(120):
            engine.step(1 / 240)
        assert not engine.diverged and engine.time == pytest.approx(0.5)
        x = engine.positions
        assert np.linalg.norm(x[foot] - rest_foot) > 0.3  # it swung
        assert np.linalg.norm(x[head] - held) < 1e-3
        if reference is None:
            reference = x
        assert np.abs(x - reference).max() < 0.01, name
    solver = puppet.Solver(model, environment=env)
    engine = puppet.Engine(model, "procedural", environment=env)
    held = solver.positions[head].copy()
    for s in (solver, engine):
        s.set_pins([puppet.Pin("head", target=held)])
    for _ in range(60):
        solver.step(1 / 240)
        engine.step(1 / 240)
    assert np.array_equal(solver.positions, engine.positions)
    assert np.array_equal(solver.rotations, engine.rotations)  # both x, y, z, w
    for bad in (dict(solver="havok"), dict(solver="mujoco", rule="xpbd"),
                dict(solver="procedural", rule="newton")):
        with pytest.raises(ValueError) as error:
            puppet.Engine(model, **bad)
        assert "\n" not in str(error.value)
    with pytest.raises(ValueError):
        engine.step(0.0)
    with pytest.raises(ValueError):
        engine.set_pin_target(3, (0, 0, 1))
