"""What-if scenarios: scenario files, runs in virtual time, metrics and starvation diagnosis
computed from the event log, plots, and parameter sweeps (local process pool or Dask).

Entry points: :func:`app.scenarios.model.load_scenario`, :func:`app.scenarios.runner.run`,
:func:`app.scenarios.report.report`, :mod:`app.scenarios.sweep`; the ``motionsim run`` and
``motionsim sweep`` commands live in :mod:`app.scenarios.cli`.
"""
