"""Propeller astern: the rudder loses its inflow and the propeller walks the stern sideways.

A harbour manoeuvre stops the ship by reversing the propeller while it still makes way ahead. The
reversed propeller pushes water forward, against the flow past the stern: the rudder, which sits
behind it, sees less inflow and loses its grip (Brix 1993, *Manoeuvring Technical Manual*, 2.1.4;
the astern regime of the MMG rudder model, Yasukawa & Yoshimura 2015, J. Mar. Sci. Technol. 20,
where the rudder force is set by the propeller's reversed flow). The model takes

    u_R^2 = max(u_R^2 - c_a (n D)^2, 0)                           for n < 0

in place of the rudder's inflow (see ``yaw``, ``propeller_slipstream``, which acts for n > 0 only).
A single-screw propeller turning astern also *walks*: its blades meet the water unevenly across
the disc and push the stern sideways, much harder than when turning ahead (a right-handed
propeller walks the stern to port). As a yaw moment in the units of the rudder's (yaw.py):

    M_w = c_w (n D)^2                                              for n < 0, + turns the bow to port

With c_a = c_w = 0 the effect vanishes. With it on the model holds with the propeller astern: the
effect widens the envelope to both propeller directions.

Symbols: n propeller rate (rps, negative astern), D propeller diameter (m,
``propeller_slipstream.propeller_diameter``).

Smallest physical sizes (``material``): c_a = 0.01 and c_w = 0.003 each change the rudder's inflow or
moment by a few % at (n D / u)^2 = 3 and 10 deg of rudder with K* = 1.5 (as ``propeller_slipstream``
and ``asymmetry``'s side force).
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Envelope, Parameter, kernel

EFFECT = Effect(
    "propeller_astern",
    "propeller astern (the rudder loses its inflow; the propeller walks the stern sideways)",
    "u_R^2 = max(u_R^2 - c_a (n D)^2, 0) and a side moment c_w (n D)^2 for n < 0, in (2.54)",
    Parameter(
        "rudder_inflow", "-", "c_a, fraction of (n D)^2 taken from the rudder inflow astern", minimum=0.0, material=0.01
    ),
    Parameter(
        "walk",
        "-",
        "c_w, propeller walk astern per (n D)^2 in the units of K* u^2 delta; + turns to port",
        material=0.003,
    ),
    envelope=Envelope(propeller_ahead_only=False),
)


@kernel
def inflow_speed_squared(inflow_speed_squared, propeller_rate, propeller_slipstream_propeller_diameter, rudder_inflow):
    """u_R^2 less c_a (n D)^2 for a propeller astern, not below 0, m^2/s^2."""
    if propeller_rate >= 0.0:
        return inflow_speed_squared
    induced = propeller_rate * propeller_slipstream_propeller_diameter
    return max(inflow_speed_squared - rudder_inflow * induced * induced, 0.0)


@kernel
def walk_moment(propeller_rate, propeller_slipstream_propeller_diameter, walk):
    """c_w (n D)^2 for a propeller astern, m^2/s^2 (the units of u_R^2 K* delta)."""
    if propeller_rate >= 0.0:
        return 0.0
    induced = propeller_rate * propeller_slipstream_propeller_diameter
    return walk * induced * induced


CONTRIBUTIONS = (
    Contribution("inflow_speed_squared", inflow_speed_squared),
    Contribution("side_moment", walk_moment),
)
