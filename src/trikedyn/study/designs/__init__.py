"""The study designs: what to evaluate, each handing its evaluations to the engine (:mod:`trikedyn.study.engine`:
:func:`~trikedyn.study.engine.loop.drive`, through :class:`~trikedyn.study.engine.pool.ResilientPool` for the
sampled designs); none runs a scheduling loop of its own (the optimiser's generations are scipy's
differential evolution asking the engine to evaluate each population).

- :mod:`~trikedyn.study.designs.runner`: the grid study (a spec's scenarios into the SQLite store;
  :mod:`~trikedyn.study.designs.study_run`: its outcome and folder), with its figures
  (:mod:`~trikedyn.study.designs.figures`, over :mod:`~trikedyn.study.designs.effects`);
- :mod:`~trikedyn.study.designs.sensitivity`: Morris elementary effects and Sobol indices
  (:mod:`~trikedyn.study.designs.sensitivity_methods`) over the assumed values
  (:mod:`~trikedyn.study.designs.factors`, :mod:`~trikedyn.study.designs.vehicle_values`);
- :mod:`~trikedyn.study.designs.uncertainty`: uncertainty propagation (Latin hypercube over the assumed and
  measured values: :mod:`~trikedyn.study.designs.uncertain_inputs`,
  :mod:`~trikedyn.study.designs.measured_sigmas`);
- :mod:`~trikedyn.study.designs.loading`: the loading chart (threshold over payload and its position;
  :mod:`~trikedyn.study.designs.loading_grid`);
- :mod:`~trikedyn.study.designs.optimise`: the optimiser (differential evolution over design knobs,
  :mod:`~trikedyn.study.designs.optimise_log`);
- :mod:`~trikedyn.study.designs.sample_runs`: the sampled designs' evaluations (a
  :class:`~trikedyn.study.designs.search.Search` per sample: the threshold or any registered study metric),
  their logs (:mod:`~trikedyn.study.designs.csv_log`) and the threshold limits' counts
  (:mod:`~trikedyn.study.designs.limits`);
- :mod:`~trikedyn.study.designs.named`: the names of a design's figures when its metric is not the threshold.
"""
