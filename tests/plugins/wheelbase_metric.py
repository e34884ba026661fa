"""A study metric from outside the package: the wheelbase of the varied vehicle, scaled by an option."""

from trikedyn.options import Option
from trikedyn.study.metrics import study_metric

NAME = "test_wheelbase"


@study_metric(NAME, unit="m", per_manoeuvre=False,
              options=(Option("factor", 1.0, "", "scale of the wheelbase", minimum=0.5, maximum=2.0),))
def wheelbase(pset, scenario, factor):
    """the vehicle's wheelbase times a factor (a metric registered by a test plug-in)"""
    return {"value": factor * float(pset.params.wheelbase_m)}
