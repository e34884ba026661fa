"""Does the Morris ranking of the assumed values hang on the seed? (``make morris-seeds``; never in make test)

Issue 19's check: Morris screening with 10 trajectories over every assumed value of the reference trike
(``trikedyn sensitivity reference-etrike --manoeuvre dlc --criterion course --samples 10``), with seeds 1
and 2: the two rankings must have the same top-five set and the same top three in order. Prints both rankings
with their 95 % intervals, writes ``benchmarks/morris_seeds.json`` and exits 1 when either condition fails.
About 1.5 min per seed on 2 workers.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

SEEDS = (1, 2)
TRAJECTORIES = 10


def ranking(seed: int, criterion: str = "course", workers: int = 2) -> dict:
    """One Morris run on the reference trike's double lane change: the indices, limits and wall time."""
    from trikedyn.params import load_vehicle
    from trikedyn.study.designs import sensitivity as sa

    pset = load_vehicle("reference-etrike")
    factors, excluded = sa.candidate_factors(pset, sa.DEFAULT_FRACTION)
    search = sa.Search("dlc", {}, 0.1, criterion=criterion)
    start = time.perf_counter()
    result = sa.run_sensitivity(pset, search, factors, method="morris", samples=TRAJECTORIES, seed=seed,
                                excluded=excluded, workers=workers)
    data = result.to_dict()
    return {"seed": seed, "criterion": criterion, "factors": len(factors), "runs": data["n_runs"],
            "failed": data["failed"], "limits": data["limits"], "indices": data["indices"],
            "wall_s": time.perf_counter() - start}


def main() -> int:
    runs = [ranking(seed) for seed in SEEDS]
    order = [[r["parameter"] for r in run["indices"]] for run in runs]
    same_top5 = set(order[0][:5]) == set(order[1][:5])
    same_top3 = order[0][:3] == order[1][:3]
    for run in runs:
        print(f"seed {run['seed']}: {run['factors']} factors, {run['runs']} searches ({run['failed']} failed) in "
              f"{run['wall_s']:.0f} s; limits {run['limits']}")
        for rank, row in enumerate(run["indices"][:6], 1):
            print(f"  {rank}. {row['parameter']:<36} mu* {row['mu_star']:.2f} +/- {row['mu_star_conf']:.2f} km/h")
    print(f"same top-five set: {'yes' if same_top5 else 'NO'}; same top three in order: {'yes' if same_top3 else 'NO'}")
    out = Path(__file__).with_name("morris_seeds.json")
    out.write_text(json.dumps({"runs": runs, "same_top5_set": same_top5, "same_top3_order": same_top3}, indent=2))
    print(f"wrote {out}")
    return 0 if same_top5 and same_top3 else 1


if __name__ == "__main__":
    sys.exit(main())
