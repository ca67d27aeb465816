"""The testbed's studies from Python: `run`, `verdict` and `robustness` are the commands of the
same names (docs/testbed.md), parsed and checked by the command line's own code in this process.
Keyword arguments are its flags (`no_accuracy=True` is `--no-accuracy`, `dt=["1/60", "1/240"]`
is `--dt 1/60,1/240`). Each returns the command's main table as rows, read back from the CSV file
it wrote: a list of dicts, or a pandas DataFrame with `as_frame=True`. Bad input raises ValueError
with the command line's one-line message (its exit status 2), before anything runs.
"""
import contextlib
import csv
import os
import tempfile

from . import _puppet


def _flag_words(flags):
    """The command line's words for keyword arguments, in their order."""
    words = []
    for key, value in flags.items():
        flag = "--" + key.replace("_", "-")
        if value is None or value is False:
            continue
        if value is True:
            words.append(flag)
        elif isinstance(value, (list, tuple)):
            words += [flag, ",".join(str(v) for v in value)]
        else:
            words += [flag, str(value)]
    return words


def _number(text):
    """A CSV cell as the testbed wrote it: an int, a float, or the text itself."""
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


# columns of text even where every value reads as a number
_TEXT_COLUMNS = {"git_sha", "machine", "model", "rule", "reference", "setting", "grab_segment"}


def read_table(path, as_frame=False):
    """A CSV file the testbed wrote, as rows: a list of dicts (numbers as int or float, an empty
    cell as None), or a pandas DataFrame with as_frame=True."""
    if as_frame:
        try:
            import pandas
        except ImportError as e:
            raise ImportError("as_frame=True needs pandas (Debian: python3-pandas)") from e
        return pandas.read_csv(path, dtype={c: str for c in _TEXT_COLUMNS})
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        for key, text in row.items():
            if text == "":
                row[key] = None
            elif key not in _TEXT_COLUMNS:
                row[key] = _number(text)
    return rows


def _study(command, table, out, as_frame, flags):
    if "out" in flags:
        raise ValueError(f"{command}: pass the output folder as out=, not as a flag")
    if "help" in flags:
        raise ValueError(f"{command}: help= is not a study's argument (its flags: testbed "
                         f"{command} --help, or docs/testbed.md)")
    # without out=, a temporary folder that is removed once its table is read
    with contextlib.ExitStack() as stack:
        if out is None:
            out = os.path.join(stack.enter_context(tempfile.TemporaryDirectory(prefix="puppet-")),
                               command)
        _puppet._testbed([command, "--out", os.fspath(out)] + _flag_words(flags))
        return read_table(os.path.join(out, table), as_frame)


def run(*, out=None, as_frame=False, **flags):
    """`testbed run`: scenarios x solvers x rules x dts. Returns summary.csv's rows (one per
    run, metric and statistic, docs/design.md "Outputs"). `out`: a folder to keep every file the
    command writes (the traces too); by default a temporary one. With no flags it is the main
    job (every scenario, solver and rule at five dts, judged by both truths): minutes."""
    return _study("run", "summary.csv", out, as_frame, flags)


def verdict(*, out=None, as_frame=False, **flags):
    """`testbed verdict`: per solver and scenario, the cheapest configuration within each error
    budget that survives the random starts (docs/verdict.md). Returns verdict.csv's rows; `out`
    keeps candidates.csv and contact.csv beside it."""
    return _study("verdict", "verdict.csv", out, as_frame, flags)


def robustness(*, out=None, as_frame=False, **flags):
    """`testbed robustness`: the divergence rate from random starts with its 95 % interval
    (docs/robustness.md). Returns robustness_summary.csv's rows; `out` keeps robustness.csv (one
    row per run) and worst.csv (the replay commands)."""
    return _study("robustness", "robustness_summary.csv", out, as_frame, flags)
