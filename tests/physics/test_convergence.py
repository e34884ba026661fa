"""The fixed-step RK4 loop converges: against scipy's DOP853 at rtol 1e-10 on a 5 s steer manoeuvre and on the
ISO 3888-1 lane change at 40 km/h (the driver's commands replayed)."""

import numpy as np
import pytest
from numba import njit
from scipy.integrate import solve_ivp

import trikedyn as td
from trikedyn.model.rhs import f, f_with_outputs, interpolate_inputs
from trikedyn.model.statics import rolling_state, static_equilibrium
from trikedyn.model.vehicle import build_model
from trikedyn.simulate.integrator import OPEN_LOOP, STATUS_OK, rk4_loop


@pytest.mark.parametrize("dt", [1e-3, 2e-3, 3e-3, 4e-3, 5e-3])
def test_rk4_wheel_loads_match_dop853(reference, dt):
    model = build_model(reference)
    eq = static_equilibrium(model)
    x0 = rolling_state(model, eq, 30 / 3.6)
    inputs = np.array([[0.0, 0.04, 60.0, 0.0]])  # a steer step to 0.04 rad, some drive torque
    u = inputs[0, 1:].copy()

    def loads(x):
        return f_with_outputs(0.0, x, u, model.plant)[1]["fz"].copy()

    duration = 5.0
    record = int(round(0.01 / dt))
    times, states, _, _, _, status, rec, _ = rk4_loop(x0, 0.0, dt, int(round(duration / dt)), record, inputs, *OPEN_LOOP, model.plant)
    assert status == STATUS_OK
    reference_run = solve_ivp(f, (0.0, duration), x0, args=(u, model.plant), method="DOP853", rtol=1e-10, atol=1e-12,
                              t_eval=times[:rec])
    assert reference_run.success
    ours = np.array([loads(x) for x in states[:rec]])
    exact = np.array([loads(x) for x in reference_run.y.T])
    static = np.array(list(eq.wheel_loads_N.values()))
    worst = (np.abs(ours - exact) / static).max()
    print(f"dt {dt}: worst wheel-load difference {100 * worst:.4f} % of static; DOP853 nfev {reference_run.nfev}")
    assert worst < 0.005, worst
    # the manoeuvre really loads the wheels unevenly (the comparison is not on a static vehicle)
    assert np.ptp(exact[:, 1] - exact[:, 2]) > 0.1 * static.mean()


@njit
def _rhs_with_table(t, x, table, plant):
    u = np.empty(3)
    u[0], u[1], u[2] = interpolate_inputs(t, table)
    return f(t, x, u, plant)


def test_closed_loop_lane_change_at_the_default_step_matches_dop853(reference):
    """The ISO 3888-1 lane change at 40 km/h, RK4 at the default step (5 ms) against DOP853 at rtol 1e-10:
    the driver's commands of the run are replayed as inputs to both, so that only the integrators differ.
    Wheel loads within 0.5 % of the static load, lateral acceleration within 1 % of its peak (measured:
    0.017 % and 0.010 %)."""
    model = build_model(reference)
    run = td.run(model, "dlc", speed_kmh=40.0)
    assert run.success
    t = run.time_s
    table = np.column_stack([t, run["steer_cmd_rad"], run["drive_torque_Nm"], run["brake_torque_Nm"]])
    dt = float(run.meta["dt_s"])
    x0 = run.states[0]
    duration = float(t[-1]) - 0.01
    times, states, derivs, wheels, _, status, rec, _ = rk4_loop(x0, 0.0, dt, int(round(duration / dt)),
                                                                int(round(0.01 / dt)), table, *OPEN_LOOP, model.plant)
    assert status == STATUS_OK
    times, states, derivs, wheels = times[:rec], states[:rec], derivs[:rec], wheels[:rec]
    exact = solve_ivp(_rhs_with_table, (0.0, duration), x0, args=(table, model.plant), method="DOP853",
                      rtol=1e-10, atol=1e-12, t_eval=times, max_step=0.01)
    assert exact.success
    n = model.n_dof
    exact_loads, exact_ay = [], []
    for tk, x in zip(times, exact.y.T, strict=True):
        u = np.array(interpolate_inputs(tk, table))
        xdot, wout = f_with_outputs(tk, x, u, model.plant)
        exact_loads.append(wout["fz"])
        exact_ay.append(xdot[n + 4] + x[n + 2] * x[n + 3])  # dv_y/dt + w_z v_x, chassis axes
    exact_loads, exact_ay = np.array(exact_loads), np.array(exact_ay)
    ay = derivs[:, n + 4] + states[:, n + 2] * states[:, n + 3]
    static = np.array(list(static_equilibrium(model).wheel_loads_N.values()))
    assert (np.abs(wheels["fz"] - exact_loads) / static).max() < 0.005
    assert np.abs(ay - exact_ay).max() < 0.01 * np.abs(exact_ay).max()
    assert np.abs(exact_ay).max() > 2.0  # a real lane change
