"""Analysis of records: comparison of a measured log with a simulation, or of two runs.

:mod:`trikedyn.analysis.compare` aligns two tables in time by cross-correlation, resamples them onto a
common time base and reports per-channel error metrics, as the paper's Figs. 7-8 compare measured and
simulated lateral acceleration and yaw rate.
"""
