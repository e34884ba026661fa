"""Tests of trikedyn.analysis.compare and the modules it chains: offset by cross-correlation (.alignment),
metrics and results (.scoring), tables, bad input."""

from __future__ import annotations

import json
import math

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
import pytest

from trikedyn.analysis.alignment import find_offset
from trikedyn.analysis.compare import compare, load_table
from trikedyn.analysis.scoring import ChannelComparison, Comparison, channel_metrics
from trikedyn.errors import InputError
from trikedyn.measure.logs import write_log

SHIFT_S = 0.3  # the measured record lags the simulation: its events are 0.3 s later


def bump(t, centre, width):
    return np.exp(-0.5 * ((t - centre) / width) ** 2)


def lane_change(t, double=False, gain_wz=1.0, gain_ay=1.0):
    """Yaw rate [rad/s] and lateral acceleration [m/s^2] of a single or double lane change."""
    if double:
        shape = lambda c: bump(t, c, 0.45) - bump(t, c + 1.2, 0.45) - bump(t, c + 3.5, 0.45) + bump(t, c + 4.7, 0.45)  # noqa: E731
        return gain_wz * 0.25 * shape(3.0), gain_ay * 1.2 * shape(3.1)
    shape = lambda c: bump(t, c, 0.5) - bump(t, c + 1.5, 0.5)  # noqa: E731
    return gain_wz * 0.3 * shape(3.0), gain_ay * 1.5 * shape(3.1)


def nominal(double=False, gain_wz=1.0, gain_ay=1.0, shift_s=0.0, rate_hz=100.0, duration_s=12.0):
    """A simulation-like 100 Hz table (with a channel only it has)."""
    t = np.arange(round(duration_s * rate_hz) + 1) / rate_hz
    wz, ay = lane_change(t - shift_s, double, gain_wz, gain_ay)
    return pd.DataFrame({"time_s": t, "speed_mps": 5.0, "ay_mps2": ay, "wz_radps": wz})


def measured(seed, double=False, shift_s=SHIFT_S):
    """A 10 Hz noisy record of the manoeuvre with other gains, shifted by ``shift_s``."""
    rng = np.random.default_rng(seed)
    t = np.round(np.arange(110) * 0.1, 3)
    wz, ay = lane_change(t - shift_s, double, gain_wz=1.1, gain_ay=0.9)
    return pd.DataFrame({"time_s": t, "ay_mps2": ay + rng.normal(0, 0.05, t.size),
                         "wz_radps": wz + rng.normal(0, 0.01, t.size),
                         "az_mps2": 9.81 + rng.normal(0, 0.05, t.size)})


# ------------------------------------------------------------------------------- synthetic records
@pytest.mark.parametrize("double", [False, True], ids=["single", "double"])
@pytest.mark.parametrize("seed", range(4))
def test_offset_of_a_witmotion_record(tmp_path, seed, double):
    path = write_log(measured(seed, double), tmp_path / "run.txt", format="witmotion-sdk")
    table, kind = load_table(path)
    assert kind == "witmotion-sdk"
    result = compare(table, nominal(double))
    # measured time + offset = simulated time; the measured events are 0.3 s late
    assert result.offset_s == pytest.approx(-SHIFT_S, abs=0.02)
    assert result.align_on == "wz_radps"
    assert result.rate_hz == pytest.approx(100.0)
    assert [c.channel for c in result.channels] == ["ay_mps2", "wz_radps"]  # speed_mps, az_mps2: one side only
    wz = result["wz_radps"]
    assert wz.correlation > 0.99 and 0.0 < wz.nrmse < 0.1
    assert wz.n_samples == result.time_s.size
    # the common base is in the simulated clock, over the overlap of the shifted measured record
    assert result.time_s[0] == 0.0 and 0.0 <= 10.9 + result.offset_s - result.time_s[-1] < 0.01
    assert np.allclose(np.diff(result.time_s), 0.01)


def test_offset_sign_and_fallback_to_lateral_acceleration():
    sim = nominal().drop(columns="wz_radps")
    late = nominal(shift_s=0.25).drop(columns="wz_radps")
    result = compare(late, sim)
    assert result.align_on == "ay_mps2"
    assert result.offset_s == pytest.approx(-0.25, abs=1e-3)
    assert compare(sim, late).offset_s == pytest.approx(0.25, abs=1e-3)


def test_two_runs_with_other_gains():
    a, b = nominal(double=True), nominal(double=True, gain_wz=0.8, gain_ay=1.2, shift_s=-0.137)
    result = compare(a, b, labels=("run A", "run B"))
    assert result.offset_s == pytest.approx(-0.137, abs=2e-3)
    assert result.rate_hz == pytest.approx(1000.0)  # 10 x 100 Hz, the cap
    assert [c.channel for c in result.channels] == ["ay_mps2", "wz_radps", "speed_mps"]
    assert result["wz_radps"].correlation == pytest.approx(1.0, abs=1e-4)
    assert result["speed_mps"].rmse == pytest.approx(0.0, abs=1e-12)


def test_a_table_compared_with_itself():
    sim = nominal(double=True)
    result = compare(sim, sim)
    assert result.offset_s == 0.0
    for c in result.channels:
        assert c.rmse == 0.0 and c.peak_error == 0.0
        if c.channel != "speed_mps":  # constant: Pearson's r is undefined
            assert c.correlation == pytest.approx(1.0, abs=1e-12) and c.nrmse == 0.0
    assert math.isnan(result["speed_mps"].correlation)
    assert result.to_dict()["channels"]["speed_mps"]["correlation"] is None


def test_time_in_the_index_and_no_alignment():
    sim = nominal()
    result = compare(nominal(shift_s=0.2).set_index("time_s"), sim, align_on=None, channels=["wz_radps"])
    assert result.offset_s == 0.0 and result.align_on is None
    assert result["wz_radps"].rmse > 0.01
    assert compare(sim, sim, max_offset_s=0).align_on is None


def test_find_offset_sub_sample():
    t_ref = np.arange(0, 10, 0.1)
    t_other = np.arange(0.013, 10, 0.01)  # other rate, other start
    x = lambda t: bump(t, 4.0, 0.6) - 0.7 * bump(t, 5.5, 0.4)  # noqa: E731
    for d in (-0.437, 0.0, 0.052, 1.3):
        assert find_offset(t_ref, x(t_ref), t_other, x(t_other - d)) == pytest.approx(d, abs=5e-3)
    assert find_offset(t_ref, x(t_ref), t_ref, x(t_ref)) == 0.0


# ------------------------------------------------------------------------------------------ metrics
def test_metrics_by_hand():
    m = channel_metrics([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 2.0, 5.0], channel="ay_mps2")
    assert m == ChannelComparison("ay_mps2", rmse=1.0, nrmse=pytest.approx(1 / 3), peak_error=2.0,
                                  correlation=pytest.approx(8 / math.sqrt(70)), n_samples=4)
    m = channel_metrics([1.0, -1.0, 1.0, -1.0], [0.5, -0.5, 0.5, -0.5])
    assert (m.rmse, m.nrmse, m.peak_error, m.correlation) == (0.5, 0.25, 0.5, 1.0)
    m = channel_metrics([2.0, 2.0, 2.0], [1.0, 2.0, 3.0])
    assert m.rmse == pytest.approx(math.sqrt(2 / 3)) and math.isnan(m.nrmse) and math.isnan(m.correlation)
    assert channel_metrics([1.0, 2.0, 3.0], [3.0, 2.0, 1.0]).correlation == -1.0


def test_metrics_of_compare_match_by_hand():
    t = np.arange(8.0)
    a = pd.DataFrame({"time_s": t, "wz_radps": [0, 1, 0, -1, 0, 1, 0, -1.0]})
    b = a.assign(wz_radps=a.wz_radps * 2)
    result = compare(a, b, align_on=None, rate_hz=1.0)
    assert result.time_s.tolist() == t.tolist()
    c = result["wz_radps"]
    assert (c.rmse, c.nrmse, c.peak_error, c.correlation, c.n_samples) == (
        pytest.approx(math.sqrt(0.5)), pytest.approx(math.sqrt(0.5) / 2), 1.0, 1.0, 8)


# ----------------------------------------------------------------------------------- result objects
def test_to_dict_is_json_safe_and_to_pandas():
    result = compare(measured(0), nominal())
    d = json.loads(json.dumps(result.to_dict(), allow_nan=False))
    assert d["offset_s"] == pytest.approx(-SHIFT_S, abs=0.02) and d["rate_hz"] == pytest.approx(100.0)
    assert set(d["channels"]) == {"ay_mps2", "wz_radps"}
    assert set(d["channels"]["wz_radps"]) >= {"rmse", "nrmse", "peak_error", "correlation"}
    frame = result.to_pandas()
    assert list(frame.columns) == ["time_s", "measured_ay_mps2", "simulated_ay_mps2", "measured_wz_radps",
                                   "simulated_wz_radps"]
    assert frame.attrs["offset_s"] == result.offset_s and len(frame) == result.time_s.size


def test_plot_one_axis_per_channel():
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure

    result = compare(measured(1), nominal())
    fig = result.plot()
    assert isinstance(fig, Figure) and len(fig.axes) == 2
    plt.close(fig)
    fig = result.plot(["wz_radps"])
    assert len(fig.axes) == 1 and fig.axes[0].get_ylabel() == "wz_radps"
    assert len(fig.axes[0].lines) == 2
    plt.close(fig)
    with pytest.raises(InputError, match="did you mean 'wz_radps'"):
        result.plot(["wz_rad"])


def test_comparison_is_frozen():
    result = compare(measured(2), nominal())
    assert isinstance(result, Comparison)
    with pytest.raises(AttributeError):
        result.offset_s = 0.0


# ------------------------------------------------------------------------------------------- files
def test_load_table_run_csv_and_parquet(tmp_path):
    sim = nominal()
    sim.set_index("time_s").to_csv(tmp_path / "run.csv")  # as a run's to_pandas() writes it
    table, kind = load_table(tmp_path / "run.csv")
    assert kind == "run-csv" and list(table.columns) == list(sim.columns)
    assert np.array_equal(table["time_s"].to_numpy(), sim["time_s"].to_numpy())
    assert compare(table, sim).offset_s == 0.0
    try:
        sim.to_parquet(tmp_path / "run.parquet")
    except ImportError:
        with pytest.raises(InputError, match="pyarrow"):
            (tmp_path / "run.parquet").write_bytes(b"PAR1")
            load_table(tmp_path / "run.parquet")
    else:
        table, kind = load_table(tmp_path / "run.parquet")
        assert kind == "run-parquet" and table.equals(sim)


def test_load_table_bad_files(tmp_path):
    with pytest.raises(InputError, match="not found"):
        load_table(tmp_path / "missing.csv")
    (tmp_path / "back.csv").write_text("time_s,wz_radps\n0,1\n1,2\n0.5,3\n")
    with pytest.raises(InputError, match="back.csv.*does not increase at row 2"):
        load_table(tmp_path / "back.csv")


# --------------------------------------------------------------------------------------- bad input
def test_no_common_channel():
    a = nominal()[["time_s", "wz_radps"]]
    b = nominal()[["time_s", "ay_mps2"]]
    with pytest.raises(InputError, match="no channel in common; measured has wz_radps, simulated has ay_mps2"):
        compare(a, b)


def test_unknown_channel_lists_the_common_ones():
    with pytest.raises(InputError, match=r"channels: unknown channel 'wz_radsp'; common channels: ay_mps2, "
                                         r"wz_radps; did you mean 'wz_radps'\?"):
        compare(measured(0), nominal(), channels=["wz_radsp"])
    with pytest.raises(InputError, match="align_on: unknown channel 'speed_mps'"):
        compare(measured(0), nominal(), align_on="speed_mps")


def test_no_overlap_after_alignment():
    a = nominal(duration_s=1.0)
    b = a.assign(time_s=a.time_s + 10.0)
    with pytest.raises(InputError, match="no overlap after alignment"):
        compare(a, b, align_on=None)


def test_peak_at_the_edge_of_the_search_window():
    late = nominal(shift_s=3.0, duration_s=20.0)
    with pytest.raises(InputError, match="edge of the search window.*raise max_offset_s"):
        compare(late, nominal(duration_s=20.0), max_offset_s=1.0)
    assert compare(late, nominal(duration_s=20.0), max_offset_s=5.0).offset_s == pytest.approx(-3.0, abs=1e-3)


def test_too_few_samples():
    with pytest.raises(InputError, match="simulated 'time_s': too few samples"):
        compare(measured(0), nominal().iloc[:3])


def test_time_not_increasing():
    bad = measured(0)
    bad.loc[5, "time_s"] = bad.loc[4, "time_s"]
    with pytest.raises(InputError, match="measured 'time_s': time does not increase at row 5"):
        compare(bad, nominal())


def test_nan_names_side_and_channel():
    sim = nominal()
    sim.loc[17, "ay_mps2"] = np.nan
    with pytest.raises(InputError, match=r"simulated 'ay_mps2': holds nan at row 17 \(time_s = 0.17 s\)"):
        compare(measured(0), sim)
    # a NaN in a channel not used is no error
    compare(measured(0), sim, channels=["wz_radps"])
    meas = measured(0)
    meas.loc[3, "wz_radps"] = np.nan
    with pytest.raises(InputError, match="measured 'wz_radps': holds nan"):
        compare(meas, nominal(), channels=["ay_mps2"])  # the alignment channel is used too


def test_constant_alignment_channel():
    flat = nominal().assign(wz_radps=0.0)
    with pytest.raises(InputError, match="measured 'wz_radps': is constant"):
        compare(flat, nominal())


def test_bad_arguments():
    with pytest.raises(InputError, match="rate_hz"):
        compare(measured(0), nominal(), rate_hz=-1)
    with pytest.raises(InputError, match="expected a pandas DataFrame"):
        compare({"time_s": [0, 1]}, nominal())
    with pytest.raises(InputError, match="has no 'time_s' column"):
        compare(nominal().drop(columns="time_s"), nominal())


def test_names_moved_out_are_still_importable_from_compare():
    """The alignment and the metrics moved to their own modules; code importing them from compare still runs."""
    from trikedyn.analysis import alignment, scoring
    from trikedyn.analysis import compare as module

    assert module.find_offset is alignment.find_offset and module.MIN_SAMPLES == alignment.MIN_SAMPLES
    for name in scoring.__all__:
        assert getattr(module, name) is getattr(scoring, name)
