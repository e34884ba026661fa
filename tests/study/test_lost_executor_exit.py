"""A sampled design that loses its workers for good (they kept dying, or the Dask scheduler is gone) ends in one
line with exit code 1, as the study does, not as a user's error (2): what finished is logged and ``--resume``
goes on (:class:`trikedyn.errors.RunIncomplete`). The executor's loss is stood in for (the real scheduler's
loss is tested in test_lost_scheduler.py and test_engine_dask.py)."""

from __future__ import annotations

import pytest

from trikedyn.cli import main
from trikedyn.study.engine.pool import ResilientPool, SchedulerGone

from ..conftest import strict_json

COMMANDS = {
    "sensitivity": ["sensitivity", "reference-etrike", "--samples", "2", "--resolution", "5", "-p", "track_m"],
    "loading-chart": ["loading-chart", "reference-etrike", "--resolution", "5"],
}


@pytest.fixture
def scheduler_gone(monkeypatch):
    def run(self, fn, tasks, on_result, on_death):  # noqa: ARG001
        raise SchedulerGone("the Dask scheduler is gone (stand-in)", [key for key, _ in tasks])

    monkeypatch.setattr(ResilientPool, "run", run)


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_a_lost_executor_is_exit_1_in_one_line(tmp_path, capsys, scheduler_gone, command):
    code = main([*COMMANDS[command], "--workers", "0", "--out", str(tmp_path / "out"), "--json"])
    out, err = capsys.readouterr()
    lines = [line for line in err.splitlines() if line.startswith("trikedyn:")]
    assert code == 1, (out, err)
    assert len(lines) == 1 and "scheduler is gone" in lines[0] and "--resume" in lines[0], err
    assert not lines[0].startswith("trikedyn: error"), lines  # not the user's mistake
    data = strict_json(out)
    assert data["incomplete"] is True and data["where"] == "executor"
