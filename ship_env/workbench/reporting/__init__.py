"""The workbench's fifth stage, reporting: ``tables`` (text tables), ``report`` (the Markdown report
with its drawings), ``documents`` (the JSON documents of a fit or a ladder, and a fitted model read
back) and ``presets`` (a fit written as a ship preset).

Layer rule: the workbench's stages are, in order, ``logs``, ``fitting``, ``judging``, ``deciding``,
``reporting`` and ``synthetic``; a stage imports only from the stages before it, from
``ship_env.workbench.defaults`` and ``.outputs``, and from outside the workbench. ``reporting`` may
import ``logs``, ``fitting``, ``judging`` and ``deciding`` (``tests/test_import_layers.py``).

The modules are imported when asked for (``ship_env.workbench.reporting.report``); this package
imports nothing.
"""
