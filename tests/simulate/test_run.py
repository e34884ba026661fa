"""The open-loop simulation API: inputs, results, channels, errors."""

import numpy as np
import pytest

from trikedyn.errors import InputError
from trikedyn.model.statics import static_equilibrium
from trikedyn.model.vehicle import build_model
from trikedyn.simulate.result import rollover_index
from trikedyn.simulate.run import input_table, simulate


@pytest.fixture(scope="module")
def straight(reference):
    return simulate(reference, duration_s=3.0, speed_kmh=30.0, drive_torque_Nm=51.0)


def test_input_table_forms():
    assert input_table(1.0, 0.01, 0.1, 20.0).shape == (1, 4)
    table = input_table(1.0, 0.01, lambda t: 0.1 * t, (np.array([0.0, 1.0]), np.array([0.0, 100.0])))
    assert table[:, 0] == pytest.approx(np.arange(0.0, 1.0 + 1e-9, 0.01))
    assert table[-1, 1] == pytest.approx(0.1) and table[50, 2] == pytest.approx(50.0)
    with pytest.raises(InputError, match="steer_rad"):
        input_table(1.0, 0.01, (np.array([0.0, 0.0]), np.array([1.0, 2.0])))
    with pytest.raises(InputError, match="drive_torque_Nm"):
        input_table(1.0, 0.01, 0.0, lambda t: np.nan * t)


def test_result_channels_and_dataframe(straight):
    frame = straight.to_pandas()
    assert frame.index.name == "time_s" and frame.index[-1] == pytest.approx(3.0)
    for name in ("speed_mps", "ay_mps2", "yaw_rate_radps", "ri", "ltr", "front_fz_N", "rear_left_travel_m",
                 "rear_right_kappa", "steer_rad"):
        assert name in frame.columns
    assert frame.speed_mps.iloc[-1] == pytest.approx(30 / 3.6, rel=0.02)
    with pytest.raises(InputError, match="did you mean 'speed_mps'"):
        straight["sped_mps"]


def test_rollover_index_on_a_straight_is_the_static_value(reference, straight):
    """Eq. 5 on a straight at constant speed equals its static value from the CG's offset to the left:
    not zero, and negative (the left rear wheel carries more)."""
    eq = static_equilibrium(build_model(reference))
    static_ri = rollover_index(eq.wheel_loads_N["rear_right"], eq.wheel_loads_N["rear_left"])
    assert static_ri < -0.04
    tail = straight.to_pandas().loc[1.0:]
    assert tail.ri.mean() == pytest.approx(static_ri, abs=2e-3)
    assert np.all(np.abs(tail.ri) <= 1.0)


def test_plot_returns_a_figure(straight):
    import matplotlib

    matplotlib.use("Agg")
    fig = straight.plot()
    assert len(fig.axes) == 4


def test_negative_speed_is_refused(reference):
    with pytest.raises(InputError, match="speed_kmh"):
        simulate(reference, duration_s=1.0, speed_kmh=-5.0)


def test_speed_bump_excites_the_suspension_and_it_settles():
    """Crossing a 60 mm bump at the paper's 5 km/h (with Eq. 4's dampers): each wheel rises over it in turn,
    the suspension compresses, and all settles back to the static state."""
    from trikedyn.model.vehicle import speed_bump
    from trikedyn.params import load_vehicle

    run = simulate(load_vehicle("reference-etrike-eq4"), duration_s=12.0, speed_kmh=5.0, drive_torque_Nm=25.0, road=speed_bump(2.5))
    frame = run.to_pandas()
    front_pass = 2.5 - 1.95  # the front wheel starts 1.95 m ahead of the origin
    t_front = front_pass / (5 / 3.6)
    assert frame.front_travel_m.max() > 0.01
    assert frame.front_travel_m.idxmax() == pytest.approx(t_front + 0.5, abs=0.6)
    assert frame.rear_left_travel_m.idxmax() > frame.front_travel_m.idxmax() + 1.0  # the rear follows 1.95 m later
    assert abs(frame.front_travel_m.iloc[-1] - frame.front_travel_m.iloc[0]) < 2e-3
    assert (frame.front_fz_N > 0).all()
