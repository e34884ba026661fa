"""``make bench`` keeps working: its threshold benchmark walks the paper study's scenarios with the API of today.

The benchmarks are not run by the tests (their figures depend on the machine), so an API they use can change
under them unnoticed: ``benchmarks/run.py`` called ``StudySpec.scenarios()`` for a round after it was gone and
``make bench`` stopped there. Here the benchmark runs with the search replaced by a stand-in that checks what it
is given and answers at once, so every line of it is exercised in a second.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"


@pytest.fixture
def bench_run(monkeypatch):
    monkeypatch.syspath_prepend(str(BENCHMARKS))
    monkeypatch.delitem(sys.modules, "run", raising=False)
    return importlib.import_module("run")


def test_the_threshold_benchmark_walks_the_paper_study(bench_run, monkeypatch):
    import trikedyn.analysis.threshold as threshold
    from trikedyn.model.vehicle import VehicleModel

    calls = []

    def search(model, manoeuvre, **options):
        assert isinstance(model, VehicleModel)
        assert manoeuvre in ("slc", "dlc")
        calls.append(options)
        return SimpleNamespace(n_runs=5, speeds_kmh=(30.0, 40.0), threshold_speed_kmh=40.0, limit="lift-off",
                               criterion=options.get("criterion", "course"))

    monkeypatch.setattr(threshold, "threshold_velocity", search)
    out = bench_run.bench_threshold()
    studies = [v for k, v in out.items() if k.startswith("threshold_search_paper_study_")]
    assert len(studies) == 3
    assert all(s["scenarios"] == 50 and s["same_threshold_as_bisection"] == 50 for s in studies)
    assert len(calls) == 2 * 4 + 3 * 2 * 50  # the DLC search by both methods (a warm-up and 3 timed), then
    # each case, method and scenario once
    assert {c["method"] for c in calls} == {"margin", "bisection"}


def test_the_generated_kernels_benchmark_times_the_loop_it_runs(monkeypatch):
    """``benchmarks/codegen.py`` times the loop inside each run by replacing the function the run looks it up
    by (``make bench`` stopped there once, after the lookup moved to ``specialised.model_time_loop``)."""
    monkeypatch.syspath_prepend(str(BENCHMARKS))
    monkeypatch.delitem(sys.modules, "codegen", raising=False)
    codegen = importlib.import_module("codegen")
    out = codegen.measure_dlc("reference-etrike", duration_s=0.3, repeats=1)
    for kernels in ("generic", "generated"):
        assert 0.0 < out[kernels]["loop_wall_s"] <= out[kernels]["wall_s"]
    assert out["state_diff_scaled"] < 1e-9


def test_the_study_benchmark_splits_a_run_by_its_stored_timestamps(bench_run, tmp_path):
    """The study's phases (until the first scenario, first to last, after) from the store's rows, as the workers
    stamp them."""
    from trikedyn.study.engine.store import StudyStore

    with StudyStore(tmp_path, "paper") as store:
        for k, (done, took) in enumerate([(101.5, 0.4), (103.0, 0.05), (102.0, 0.07)]):
            store.put({"scenario_id": f"s{k}", "status": "ok", "finished_at": done, "wall_time_s": took})
    phases = bench_run.study_phases(tmp_path, 100.0, 103.75)
    assert phases["until_first_result_s"] == pytest.approx(1.5)
    assert phases["first_to_last_result_s"] == pytest.approx(1.5)
    assert phases["after_last_result_s"] == pytest.approx(0.75)
    assert phases["scenarios"] == 3
    assert phases["search_sum_s"] == pytest.approx(0.52) and phases["search_median_s"] == pytest.approx(0.07)
