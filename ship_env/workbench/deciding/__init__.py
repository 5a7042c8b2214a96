"""The workbench's fourth stage, deciding what the model lacks: ``signals`` (past the library: the
measured signals that the missing yaw acceleration lines up with), ``diagnose`` (the missing
physical effects, ranked), ``improve`` (the error ladder: add effects while the held-out error
falls) and ``rivals`` (the forms the runs could not tell from those the ladder added, sailed beside its preset).

Layer rule: the workbench's stages are, in order, ``logs``, ``fitting``, ``judging``, ``deciding``,
``reporting`` and ``synthetic``; a stage imports only from the stages before it, from
``ship_env.workbench.defaults`` and ``.outputs``, and from outside the workbench. ``deciding`` may
import ``logs``, ``fitting`` and ``judging`` (``tests/test_import_layers.py``).

The modules are imported when asked for (``ship_env.workbench.deciding.improve``); this package
imports nothing.
"""
