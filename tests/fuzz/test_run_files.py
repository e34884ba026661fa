"""Fuzzing run files (issue 21): a real run's table (CSV or Parquet) and its ``.json`` sidecar, mutated, through
``plot`` (every kind), ``animate`` (every view) and ``compare``. Each case exits 0 or 2; an error is the one
line on stderr (no warning before it); ``--json`` output is valid JSON; nothing hangs
(:mod:`tests.fuzz.contract`).

The seed is a double lane change of the reference e-trike (with its cones), one row in 40 kept so that a case
draws in a fraction of a second. Mutations: bytes (:func:`~tests.fuzz.contract.mutated`) of the CSV, the
Parquet file and the sidecar; and, knowing the formats, cells, columns, rows, dtypes and the Parquet file's own
metadata of the table, and fields of the sidecar replaced by troublesome values (wrong types, huge numbers,
texts with ``$``, names of pipes, devices and files outside the run's folder for its path CSV).
"""

from __future__ import annotations

import copy
import json
import math
import os
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from hypothesis import event, given
from hypothesis import strategies as st

from trikedyn.cli import main
from trikedyn.report.run_figures import KINDS

from .contract import check_contract, mutated

VIEWS = ("plan", "rear", "3d")
VALUES = [None, True, False, 0, -1, 1.5, 1e308, -1e308, 10**30, "", "x", "$a", "$\\frac$", "a" * 300,
          "../../../../etc/passwd", "/etc/passwd", "/dev/zero", "fifo.csv", "line.csv", "../line.csv",
          "huge.csv", "folder.csv", "dlc", "slc", "path", "fishhook", "circle", "no-such-manoeuvre",
          "reference-etrike", "reference-tadpole", [], [1, 2], [1.0, 2.0, 3.0], [0.0, -1.0, 1.0],
          ["front", "rear_left", "rear_right"], ["front", "front"], ["x"] * 20, {}, {"a": 1},
          {"name": "path", "parameters": {"file": "fifo.csv"}}, [[[[[[[[]]]]]]]]]
"""Values a sidecar field (or a Parquet file's own metadata) is replaced by (drawn as copies: an edit inside a
drawn list or object must not change this list, or the data generation would depend on the cases before)."""
CELLS = ["nan", "inf", "-inf", "1e308", "-1e308", "", "abc", "$", "1e13", "-0", "99999999999999999999999999",
         "0x1F", "1_000", "true", "\x00", "é"]


# ----------------------------------------------------------------------------------------------------------
# the seed and the folder each case runs in
# ----------------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def seed(tmp_path_factory):
    """The seed run (table, sidecar) and a folder with what a mutated sidecar may name: a path CSV, a FIFO,
    a huge sparse file and a folder, each with a ``.csv`` name; and the valid run to compare with."""
    folder = tmp_path_factory.mktemp("run_seed")
    full = folder / "full.parquet"
    assert main(["simulate", "reference-etrike", "--manoeuvre", "dlc", "--speed", "30", "--out", str(full)]) == 0
    frame = pd.read_parquet(full).iloc[::40].reset_index(drop=True)
    frame.attrs = {}
    sidecar = json.loads(full.with_suffix(".json").read_text(encoding="utf-8"))
    case = tmp_path_factory.mktemp("run_cases")
    (case / "line.csv").write_text("x_m,y_m\n" + "".join(f"{2.0 * i:.1f},{0.1 * i:.2f}\n" for i in range(31)),
                                   encoding="utf-8")
    os.mkfifo(case / "fifo.csv")
    with open(case / "huge.csv", "wb") as fh:
        fh.truncate(3 * 2**30)  # sparse: costs nothing on disk
    (case / "folder.csv").mkdir()
    good = case / "good.parquet"
    frame.to_parquet(good, index=False)
    return {"frame": frame, "sidecar": sidecar, "case": case, "good": good}


def _command(data, run: Path, case: Path, good: Path) -> list[str]:
    """One command on the run, drawn: plot of a kind, animate in a view (to .gif or .html), or compare."""
    what = data.draw(st.sampled_from(["plot", "animate", "compare"]))
    if what == "plot":
        kind = data.draw(st.sampled_from(list(KINDS)))
        return ["plot", str(run), "--kind", kind, "--out", str(case / "figure.png"), "--force", "--json"]
    if what == "animate":
        view = data.draw(st.sampled_from(VIEWS))
        out = case / data.draw(st.sampled_from(["animation.gif", "animation.html"]))
        # at most 61 frames however the time is mutated (a run spans at most 3600 s): a case stays short
        return ["animate", str(run), "--view", view, "--every-s", "60", "--fps", "2", "--out", str(out), "--force",
                "--json"]
    pair = [str(run), str(good)]
    if data.draw(st.booleans()):
        pair.reverse()
    return ["compare", *pair, "--channels", "ay_mps2", "--json"]


def _check(args: list[str]) -> None:
    """The contract, strict (the error the only line); the exit code and the command noted for
    ``--hypothesis-show-statistics``."""
    code = check_contract(args, one_line=True)
    event(f"{args[0]} {args[3] if args[0] != 'compare' else ''}".strip() + f": exit {code}")


def _clear(case: Path) -> None:
    for name in ("run.csv", "run.parquet", "run.json"):
        (case / name).unlink(missing_ok=True)


# ----------------------------------------------------------------------------------------------------------
# mutations that know the formats
# ----------------------------------------------------------------------------------------------------------
def _json_paths(value, prefix=(), depth=0):
    """Every path (tuple of keys and indices) into a JSON value, at most 4 deep."""
    yield prefix
    if depth >= 4:
        return
    items = value.items() if isinstance(value, dict) else enumerate(value) if isinstance(value, list) else ()
    for key, inner in items:
        yield from _json_paths(inner, (*prefix, key), depth + 1)


@st.composite
def mutated_meta(draw, meta: dict) -> dict:
    """``meta`` with 1-3 fields replaced by :data:`VALUES`, deleted or added; or made to name a path CSV."""
    meta = json.loads(json.dumps(meta))
    for _ in range(draw(st.integers(1, 3))):
        op = draw(st.sampled_from(["replace", "replace", "delete", "add", "path_csv"]))
        if op == "path_csv":
            meta["manoeuvre_name"] = "path"
            spec = meta.setdefault("manoeuvre_spec", {})
            spec = spec if isinstance(spec, dict) else {}
            meta["manoeuvre_spec"] = spec | {"parameters": {"file": draw(st.sampled_from(
                ["fifo.csv", "line.csv", "../line.csv", "/dev/zero", "huge.csv", "folder.csv", "/etc/passwd"]))}}
            continue
        if op == "add":
            meta[draw(st.sampled_from(["read_from", "wheels", "extra", "footprint_m", "window"]))] = copy.deepcopy(
                draw(st.sampled_from(VALUES)))
            continue
        paths = [p for p in _json_paths(meta) if p]
        path = draw(st.sampled_from(paths))
        parent = meta
        for key in path[:-1]:
            parent = parent[key]
        if op == "delete":
            del parent[path[-1]]
        else:
            parent[path[-1]] = copy.deepcopy(draw(st.sampled_from(VALUES)))
    return meta


def _as_text(frame: pd.DataFrame, column: str) -> pd.DataFrame:
    frame = frame.copy()
    frame[column] = pd.Series([repr(v) if isinstance(v, bytes) else str(v) for v in frame[column]], dtype=object,
                              index=frame.index)
    return frame


def _floats(column: pd.Series) -> np.ndarray:
    """A column as floats as far as it goes (NaN for what is not a number)."""
    try:
        return column.astype(float).to_numpy().copy()
    except (TypeError, ValueError):
        return pd.to_numeric(pd.Series([str(v) for v in column]), errors="coerce").to_numpy(dtype=float)


@st.composite
def mutated_frame(draw, frame: pd.DataFrame, meta: dict) -> pd.DataFrame:
    """``frame`` with 1-3 edits a byte mutation would rarely make: a cell set to a troublesome text or value,
    a column made text, dates or bytes, dropped, renamed or doubled; rows dropped, shuffled, repeated; the
    time scaled, shifted or made NaN; the Parquet file's own metadata set to a mutated run metadata."""
    frame = frame.copy()
    for _ in range(draw(st.integers(1, 3))):
        columns = list(frame.columns)
        op = draw(st.sampled_from(["cell", "cell_value", "column_text", "column_dates", "column_bytes", "drop",
                                   "rename", "double", "rows", "shuffle", "repeat", "time", "attrs", "bool"]))
        if not columns or not len(frame):
            break
        column = draw(st.sampled_from(columns))
        row = draw(st.integers(0, len(frame) - 1))
        try:
            if op == "cell":
                frame = _as_text(frame, column)
                frame.loc[row, column] = draw(st.sampled_from(CELLS))
            elif op == "cell_value":
                frame[column] = _floats(frame[column])
                frame.loc[row, column] = draw(st.sampled_from([math.nan, math.inf, -math.inf, 1e308, 1e13, -1e13, 0.0]))
            elif op == "column_text":
                frame = _as_text(frame, column)
            elif op == "column_dates":
                frame[column] = pd.Timestamp("2024-01-01") + pd.to_timedelta(np.arange(len(frame)), unit="s")
            elif op == "column_bytes":
                frame[column] = [b"\x00\xff"] * len(frame)
            elif op == "drop":
                frame = frame.drop(columns=[column])
            elif op == "rename":
                frame = frame.rename(columns={column: draw(st.sampled_from(
                    ["time_s", "x_m", "", "$", "a__b_fz_N", "_fz_N", "é_fz_N", column + "_fz_N", "extra"]))})
            elif op == "double":
                frame = pd.concat([frame, frame[[column]]], axis=1)
            elif op == "rows":
                frame = frame.iloc[: draw(st.integers(0, 3))].reset_index(drop=True)
            elif op == "shuffle":
                frame = frame.sample(frac=1.0, random_state=draw(st.integers(0, 9))).reset_index(drop=True)
            elif op == "repeat":
                frame = pd.concat([frame, frame.iloc[[row]]]).reset_index(drop=True)
            elif op == "time" and "time_s" in frame.columns:
                how = draw(st.sampled_from(["scale", "shift", "nan", "last"]))
                t = _floats(frame["time_s"])
                if how == "scale":
                    t = t * draw(st.sampled_from([1e-9, 1e3, 1e6, -1.0]))
                elif how == "shift":
                    t = t + draw(st.sampled_from([1e9, -1e9, 1e12, 3600.0]))
                elif how == "nan":
                    t[row] = math.nan
                else:
                    t[-1] = draw(st.sampled_from([1e9, 3600.0, 3599.0, 1e12]))
                frame["time_s"] = t
            elif op == "attrs":
                frame.attrs = draw(mutated_meta(meta))
            elif op == "bool":
                frame[column] = _floats(frame[column]) > 0
        except (TypeError, ValueError, KeyError):  # an edit this table cannot take: the next one
            continue
    return frame


def _write_columns(frame: pd.DataFrame, target: Path) -> None:
    """Parquet written column by column with pyarrow (which allows a name twice), a column it cannot take
    as it is stored as text."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    arrays = []
    for k in range(frame.shape[1]):
        column = frame.iloc[:, k]
        try:
            arrays.append(pa.array(column.to_numpy()))
        except (pa.ArrowException, TypeError, ValueError):
            arrays.append(pa.array(column.astype(str).to_numpy()))
    pq.write_table(pa.Table.from_arrays(arrays, names=[str(c) for c in frame.columns]), target)


# ----------------------------------------------------------------------------------------------------------
# the cases
# ----------------------------------------------------------------------------------------------------------
@given(data=st.data())
def test_run_csv(seed, data):
    """The table as CSV, its bytes mutated (the sidecar as written)."""
    case = seed["case"]
    _clear(case)
    raw = data.draw(mutated(seed["frame"].to_csv(index=False).encode("utf-8")))
    (case / "run.csv").write_bytes(raw)
    (case / "run.json").write_text(json.dumps(seed["sidecar"]), encoding="utf-8")
    _check(_command(data, case / "run.csv", case, seed["good"]))


@given(data=st.data())
def test_run_parquet(seed, data):
    """The table as Parquet: cells, columns, rows and its own metadata edited, or its bytes mutated."""
    case = seed["case"]
    _clear(case)
    frame = data.draw(mutated_frame(seed["frame"], seed["sidecar"]))
    target = case / "run.parquet"
    try:
        frame.to_parquet(target, index=False)
    except Exception:  # a table pandas will not store (a column twice, bytes among floats): column by column
        _write_columns(frame, target)
    if data.draw(st.booleans()):
        target.write_bytes(data.draw(mutated(target.read_bytes())))
    if data.draw(st.booleans()):
        (case / "run.json").write_text(json.dumps(seed["sidecar"]), encoding="utf-8")
    _check(_command(data, target, case, seed["good"]))


@given(data=st.data())
def test_run_sidecar(seed, data):
    """The sidecar: its fields replaced (wrong types, huge numbers, a path CSV outside the run's folder, a
    pipe, a device), or its bytes mutated; the table as written."""
    case = seed["case"]
    _clear(case)
    table = case / data.draw(st.sampled_from(["run.csv", "run.parquet"]))
    if table.suffix == ".csv":
        seed["frame"].to_csv(table, index=False)
    else:
        seed["frame"].to_parquet(table, index=False)
    if data.draw(st.booleans()):
        text = json.dumps(data.draw(mutated_meta(seed["sidecar"])))
        (case / "run.json").write_text(text, encoding="utf-8")
    else:
        raw = json.dumps(seed["sidecar"], indent=1).encode("utf-8")
        (case / "run.json").write_bytes(data.draw(mutated(raw)))
    _check(_command(data, table, case, seed["good"]))

