"""The workbench's first stage, the logs: ``formats`` (the declared columns and units of a log
file, :class:`~ship_env.workbench.logs.formats.LogFormat`), ``logs`` (reading, checking and
writing logs, :class:`~ship_env.workbench.logs.logs.Log`) and ``channel_smoother`` (a noisy
channel's value, rate and acceleration, filterpy's Kalman filter and RTS smoother).

Layer rule: the workbench's stages are, in order, ``logs``, ``fitting``, ``judging``, ``deciding``,
``reporting`` and ``synthetic``; a stage imports only from the stages before it, from
``ship_env.workbench.defaults`` and ``.outputs``, and from outside the workbench. ``logs`` is the
first: of the workbench it imports ``defaults`` and ``outputs`` alone (``tests/test_import_layers.py``).

The modules are imported when asked for (``ship_env.workbench.logs.logs``); this package imports nothing.
"""
