"""A run metric from outside the package: the span of the judged window [s]."""

from trikedyn.analysis.metrics import judged_mask, metric

NAME = "test_window_span_s"


@metric(NAME, "s", "time from the first to the last judged sample")
def window_span(result):
    """Time [s] the run spends in its judged window."""
    times = result.time_s[judged_mask(result)]
    return float(times[-1] - times[0]) if times.size else None
