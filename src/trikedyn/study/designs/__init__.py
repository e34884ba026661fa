"""The study designs: what to evaluate, each handing its evaluations to the engine (:mod:`trikedyn.study.engine`).

- :mod:`~trikedyn.study.designs.runner`: the grid study (a spec's scenarios into the SQLite store), with its
  figures (:mod:`~trikedyn.study.designs.figures`);
- :mod:`~trikedyn.study.designs.sensitivity`: Morris elementary effects and Sobol indices over the assumed values
  (:mod:`~trikedyn.study.designs.factors`);
- :mod:`~trikedyn.study.designs.uncertainty`: uncertainty propagation (Monte Carlo over the assumed and measured
  values);
- :mod:`~trikedyn.study.designs.loading`: the loading chart (threshold over payload and its position);
- :mod:`~trikedyn.study.designs.optimise`: the optimiser (differential evolution over design knobs,
  :mod:`~trikedyn.study.designs.optimise_log`);
- :mod:`~trikedyn.study.designs.sample_runs`: the sampled designs' evaluations (a threshold search or any
  registered study metric per sample), their logs (:mod:`~trikedyn.study.designs.csv_log`) and the threshold
  limits' counts (:mod:`~trikedyn.study.designs.limits`).
"""
