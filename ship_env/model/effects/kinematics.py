"""Kinematics: the ship's velocity over the ground from its speed, drift and heading (2.64, 2.65).

    dx0/dt = u cos(psi) - v sin(psi)                                                 (2.64)
    dy0/dt = u sin(psi) + v cos(psi)                                                 (2.65)
    dpsi/dt = r

x0 points north, y0 east, psi is clockwise from north; v is positive to starboard.
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, kernel

EFFECT = Effect(
    "kinematics",
    "track over the ground from speed, drift and heading",
    "(2.64), (2.65)",
    required=True,
)


@kernel
def velocity_over_ground(speed, sway_velocity, cos_heading, sin_heading):
    """(dx0/dt, dy0/dt) in m/s from (2.64, 2.65), given cos(psi) and sin(psi)."""
    return (
        speed * cos_heading - sway_velocity * sin_heading,
        speed * sin_heading + sway_velocity * cos_heading,
    )


CONTRIBUTIONS = (Contribution("ground_velocity", velocity_over_ground),)
