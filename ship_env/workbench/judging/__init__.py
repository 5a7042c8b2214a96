"""The workbench's third stage, judging a fit: ``coverage`` (the operating points the fitted runs
covered), ``validation`` (leave one run out), ``materiality`` (whether a fitted effect is large enough to be physical),
``bands`` (prediction bands from the jackknife fits), ``compare`` (errors and drawings) and ``free_running`` (the
fitted preset sailed through the measured manoeuvres).

Layer rule: the workbench's stages are, in order, ``logs``, ``fitting``, ``judging``, ``deciding``,
``reporting`` and ``synthetic``; a stage imports only from the stages before it, from
``ship_env.workbench.defaults`` and ``.outputs``, and from outside the workbench. ``judging`` may
import ``logs`` and ``fitting`` (``tests/test_import_layers.py``).

The modules are imported when asked for (``ship_env.workbench.judging.validation``); this package
imports nothing.
"""
