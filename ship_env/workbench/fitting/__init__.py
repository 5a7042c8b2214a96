"""The workbench's second stage, fitting the model to the logs: ``replay`` (the model driven by the
measured inputs), ``terms`` (what can be fitted), ``errors`` (RMS errors and the score),
``envelope`` (where the model holds), ``runs`` (the logs screened against the envelope), ``fit``
(output-error least squares), ``uncertainty`` (the fitted terms' covariance from the Jacobian),
``threads`` and ``parallel`` (one BLAS thread, worker processes).

Layer rule: the workbench's stages are, in order, ``logs``, ``fitting``, ``judging``, ``deciding``,
``reporting`` and ``synthetic``; a stage imports only from the stages before it, from
``ship_env.workbench.defaults`` and ``.outputs``, and from outside the workbench. ``fitting`` may
import ``logs`` (``tests/test_import_layers.py``).

The modules are imported when asked for (``ship_env.workbench.fitting.fit``); this package imports
nothing, so that the command line, which imports ``parallel``, parses its arguments first.
"""
