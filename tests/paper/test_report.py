"""The reproduction's report (:mod:`trikedyn.paper.report`): each statement and each file shown once, the study
folded, warnings visible; the lane-change animation cut to the judged window."""

from __future__ import annotations

import pandas as pd
from PIL import Image

from trikedyn.paper.html import render_report
from trikedyn.paper.report import SECTIONS, report_sections

IDS = ("eq4", "eq3", "table3", "sampling", "tyre", "cg_offset", "model_bump", "lane_changes", "rollover", "freight",
       "stiffness", "damping", "speed_control")


def _statements(ids=IDS):
    return [{"id": i, "paper": f"the paper says {i}", "verdict": "reproduces", "evidence": f"evidence {i}"} for i in ids]


def test_each_statement_and_each_file_belongs_to_one_section():
    ids = [i for spec in SECTIONS for i in spec["statements"]]
    assert sorted(ids) == sorted(IDS)
    files = [f for spec in SECTIONS for f in spec.get("figures", ())]
    files += [name for spec in SECTIONS for key in ("tables", "folded") for name, _ in spec.get(key, ())]
    assert len(files) == len(set(files)), files
    assert sum("Table 1" in spec["title"] for spec in SECTIONS) == 1


def test_sections_show_the_study_folded_and_the_warnings_as_notes(tmp_path):
    study = pd.DataFrame({"manoeuvre": ["slc", "dlc"], "freight_kg": [0.0, 200.0], "stiffness_scale": [0.8, 1.2],
                          "damping_scale": [1.0, 1.0], "threshold_speed_kmh": [80.1, 35.2], "limit": "lift-off",
                          "limiting_wheel": "rear_left", "detail": "not shown", "driven_min_kmh": [79.2, 34.9],
                          "driven_max_kmh": [80.4, 35.3]})
    study.to_csv(tmp_path / "fig10_threshold_study.csv", index=False)
    pd.DataFrame({"vehicle": ["reference-etrike"], "suspension": ["front"], "identified_frequency_hz": [2.5],
                  "warnings": ["Nyquist: only 3.96 samples per cycle"]}).to_csv(tmp_path / "table1_model_bump.csv",
                                                                                 index=False)
    sections = report_sections(tmp_path, _statements())
    assert [s["title"] for s in sections] == [spec["title"] for spec in SECTIONS]
    last = sections[-1]
    assert last["tables"] == [] and len(last["folded"]) == 1
    folded = last["folded"][0][0]
    assert list(folded.columns) == ["manoeuvre", "freight_kg", "stiffness_scale", "damping_scale",
                                    "threshold_speed_kmh", "driven_min_kmh", "driven_max_kmh", "limit", "limiting_wheel"]
    identification = sections[1]
    assert any("Nyquist: only 3.96 samples per cycle" in note for note in identification["notes"])
    assert all("warnings" not in frame.columns for frame, _ in identification["tables"])
    doc = render_report("t", sections, summary=True)
    assert "<details>" in doc and "Threshold speed [km/h]" in doc and "not shown" not in doc


def test_a_warnings_column_empty_everywhere_gives_no_note_and_no_pandas_warning(tmp_path):
    """Empty everywhere, the column reads back as float NaN: no note, and no dtype warning from pandas (which
    ``trikedyn reproduce`` would print)."""
    import warnings

    pd.DataFrame({"vehicle": ["reference-etrike"], "suspension": ["front"], "identified_frequency_hz": [2.5],
                  "warnings": [""]}).to_csv(tmp_path / "table1_model_bump.csv", index=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sections = report_sections(tmp_path, _statements())
    assert sections[1]["notes"] == []


def test_sections_without_the_study_leave_it_out(tmp_path):
    sections = report_sections(tmp_path, _statements(IDS[:-4]))
    assert not any("Threshold" in s["title"] for s in sections)
    assert all(not s["figures"] and not s["tables"] for s in sections)  # no file written: none shown


def test_the_animation_shows_the_judged_window(tmp_path, monkeypatch):
    """The GIF of a lane change starts a second before the entry gate and ends a second after the exit gate; it
    is drawn here when no other process can be started."""
    from trikedyn.model.vehicle import build_model
    from trikedyn.paper import report
    from trikedyn.params import load_vehicle
    from trikedyn.simulate.closed_loop import run

    result = run(build_model(load_vehicle("reference-etrike")), "slc", speed_kmh=30.0, raise_on_failure=True)
    scene = report.lane_change_scene(result)
    judged = result.time_s[result["judged"] > 0.5]
    assert scene.time_s[0] >= judged[0] - 1.0 - 1e-9 and scene.time_s[-1] <= judged[-1] + 1.0 + 1e-9
    assert scene.time_s[0] > result.time_s[0] and scene.x_m.shape == scene.time_s.shape
    assert all(load.shape == scene.time_s.shape for load in scene.loads_N.values())
    path = report.animate_lane_change(result, tmp_path / "slc.gif")
    with Image.open(path) as gif:
        assert gif.n_frames >= 5

    import concurrent.futures

    def refuse(*args, **kwargs):
        raise OSError("no processes here")

    monkeypatch.setattr(concurrent.futures, "ProcessPoolExecutor", refuse)
    (tmp_path / "inline").mkdir()
    paths = report.start_animations(tmp_path / "inline", {"single lane change (ISO 14791)": result}).wait()
    assert paths == {"slc": tmp_path / "inline" / "animation_slc.gif"} and paths["slc"].stat().st_size > 1000
