"""The fixed-step RK4 loop converges: against scipy's DOP853 at rtol 1e-10 on a 5 s steer manoeuvre."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from trikedyn.model.rhs import f, f_with_outputs
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
