"""The study engine under every design: where evaluations run and how they are kept.

- :mod:`~trikedyn.study.engine.executors`: the executors (in this process, a process pool) and the choice
  among them from a run's options (``workers``, ``dask_local``, ``scheduler``);
  :mod:`~trikedyn.study.engine.dask`: the Dask executor (a local cluster, or a scheduler);
- :mod:`~trikedyn.study.engine.loop`: the one scheduling loop (:func:`~trikedyn.study.engine.loop.drive`:
  a window of calls in flight, each collected as it finishes, a stop flag, lost workers and a lost scheduler
  said back rather than waited for);
- :mod:`~trikedyn.study.engine.pool`: calls that survive dead workers (the sampled designs: sensitivity,
  uncertainty, the loading chart, the optimiser);
- :mod:`~trikedyn.study.engine.store` and :mod:`~trikedyn.study.engine.table`: the grid study's resumable
  SQLite store and its table; :mod:`~trikedyn.study.engine.database`: the store's file (tables, transactions)
  and its folder's writer lock;
- :mod:`~trikedyn.study.engine.progress`: progress on a terminal or in a log.
"""
