"""A design's figures named by what they are: the threshold's keys and columns end in ``_kmh``; another study
metric's value (``--metric``: a tilt angle in deg, an understeer gradient in deg/g ...) is named neutrally.

The four designs (sensitivity, uncertainty, loading chart, optimiser) build their results with the threshold's
names; with another metric, :func:`by_metric` renames the JSON keys (``reference_threshold_speed_kmh`` ->
``reference_value``, ``median_kmh`` -> ``median``, ``threshold_speed_kmh`` -> ``value`` ...; the ``metric`` and
``unit`` keys beside them say what and in which unit) and :func:`column` names a CSV column by the metric
(``threshold_speed_kmh`` -> ``tilt_angle``, ``worst_threshold_speed_kmh`` -> ``worst_tilt_angle``,
``threshold_dlc_kmh`` -> ``tilt_angle_dlc``): a CSV file has no ``unit`` beside it, so its header says which
metric. With the threshold both leave every name as it is.
"""

from __future__ import annotations

__all__ = ["JSON_NAMES", "THRESHOLD", "by_metric", "column", "meets_the_course"]

THRESHOLD = "threshold"
"""The default metric, whose names are the ``_kmh`` ones."""

JSON_NAMES = {
    "threshold_speed_kmh": "value",
    "reference_threshold_speed_kmh": "reference_value",
    "best_threshold_speed_kmh": "best_value",
    "worst_threshold_speed_kmh": "worst_value",
    "gain_kmh": "gain",
    "median_kmh": "median",
    "p05_kmh": "p05",
    "p95_kmh": "p95",
    "mean_kmh": "mean",
    "std_kmh": "std",
    "thresholds": "values",
    "vehicle_file_thresholds_kmh": "vehicle_file_values",
}
"""A threshold's JSON key -> the key of another metric's value (in the metric's unit)."""


def by_metric(data, metric: str):
    """``data`` (a design's JSON output: dicts and lists) with its keys named for ``metric``.

    Parameters
    ----------
    data : dict or list
        The output, with the threshold's keys.
    metric : str
        The study metric its values are of.

    Returns
    -------
    dict or list
        ``data`` itself for the threshold; else a copy with every key of :data:`JSON_NAMES` renamed, at any
        depth (none of them is a factor's, a knob's or a manoeuvre's name).
    """
    if metric == THRESHOLD:
        return data
    if isinstance(data, dict):
        return {JSON_NAMES.get(k, k): by_metric(v, metric) for k, v in data.items()}
    if isinstance(data, list):
        return [by_metric(v, metric) for v in data]
    return data


def column(name: str, metric: str) -> str:
    """A CSV column of the threshold's, named for ``metric``.

    Parameters
    ----------
    name : str
        ``threshold_speed_kmh``, ``worst_threshold_speed_kmh`` or ``threshold_MANOEUVRE_kmh``.
    metric : str
        The study metric the column holds.

    Returns
    -------
    str
        ``name`` for the threshold; else ``METRIC``, ``worst_METRIC`` or ``METRIC_MANOEUVRE``.
    """
    if metric == THRESHOLD:
        return name
    if name == "threshold_speed_kmh":
        return metric
    if name == "worst_threshold_speed_kmh":
        return f"worst_{metric}"
    if name.startswith("threshold_") and name.endswith("_kmh"):
        return f"{metric}_{name[len('threshold_'):-len('_kmh')]}"
    raise ValueError(f"not a threshold column: {name!r}")


def meets_the_course(metric: str) -> bool:
    """The metric runs the manoeuvre (the threshold, ``peak_ri`` ...), so the course it is laid out on counts; a
    quasi-static one (``tilt_angle``, ``understeer_gradient``) meets no course.

    Parameters
    ----------
    metric : str
        A registered study metric.

    Returns
    -------
    bool
        The metric is per manoeuvre.
    """
    from ..metrics import get

    return get(metric).per_manoeuvre
