"""Everything an effect is written with, in one import, for the built-in effects and your own.

One line imports it::

    from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel

An effect is a module (or a notebook cell) that declares

- ``EFFECT = Effect(name, title, equations, *parameters)``: its name, its words, the equations it
  implements and its :class:`Parameter` s one after another (``required=``, and ``envelope=`` an
  :class:`Envelope` where it widens the model's validity);
- ``CONTRIBUTIONS``: its :class:`Contribution` s to the quantities of the state derivative
  (:data:`QUANTITIES`, in the order they are computed), functions of floats whose argument names
  say what they read (see ``ship_env.model.contributions``), compiled with :func:`kernel`;
- ``STATES``: the state variables it owns, if any: :class:`State` s (unit, words, initial value,
  whether white noise drives it), each with a contribution to its rate ``<name>_derivative``;
- ``DRAWS``: the random numbers it draws for each ship where the ship starts, if any: :class:`Draw` s
  (unit, words, shape, a function of uniform samples from the ship's seed and of the conditions),
  which its contributions read by name (``wave_spectrum``'s sea).

``ship_env/model/effects/norrbin.py`` is the shortest built-in, ``examples/rudder_stall.py`` an
effect written outside ``ship_env``. The built-ins are listed in ``ship_env.model.effects``; an
effect written outside ``ship_env`` registers with :func:`register_effect` or an entry point (see
``ship_env.model.registry``).
"""

from ship_env.model.contributions import QUANTITIES, Contribution, Draw, State
from ship_env.model.declarations import Effect, Envelope, Parameter
from ship_env.model.kernel import kernel
from ship_env.model.registry import register_effect

__all__ = [
    "QUANTITIES",
    "Contribution",
    "Draw",
    "Effect",
    "Envelope",
    "Parameter",
    "State",
    "kernel",
    "register_effect",
]
