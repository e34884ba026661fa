"""Everything specific to the reference paper, "Electric Delta Trike Stability Characteristic and
Maneuverability Analysis: Experiment and Multi-Body Dynamic Simulation" (``shared/seed/``).

- :mod:`trikedyn.paper.data` -- the paper's published numbers (Tables 1-3, masses, CG), for comparison only;
- :mod:`trikedyn.paper.reproduce` -- ``trikedyn reproduce``: the measurement side (section 2.1: audit,
  Table 1 by Eqs. 1-4 and by identification, Table 3) and the whole workflow;
- :mod:`trikedyn.paper.model_side` -- the model side (sections 2.3-3: the model's bump test, the lane
  changes, the rollover index, the parametric study of Fig. 10);
- :mod:`trikedyn.paper.report` -- the reproduction's report: its sections, figures, animations;
- :mod:`trikedyn.paper.html` -- the report rendered from the Jinja2 templates in ``paper/templates/``.

The paper's parametric study (Fig. 10) is the built-in study spec :data:`STUDY_SPEC`
(``trikedyn/study/specs/paper.toml``, run by ``trikedyn study paper``), kept with the other built-in specs.
"""

from __future__ import annotations

__all__ = ["STUDY_SPEC", "reproduce"]

from .data import STUDY_SPEC


def __getattr__(name):
    if name == "reproduce":  # imported on first use: the reproduction loads the model and matplotlib
        from .reproduce import reproduce

        return reproduce
    raise AttributeError(f"module 'trikedyn.paper' has no attribute {name!r}")
