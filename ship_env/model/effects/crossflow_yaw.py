"""Cross-flow yaw damping: the hull's quadratic drag against turning, which holds at any speed.

The Nomoto model's yaw damping scales with the ship's speed: H(r*) (u / L)^2 with r* = L r / u
(2.40, 2.54), so at low speed -- a harbour approach, a ship stopping -- the damping fades and a
ship turned by its rudder, its propeller or the wind spins on. The hull's cross-flow drag does not
fade. By the cross-flow principle (strip theory), each strip of the hull at x from midships moves
sideways at x r through the water and meets the drag 1/2 rho T C_D |x r| x r per unit length
(Faltinsen 2005, *Hydrodynamics of High-Speed Marine Vehicles*, ch. 10; the hull cross-flow term
of the low-speed manoeuvring models, e.g. Oltmann & Sharma 1984). Integrated over the length,
-L/2 .. L/2, the yaw moment is

    N_cf = - 1/2 rho T C_D (L^4 / 32) |r| r

and the yaw acceleration it adds

    dr/dt += - c_cf |r| r,   c_cf = rho T C_D L^4 / (64 I_zz)   [1/rad]

with I_zz the ship's yaw inertia including the added inertia. With c_cf = 0 the effect vanishes.
With it on the yaw equation holds down to rest, and the effect widens the model's envelope to any
forward speed (``minimum_speed`` 0); going astern stays outside it.
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Envelope, Parameter, kernel

EFFECT = Effect(
    "crossflow_yaw",
    "cross-flow yaw damping (the hull's quadratic drag against turning, at any speed)",
    "dr/dt += -c_cf |r| r, c_cf = rho T C_D L^4 / (64 I_zz) (cross-flow principle, strip theory)",
    Parameter("coefficient", "1/rad", "c_cf, yaw acceleration per |r| r from the hull's cross-flow drag", 0.0),
    envelope=Envelope(minimum_speed=0.0),
)


@kernel
def yaw_acceleration(rate_of_turn, coefficient):
    """-c_cf |r| r, rad/s^2."""
    return -coefficient * abs(rate_of_turn) * rate_of_turn


CONTRIBUTIONS = (Contribution("yaw_acceleration", yaw_acceleration),)
