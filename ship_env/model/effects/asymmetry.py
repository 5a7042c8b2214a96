"""Port-starboard asymmetry of the turning: the propeller's side force and the even terms of H(r*).

    dr/dt = [ u_R^2 K* delta_e - u^2 H(r*) - c_p (n D)^2 ] / (tau* L^2)              (2.54 + side force)
    H(r*) = ... + alpha0 + alpha2 r*^2                                               (2.27)

A single-screw ship does not turn alike to port and starboard. Its propeller pushes the stern
sideways (the side force or "propeller walk", c_p (n D)^2, largest at high propeller rate and low
speed: a model accelerating from rest), and the asymmetric flow over the stern makes it turn
tighter to one side (alpha2) or turn at zero rudder (alpha0: steady r* = -alpha0 to first order;
like a rudder offset, it scales with speed squared, so a fit cannot tell the two apart and
estimates the offset, ``rudder_offset``). With c_p = alpha0 = alpha2 = 0 the effect vanishes.

Symbols: n propeller rate (rps), D propeller diameter (m, ``propeller_slipstream.propeller_diameter``),
c_p side-force coefficient (positive turns the ship to port), alpha0 constant and alpha2 quadratic
coefficients of H(r*).

Smallest physical sizes (``material``): c_p = 0.003 is 3 % of the rudder moment K* u^2 delta at
10 deg of rudder with K* = 1.5 and (n D / u)^2 = 3; alpha0 = 0.01 turns the ship like a rudder offset
of 0.3 deg (K* delta_0, see ``rudder_offset``); alpha2 = 0.05 changes H(r*) by 2.5 % at r* = 0.5.
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel

EFFECT = Effect(
    "asymmetry",
    "port-starboard asymmetry (propeller side force, asymmetric stern flow)",
    "(2.27), (2.54) with a propeller side force",
    Parameter(
        "side_force",
        "-",
        "c_p, propeller side force per (n D)^2 in the units of K* u^2 delta; + turns to port",
        material=0.003,
    ),
    Parameter("constant", "-", "alpha0 of H(r*): steady r* at zero rudder is -alpha0 / alpha1", material=0.01),
    Parameter("quadratic", "-", "alpha2 of H(r*): the ship turns tighter to port for alpha2 > 0", material=0.05),
)


@kernel
def restoring(normalised_rate, constant, quadratic):
    """The constant and quadratic part of H(r*) (2.27)."""
    return constant + quadratic * normalised_rate * normalised_rate


@kernel
def side_force_moment(propeller_rate, propeller_slipstream_propeller_diameter, side_force):
    """c_p (n D)^2, m^2/s^2: the propeller's yaw moment in the units of u_R^2 K* delta."""
    induced = propeller_rate * propeller_slipstream_propeller_diameter
    return side_force * induced * induced


CONTRIBUTIONS = (Contribution("restoring", restoring), Contribution("side_moment", side_force_moment))
