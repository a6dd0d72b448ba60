"""What-if scenarios: scenario files, runs in virtual time, metrics and starvation diagnosis
computed from the event log, plots, and parameter sweeps (local process pool or Dask).

Entry points: :func:`motionsim.app.scenarios.model.load_scenario`,
:func:`motionsim.app.scenarios.runner.run`, :func:`motionsim.app.scenarios.report.report`,
:mod:`motionsim.app.scenarios.sweep`; the ``motionsim run`` and ``motionsim sweep`` commands live
in :mod:`motionsim.app.scenarios.cli`.
"""
