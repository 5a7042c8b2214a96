"""The workbench's sixth stage, logs made by the simulator, for checking the workbench on a known
truth: ``synthetic`` (runs sailed with chosen effects and noise) and ``demo_logs``
(``ship-env demo-logs``: such logs written as CSV with their truth, to try the workbench on).

Layer rule: the workbench's stages are, in order, ``logs``, ``fitting``, ``judging``, ``deciding``,
``reporting`` and ``synthetic``; a stage imports only from the stages before it, from
``ship_env.workbench.defaults`` and ``.outputs``, and from outside the workbench. ``synthetic``, the
last, may import every other stage (``tests/test_import_layers.py``).

The modules are imported when asked for (``ship_env.workbench.synthetic.synthetic``); this package
imports nothing.
"""
