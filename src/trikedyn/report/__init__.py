"""Figures and animations of runs and studies (matplotlib). The reference paper's report is in
:mod:`trikedyn.paper` (:mod:`trikedyn.paper.report`, rendered by :mod:`trikedyn.paper.html`)."""
