"""Issue 25: how far a run moves when its input moves by one unit in the last place (ulp).

The lockstep batch must equal the scalar loop to 1e-9 of the states, lanes that stop early included. A lane whose
arithmetic strays from its scalar run's by a few ulp (branch-free library functions, another order of sums) moves
it as a perturbation of its input would. This script runs the batch tests' eight closed-loop double lane changes
(``tests/simulate/test_batch.py``: reference-etrike at six speeds, with 100 kg of freight, with springs 1.5 times as
stiff) twice: at the speed, and at the next float above it (one ulp, 7e-15 km/h at 58 km/h), then at ``1 + 1e-14``
times it. It prints, per run, the largest difference of the states (of their size, or of 1 where smaller) and of the
wheel loads [N] between the two.

Run: ``python benchmarks/conditioning.py`` (2 s once the loop is compiled). Not part of ``make bench``: it measures the problem, not
the code's speed.
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from trikedyn.model.vehicle import build_model  # noqa: E402
from trikedyn.params import load_vehicle, scale_suspension, with_freight  # noqa: E402
from trikedyn.simulate.closed_loop import run  # noqa: E402

LOADS = ("front_fz_N", "rear_left_fz_N", "rear_right_fz_N")


def eight_lanes():
    """The batch tests' eight runs, as (label, model, speed [km/h])."""
    ref = load_vehicle("reference-etrike")
    base = build_model(ref)
    lanes = [("reference", base, v) for v in (20.0, 35.0, 45.0, 50.0, 58.0, 70.0)]
    lanes.append(("100 kg freight", build_model(with_freight(ref, 100.0)), 40.0))
    lanes.append(("springs x1.5", build_model(scale_suspension(ref, stiffness=1.5)), 48.0))
    return lanes


def difference(a, b) -> tuple[float, float]:
    """Largest state difference (of the state's size, or of 1 where smaller) and wheel-load difference [N] over the
    steps both runs have."""
    n = min(len(a.time_s), len(b.time_s))
    scale = np.maximum(1.0, np.abs(a.states[:n]).max(axis=0))
    states = float(np.max(np.abs(b.states[:n] - a.states[:n]) / scale))
    loads = max(float(np.max(np.abs(b.channels[name][:n] - a.channels[name][:n]))) for name in LOADS)
    return states, loads


def main() -> int:
    print("closed-loop ISO 3888-1 double lane changes: each run against the same run at a speed one ulp higher, "
          "then 1e-14 higher")
    print(f"{'run':>16} {'km/h':>5} {'status':>10} {'records':>7}  {'1 ulp: states':>14} {'loads [N]':>10}  "
          f"{'1e-14: states':>14} {'loads [N]':>10}")
    for label, model, speed in eight_lanes():
        a = run(model, "dlc", speed_kmh=speed)
        ulp = difference(a, run(model, "dlc", speed_kmh=float(np.nextafter(speed, 2.0 * speed))))
        rel = difference(a, run(model, "dlc", speed_kmh=speed * (1.0 + 1e-14)))
        status = "ok" if a.status == "ok" else "stopped"
        print(f"{label:>16} {speed:5.1f} {status:>10} {len(a.time_s):7d}  {ulp[0]:14.2e} {ulp[1]:10.2e}  "
              f"{rel[0]:14.2e} {rel[1]:10.2e}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
