"""The testbed's studies from Python (python/puppet/studies.py): the rows are what the command line
writes, bad input is its one-line message as ValueError before anything is written, and each
study's table comes back as rows."""
import importlib.util
import os
import signal
import subprocess
import sys
import threading
import time

import pytest

sys.path.insert(0, os.environ.get("PUPPET_PYTHON_DIR", "build/release/python"))
import puppet  # noqa: E402

TESTBED = os.environ.get("PUPPET_TESTBED", "build/release/testbed")
HANG = dict(scenario="hang", solver="procedural", rule=["relaxed", "xpbd"], dt="1/240",
            duration=0.5, no_accuracy=True, no_timing=True, sample_hz=30)


def test_run_gives_the_rows_the_command_line_writes(tmp_path):
    rows = puppet.run(out=tmp_path / "python", **HANG)
    subprocess.run([TESTBED, "run", "--scenario", "hang", "--solver", "procedural", "--rule",
                    "relaxed,xpbd", "--dt", "1/240", "--duration", "0.5", "--no-accuracy",
                    "--no-timing", "--sample-hz", "30", "--out", str(tmp_path / "cli")],
                   check=True, capture_output=True)
    assert rows == puppet.read_table(tmp_path / "cli" / "summary.csv")
    assert {row["rule"] for row in rows} == {"relaxed", "xpbd"}
    gap = [r for r in rows if r["rule"] == "xpbd" and r["metric"] == "joint_gap_m"
           and r["stat"] == "max"]
    assert len(gap) == 1 and gap[0]["status"] == "ok" and 0 <= gap[0]["value"] < 1e-3
    assert isinstance(gap[0]["dt"], float) and gap[0]["git_sha"]  # numbers as numbers


def test_a_temporary_folder_is_removed_and_the_rows_kept():
    rows = puppet.run(**HANG)
    assert len(rows) > 10 and all(r["scenario"] == "hang" for r in rows)


@pytest.mark.parametrize("flags, cli", [
    (dict(scenario="nope"), ["--scenario", "nope"]),
    (dict(dt="1/0"), ["--dt", "1/0"]),
    (dict(solver="procedural", rule="xpbd,xpbd"), ["--solver", "procedural", "--rule",
                                                   "xpbd,xpbd"]),
    (dict(model="/nonexistent/model.json"), ["--model", "/nonexistent/model.json"]),
    (dict(bogus=1), ["--bogus", "1"]),
])
def test_bad_input_is_the_command_lines_line_and_writes_nothing(tmp_path, flags, cli):
    with pytest.raises(ValueError) as raised:
        puppet.run(out=tmp_path / "out", **flags)
    done = subprocess.run([TESTBED, "run", "--out", str(tmp_path / "out")] + cli,
                          capture_output=True, text=True)
    assert done.returncode == 2
    assert str(raised.value) == done.stderr.strip()
    assert "\n" not in str(raised.value)
    assert not (tmp_path / "out").exists()


def test_robustness_gives_its_rates():
    rows = puppet.robustness(scenario="hang", solver="procedural", rule="xpbd", dt="1/120",
                             starts=4, duration=0.5)
    assert len(rows) == 1
    row = rows[0]
    assert (row["runs"], row["diverged"], row["rate"]) == (4, 0, 0.0)
    assert 0.0 <= row["ci95_low"] <= row["ci95_high"] <= 1.0


def test_verdict_gives_its_rows(tmp_path):
    rows = puppet.verdict(out=tmp_path, scenario="hang", solver="procedural", rule="literal",
                          dt="1/30", budget="5cm", starts=1)
    assert [(r["scenario"], r["rule"], r["budget_m"]) for r in rows] == \
        [("hang", "literal", 0.05)] * len(rows)
    assert {r["verdict"] for r in rows} <= {"met", "refused", "diverges", "error-floor",
                                            "not-robust", "not-measured"}
    assert (tmp_path / "candidates.csv").exists()


def test_a_frame_needs_pandas(tmp_path):
    rows = puppet.run(out=tmp_path, **HANG)
    if importlib.util.find_spec("pandas") is None:
        with pytest.raises(ImportError, match="python3-pandas"):
            puppet.read_table(tmp_path / "summary.csv", as_frame=True)
        return
    frame = puppet.read_table(tmp_path / "summary.csv", as_frame=True)
    assert len(frame) == len(rows) and frame["value"].dtype.kind == "f"


def test_ctrl_c_stops_a_study_and_leaves_its_folder_as_it_was(tmp_path):
    # SIGINT half a second into a run judged by the truths (several seconds): KeyboardInterrupt,
    # no output folder and nothing staged beside it; the next study runs
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    begin = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        puppet.run(out=tmp_path / "out", scenario="hang", solver="procedural", rule="xpbd",
                   dt="1/240", duration=5)
    timer.join()
    assert time.monotonic() - begin < 5.0
    assert list(tmp_path.iterdir()) == []
    assert len(puppet.run(**HANG)) > 10
