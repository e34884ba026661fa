"""Hypothesis profiles: a small deterministic share in `make test`, a long campaign in `make fuzz`.

``TRIKEDYN_FUZZ_EXAMPLES=N`` (set by ``make fuzz``) runs N examples per input kind, randomised; otherwise
each kind runs a few dozen derandomised examples (the CI budget, well under a minute in all).
"""

import os

from hypothesis import HealthCheck, settings

_common = {"deadline": None, "suppress_health_check": [HealthCheck.too_slow, HealthCheck.function_scoped_fixture]}
settings.register_profile("ci", max_examples=30, derandomize=True, **_common)
settings.register_profile("campaign", max_examples=int(os.environ.get("TRIKEDYN_FUZZ_EXAMPLES", "1000")),
                          database=None, **_common)
settings.load_profile("campaign" if "TRIKEDYN_FUZZ_EXAMPLES" in os.environ else "ci")
