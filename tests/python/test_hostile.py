"""What the Python package promises a hostile or careless caller (docs/python.md, "Threads,
fork and bad arrays"): no option of one call in the next, a crowd that takes one call at a time,
a process forked with a crowd or a pooled driver, arrays read as written or refused before they
are copied, an engine's own error as a divergence, and no driver outliving a killed interpreter.
"""
import ctypes
import os
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

sys.path.insert(0, os.environ.get("PUPPET_PYTHON_DIR", "build/release/python"))
import puppet  # noqa: E402

SOURCE = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
OUTSIDE = os.path.join(SOURCE, "tests", "data", "bad", "mjcf_include_outside.xml")
PUBLISHED = os.path.join(SOURCE, "tests", "data", "mjcf", "published_style.xml")
QUIET = dict(no_accuracy=True, no_timing=True, duration=0.05, dt="1/240", scenario="hang")


def test_reading_options_last_one_call():
    for _ in range(2):
        with pytest.raises(ValueError, match="outside the model's folder"):
            puppet.load_model(OUTSIDE)
        assert puppet.load_model(OUTSIDE, include_outside=True).segment_count == 1
        with pytest.raises(ValueError, match="outside the model's folder"):
            puppet.load_model(OUTSIDE)
        puppet.run(model=OUTSIDE, include_outside=True, solver="procedural", rule="xpbd", **QUIET)
        with pytest.raises(ValueError, match="outside the model's folder"):
            puppet.run(model=OUTSIDE, solver="procedural", rule="xpbd", **QUIET)
        with pytest.raises(ValueError, match="not modelled by the testbed"):
            puppet.load_model(PUBLISHED, strict=True)
        # refused for another argument, with --strict on: the next call does not see it
        with pytest.raises(ValueError, match="--engine-budget"):
            puppet.run(model=PUBLISHED, strict=True, engine_budget=float("nan"), **QUIET)
        assert puppet.load_model(PUBLISHED).segment_count > 1
        rows = puppet.run(model=PUBLISHED, solver="procedural", rule="xpbd", **QUIET)
        assert rows


def test_an_engine_budget_lasts_one_call():
    for _ in range(2):
        with pytest.raises(ValueError, match="past the budget"):
            puppet.run(solver="bullet-multibody", engine_budget=1e-3, **QUIET)
        assert puppet.run(solver="bullet-multibody", **QUIET)


def test_a_crowd_takes_one_call_at_a_time():
    model = puppet.load_model("pinocchio")
    for threads in (1, 2):
        crowd = puppet.Crowd(model, 256, threads=threads)
        refused = []

        def work():
            for _ in range(100):
                try:
                    crowd.step(1 / 60)
                    crowd.puppet(0).positions
                except RuntimeError as e:
                    refused.append(str(e))

        workers = [threading.Thread(target=work) for _ in range(2)]
        for w in workers:
            w.start()
        for w in workers:
            w.join()
        # the two threads met (256 puppets take long enough), and nothing ran alongside
        assert refused and all("stepping on another thread" in r for r in refused), refused[:1]
        assert np.isfinite(crowd.positions()).all()
        assert not any(crowd.diverged())


def test_a_forked_child_gets_its_own_drivers_and_a_clear_error_for_old_threads():
    model = puppet.load_model("pinocchio")
    lone = puppet.Crowd(model, 4, threads=1)
    pooled = puppet.Crowd(model, 4, threads=2)
    pooled.step(1 / 60)
    jolt = dict(solver="jolt", **QUIET)
    have_jolt = True
    try:
        puppet.run(**jolt)  # a driver is now pooled in this process
    except ValueError as e:
        if "not built" not in str(e):
            raise
        have_jolt = False
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(read)
        said = []
        try:
            if have_jolt:
                rows = puppet.run(**jolt)
                said.append("jolt-diverged" if any(r["status"] == "diverged" for r in rows)
                            else "jolt-ok")
            lone.step(1 / 60)
            said.append("lone-ok")
            try:
                pooled.step(1 / 60)
                said.append("pooled-stepped")
            except RuntimeError as e:
                said.append("pooled-refused" if "before fork()" in str(e) else str(e))
        except BaseException as e:  # noqa: BLE001 - reported to the parent
            said.append(repr(e))
        os.write(write, ",".join(said).encode())
        os._exit(0)
    os.close(write)
    _, status = os.waitpid(pid, 0)
    said = os.read(read, 4096).decode()
    os.close(read)
    assert status == 0
    expected = (["jolt-ok"] if have_jolt else []) + ["lone-ok", "pooled-refused"]
    assert said == ",".join(expected)
    # the parent's own crowd and drivers are untouched
    pooled.step(1 / 60)
    if have_jolt:
        assert all(r["status"] == "ok" for r in puppet.run(**jolt))


def test_arrays_are_read_as_written_or_refused_before_they_are_copied():
    model = puppet.load_model("pinocchio")
    solver = puppet.Solver(model)
    n = model.segment_count
    x, q, v, w = (solver.positions.copy(), solver.rotations.copy(), solver.velocities.copy(),
                  solver.angular_velocities.copy())
    huge = np.broadcast_to(np.float64(0.0), (10**12, 3))  # a terabyte, if it were copied
    cases = [
        (lambda: solver.set_state(x.astype(complex), q, v, w), "dtype complex128"),
        (lambda: solver.set_state(x.astype(object), q, v, w), "dtype object"),
        (lambda: solver.set_state(x.astype(bool), q, v, w), "dtype bool"),
        (lambda: solver.set_state(huge, q, v, w), "positions: expected shape (14, 3)"),
        (lambda: solver.set_state("positions", q, v, w), "positions: expected an array"),
        (lambda: puppet.Environment(gravity=np.array([0, 0, -9.81 + 1j])), "dtype complex128"),
        (lambda: puppet.Environment(gravity=np.broadcast_to(0.0, (10**12,))),
         "gravity: expected three numbers"),
        (lambda: puppet.Pin("head", target="abc"), "target: expected three numbers"),
        (lambda: puppet.load_model("pinocchio\0.json"), "NUL byte"),
        (lambda: puppet.load_model(os.path.join(SOURCE, "models", "pinocchio.json\0x")),
         "NUL byte"),
        (lambda: puppet.run(out="/tmp/puppet-nul\0x", **QUIET), "NUL byte"),
        (lambda: puppet.run(model="pinocchio\0", **QUIET), "NUL byte"),
        (lambda: puppet.run(help=True), "help= is not a study's argument"),
    ]
    for call, words in cases:
        start = time.monotonic()
        with pytest.raises(ValueError) as raised:
            call()
        message = str(raised.value)
        assert words in message and "\n" not in message, message
        assert len(message.encode()) <= 400, message
        assert time.monotonic() - start < 5, "refused before anything was copied"
    assert not os.path.exists("/tmp/puppet-nul")
    # whole numbers and lists are still numbers
    solver.set_state(x.astype(np.float32).astype(np.float64).tolist(), q, v.astype(np.int64), w)
    assert solver.positions.shape == (n, 3)


def test_an_engine_error_in_a_study_is_a_divergence_not_an_exit():
    model = os.path.join(SOURCE, "tests", "data", "engine_errors", "mujoco_rank_deficient.json")
    try:
        rows = puppet.run(model=model, solver="mujoco", scenario="drop", dt="1/240", duration=1,
                          no_accuracy=True, no_timing=True)
    except ValueError as e:
        if "not built" in str(e):
            pytest.skip(str(e))
        raise
    assert any(r["status"] == "diverged" for r in rows)
    assert puppet.load_model("pinocchio").segment_count == 14  # the interpreter lives on


def _driver_children(parent):
    """The node drivers (server.mjs) whose parent is `parent`."""
    found = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                ppid = int(f.read().rsplit(")", 1)[1].split()[1])
            with open(f"/proc/{entry}/cmdline", "rb") as f:
                cmdline = f.read()
        except OSError:
            continue
        if ppid == parent and b"server.mjs" in cmdline:
            found.append(int(entry))
    return found


def test_a_killed_interpreter_leaves_no_driver():
    # this process adopts what its children leave behind, so an orphan would be ours to see
    PR_SET_CHILD_SUBREAPER = 36
    libc = ctypes.CDLL(None, use_errno=True)
    assert libc.prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0) == 0
    script = ("import sys; sys.path.insert(0, %r); import puppet; "
              "puppet.run(model='chain:60', solver='jolt', scenario='shake', dt='1/960', "
              "duration=60, no_accuracy=True, no_timing=True)" % sys.path[0])
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE)
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline and not _driver_children(child.pid):
        if child.poll() is not None:
            stderr = child.stderr.read().decode()
            if "jolt" in stderr and "not built" in stderr:
                pytest.skip(stderr.strip())
            pytest.fail("the study ended before its driver was seen: " + stderr[-300:])
        time.sleep(0.05)
    drivers = _driver_children(child.pid)
    assert drivers, "no driver started"
    child.kill()
    child.wait()
    gone_by = time.monotonic() + 1.0
    while time.monotonic() < gone_by and any(_alive(p) for p in drivers):
        time.sleep(0.02)
    left = [p for p in drivers if _alive(p)]
    for p in left:
        os.kill(p, 9)
    assert not left, "a driver outlived its interpreter by more than 1 s"


def _alive(pid):
    """Whether `pid` is a live process (an orphan adopted by this one is reaped here)."""
    try:
        done, _ = os.waitpid(pid, os.WNOHANG)
        if done == pid:
            return False
    except ChildProcessError:
        pass
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False
