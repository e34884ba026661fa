"""Issue 25: how far a run moves when its input moves by one unit in the last place (ulp).

The lockstep batch must equal the scalar loop to 1e-9 of the states, lanes that stop early included. A lane whose
arithmetic strays from its scalar run's by a few ulp (branch-free library functions, another order of sums) moves
it as a perturbation of its input would. This script runs the batch tests' eight closed-loop double lane changes
(``tests/simulate/test_batch.py``: reference-etrike at six speeds, with 100 kg of freight, with springs 1.5 times as
stiff) twice: at the speed, and at the next float above it (one ulp, 7e-15 km/h at 58 km/h), then at ``1 + 1e-14``
times it. It prints, per run, the largest difference of the states (of their size, or of 1 where smaller) and of the
wheel loads [N] between the two.

The runs are the tests' own (:func:`tests.simulate.test_batch.eight_lanes`), so the two cannot drift apart. Run:
``python benchmarks/conditioning.py`` (2 s once the loop is compiled). Not part of ``make bench``: it measures the
problem, not the code's speed.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository, for the tests' lanes

import numpy as np  # noqa: E402
from tests.simulate.test_batch import LOADS, eight_lanes  # noqa: E402

from trikedyn.params import load_vehicle  # noqa: E402
from trikedyn.simulate.closed_loop import run  # noqa: E402


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
    print(f"{'lane':>4} {'km/h':>5} {'status':>10} {'records':>7}  {'1 ulp: states':>14} {'loads [N]':>10}  "
          f"{'1e-14: states':>14} {'loads [N]':>10}")
    models, speeds = eight_lanes(load_vehicle("reference-etrike"))
    for lane, (model, speed) in enumerate(zip(models, speeds, strict=True)):
        a = run(model, "dlc", speed_kmh=speed)
        ulp = difference(a, run(model, "dlc", speed_kmh=float(np.nextafter(speed, 2.0 * speed))))
        rel = difference(a, run(model, "dlc", speed_kmh=speed * (1.0 + 1e-14)))
        status = "ok" if a.status == "ok" else "stopped"
        print(f"{lane:>4} {speed:5.1f} {status:>10} {len(a.time_s):7d}  {ulp[0]:14.2e} {ulp[1]:10.2e}  "
              f"{rel[0]:14.2e} {rel[1]:10.2e}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
