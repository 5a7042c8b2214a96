"""What an effect adds to the ship's state derivative: its contributions to named quantities, and its states.

The model computes d(state)/dt in a fixed sequence of *quantities* (:data:`QUANTITIES`): the sway
velocity, the velocity over the ground, the apparent wind, the effective rudder and the rudder's
inflow, H(r*), the yaw accelerations and the speed-loss rate; then the rate of each state an effect
owns, ``<state>_derivative``. An effect declares, for each quantity it changes, a
:class:`Contribution`: a function of floats whose *argument names* say what it reads. ``dynamics``
composes the contributions of the effects that are registered into one compiled function; each runs
only where its effect is on.

A contribution either *adds* to its quantity or, when it takes the quantity itself as an
argument, *replaces* it (``effective_rudder(effective_rudder, angle)`` returns the new angle).
Contributions to one quantity run in the order the effects were registered.

An argument may name:

- a quantity computed before it (see :data:`QUANTITIES`, in order) or one of :data:`INPUTS`;
- a state variable (``heading``, ``speed_loss``, an effect's own state...; see ``state.MOTION_STATES``
  and the effects' :class:`State` s), with ``rudder`` the actual rudder at the instant;
- ``<state>_white_noise`` for a state of the effect driven by white noise (:attr:`State.white_noise`);
- one of the effect's own :class:`Draw` s by its name: the random numbers it drew where the ship started;
- a condition (``propeller_rate``, ``wind_speed``..., or the current's and the wind's velocity
  components derived from them, ``current_north``, ``wind_north``...; see ``state.CONDITION_NAMES``);
- a principal particular (``length``, ``draught``...);
- one of the effect's own parameters by its name (``gain``), or any effect's parameter by its
  record field (``propeller_slipstream_propeller_diameter``).

Two quantities belong to the step rather than to the derivative (the integrator evaluates them,
:data:`STEP_QUANTITIES`): a contribution ``held`` over the step (the sea's yaw excitation) and the
actual rudder a rudder actuator reaches (the steering machine).

An effect may also draw random numbers for each ship where it starts and hold them for the run
(:class:`Draw`: the sea's wave components, a bank's profile, gusts' phases).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

#: Values every contribution may read, computed first: u = U0 (1 - u*) (2.53), the speed floored at
#: ``minimum_speed`` where the model divides by it, r* = L r / u (2.40), cos(psi), sin(psi).
INPUTS: dict[str, str] = {
    "speed": "u, forward speed through the water, m/s (2.53)",
    "scheduling_speed": "u floored at the principal minimum_speed, m/s: use it where dividing by u",
    "normalised_rate": "r* = L r / u, the normalised rate of turn (2.40)",
    "cos_heading": "cos(psi)",
    "sin_heading": "sin(psi)",
}

#: The quantities, in the order they are computed, with their starting value and what they hold.
#: ``ground_velocity`` is a pair (north, east); a contribution that reads the apparent wind adds to
#: it after the wind is known (the wind is computed from the velocity over the ground before that).
#: The rates of the states effects own follow them, ``<state>_derivative``, starting at 0.
QUANTITIES: dict[str, tuple[str, str]] = {
    "sway_velocity": ("0.0", "v, sway velocity through the water, m/s, + to starboard (2.47)"),
    "ground_velocity": ("(0.0, 0.0)", "(dx0/dt, dy0/dt), velocity over the ground north and east, m/s (2.64)"),
    "relative_wind_speed": ("0.0", "V_wr, apparent wind speed, m/s (2.74); computed where an effect reads it"),
    "cos_wind": ("1.0", "cos(gamma_r), the apparent wind's angle off the bow (2.74)"),
    "sin_wind": ("0.0", "sin(gamma_r), + for a wind from starboard (2.74)"),
    "effective_rudder": ("rudder", "delta_e, the rudder angle that makes the rudder force, rad"),
    "inflow_speed_squared": ("speed * speed", "u_R^2, squared inflow speed at the rudder, m^2/s^2"),
    "restoring": ("0.0", "H(r*), the hull's yaw damping function of r* (2.27)"),
    "side_moment": ("0.0", "M_p, a side moment in the units of u_R^2 K* delta, m^2/s^2 (yaw.py)"),
    "hull_yaw_acceleration": ("0.0", "dr/dt from the rudder and the hull, rad/s^2 (2.54)"),
    "yaw_acceleration": (
        "held_yaw_acceleration",
        "dr/dt added by outside moments (wind, waves), rad/s^2; starts at the held contributions' sum",
    ),
    "speed_loss_derivative": ("0.0", "du*/dt, 1/s (2.55); acts where the speed_loss effect is on"),
}

#: The apparent wind: computed (2.74) only where an effect that reads it is on.
WIND = ("relative_wind_speed", "cos_wind", "sin_wind")

#: Quantities of the step, evaluated by the integrator, as ``QUANTITIES``; a contribution replaces them.
STEP_QUANTITIES: dict[str, tuple[str, str]] = {
    "actual_rudder": (
        "limited_order",
        "the actual rudder angle ``duration`` s into the step, rad: the ordered rudder clipped at the rudder "
        "limit (``limited_order``) unless an effect moves the rudder there itself (the steering machine); "
        "``rudder`` is the actual rudder at the start of the step",
    ),
}
#: The inputs only a step quantity's contributions may read.
STEP_INPUTS: dict[str, tuple[str, ...]] = {"actual_rudder": ("limited_order", "duration")}

#: Contributions ``held`` over a step may add to these quantities only.
HELD_QUANTITIES = ("yaw_acceleration",)


def derivative_quantity(state: str) -> str:
    """The quantity that holds a state's rate: ``<state>_derivative``."""
    return f"{state}_derivative"


def white_noise_input(state: str) -> str:
    """The input that holds the white noise driving a state: ``<state>_white_noise``."""
    return f"{state}_white_noise"


@dataclass(frozen=True)
class Contribution:
    """One effect's term in one quantity of the state derivative.

    Attributes:
        quantity: the quantity it changes (a key of :data:`QUANTITIES`, ``<state>_derivative`` or
            one of :data:`STEP_QUANTITIES`).
        function: a function of floats (compiled with ``ship_env.model.kernel.kernel``, or plain
            Python, which is then compiled); its argument names say what it reads (module
            docstring). It returns the quantity's new value if it reads the quantity, else the
            amount it adds (a pair for ``ground_velocity``).
        held: evaluated once per step and held over it (an excitation that would be costly to
            evaluate at every stage, as the sea's): with the time at mid-step, the other states
            at the step's start. Only for :data:`HELD_QUANTITIES`.
    """

    quantity: str
    function: Callable[..., Any]
    held: bool = False


@dataclass(frozen=True)
class State:
    """A state variable an effect owns: integrated with the ship's, at the rate the effect gives.

    Its rate is the quantity ``<name>_derivative``, to which the effect contributes; where the effect
    is off the state stays at its initial value. A state of the ship's motion
    (``state.MOTION_STATES``) may be named instead: the effect then governs its rate (``speed_loss``).

    Attributes:
        name: unique among the states of the motion and of every registered effect.
        unit: its SI unit.
        description: what it holds, with the thesis symbol where there is one.
        initial: its value where a ship starts (a reset, the first sample of a replayed log): a
            number, or a function whose argument names read the motion's states, the conditions, the
            :data:`INPUTS` (u, r*), principal particulars and parameters as a contribution's do (a lag
            that starts settled at the actual rudder: ``lambda rudder: rudder``; a drift settled at its
            r*'s value: ``sway_lag``'s).
        white_noise: None, or a function (arguments as a contribution's) of the intensity with which
            unit white noise ``<name>_white_noise`` drives the state: the effect's contributions read
            that input; a step draws the noise only where an intensity is not zero.
    """

    name: str
    unit: str
    description: str
    initial: float | Callable[..., float] = 0.0
    white_noise: Callable[..., float] | None = None


@dataclass(frozen=True)
class Draw:
    """Random numbers an effect draws for each ship where it starts (a reset) and holds for the run.

    The simulator draws ``uniforms``, samples uniform in (0, 1) from the ship's seed (so a seed
    repeats them, and a ship of a batch draws what a single run with its seed does), and hands
    them to ``function``; the effect's contributions read the result by the draw's ``name``, an
    array of ``shape`` (the sea's components: frequency, amplitude and phase of each).

    Attributes:
        name: the argument the effect's contributions read it by, unique among the names they read.
        unit: the SI unit of its values.
        description: what it holds.
        shape: its shape for one ship: whole numbers, or names of the effect's whole-number
            parameters (``(3, "components")``).
        function: the numbers from the uniforms, for all ships being started at once: its argument
            ``uniforms`` is an array ``(ships, *uniforms)``; other arguments name a condition (an array,
            one value per ship: those of ``state.CONDITION_NAMES`` and ``state.START_CONDITION_NAMES``),
            a principal particular or a parameter, as a contribution's do. It returns
            ``(ships, *shape)`` finite numbers.
        uniforms: the shape of the uniform samples one ship's draw takes (as ``shape``); None: ``shape``.
    """

    name: str
    unit: str
    description: str
    shape: tuple[int | str, ...]
    function: Callable[..., Any]
    uniforms: tuple[int | str, ...] | None = None
