"""Hull cross-flow drag in yaw: strip theory's non-linear yaw damping, growing as |r*| r* (beyond the thesis).

Each strip dx of the hull at x (from midships, + forward) meets the water sideways at the local
lateral velocity v + x r and is dragged like a plate in cross-flow, with its draught T and a
cross-flow drag coefficient C_D (the cross-flow principle: Hooft 1994; Oltmann & Sharma 1984's hull
forces; Fossen 2011, sec. 6.4). Over the length L the strips' yaw moment is

    N_cf = -1/2 rho T C_D  integral_{-L/2}^{L/2} x |v + x r| (v + x r) dx

In the model's variables x = xi L, v* = v / u, r* = L r / u (2.40), v + x r = u (v* + xi r*):

    N_cf = -1/2 rho T C_D L^2 u^2 I(v*, r*),  I(v*, r*) = integral_{-1/2}^{1/2} xi |v* + xi r*| (v* + xi r*) dxi

and in the yaw equation (2.54), where dr/dt = (u/L)^2 (K* delta - H(r*)) / tau*, it is a part of H:

    H(r*) += 32 c_cf I(v*, r*),   c_cf = tau* (1/2 rho T C_D L^4) / (32 (I_z + J_z))

c_cf, the one coefficient, is the |r*| r* coefficient at zero drift: I(0, r*) = |r*| r* / 32. In
closed form (s = v* +- r*/2 at the bow and the stern, F(s) = s^3 |s| / 4 - v* s^2 |s| / 3):

    I = |v*| r* / 6                          where |v*| >= |r*| / 2 (the flow does not change side)
    I = (F(v* + r*/2) - F(v* - r*/2)) / r*^2  else (the pivot point x = -v*/r* lies on the hull)

v* is the sway effect's drift (2.47-2.49; 0 without it). With the linear sway v* = -gamma1* r*
(2.60) the pivot point lies gamma1* L forward of midships, the aft body meets the more cross-flow,
and the term is |r*| r* times c_cf g(gamma1*), g = 1 + 8 gamma^2 - 16 gamma^4 / 3 for |gamma| <= 1/2
and 16 |gamma| / 3 beyond: Norrbin's alpha2' (``norrbin``) with the sign of a drag (c_cf >= 0) and
the drift's share that strip theory gives. Steady turn (2.26): r* + c_cf g r*|r*| = K* delta.

Why it extrapolates: a turning circle's r* (0.5-1 at hard over) lies beyond a zig-zag's (0.1-0.3).
A cubic alpha3 r*^3 fitted where r* is small grows with the cube beyond it; the cross-flow drag grows
with the square, as the hull's resistance to a flow across it does, so a value fitted on zig-zags
predicts a tight turn more gently. Yasukawa & Yoshimura (2015, the MMG standard) fit the same
non-linear damping as polynomials in v' and r' (N'_vvr, N'_vrr, N'_rrr) inside their model tests'
range; Hooft (1994) shows the cross-flow integral reproduces them from one drag coefficient. The
sway force of the same drag is left out: the model's sway is algebraic (``sway``), its gammas hold it.

Smallest physical size (``material``): c_cf = 0.05 changes H(r*), and so the steady rate of turn,
by 2.5 % at r* = 0.5 without drift (as Norrbin's alpha2' = 0.05).

Sources: J. P. Hooft (1994), The cross-flow drag on a manoeuvring ship, Ocean Engineering 21(3),
329-342; P. Oltmann and S. D. Sharma (1984), Simulation of combined engine and rudder maneuvers using
an improved model of hull-propeller-rudder interactions, 15th Symposium on Naval Hydrodynamics,
Hamburg; T. I. Fossen (2011), Handbook of Marine Craft Hydrodynamics and Motion Control, Wiley,
sec. 6.4; H. Yasukawa and Y. Yoshimura (2015), Introduction of MMG standard method for ship
maneuvering predictions, J. Marine Science and Technology 20, 37-52.
"""

from __future__ import annotations

from ship_env.model.effect_api import Contribution, Effect, Parameter, kernel

EFFECT = Effect(
    "hull_crossflow",
    "hull cross-flow drag in yaw (strip theory: damping as |r*| r*, with the drift's pivot point)",
    "(2.27), (2.40), (2.54), (2.60)",
    Parameter(
        "coefficient",
        "-",
        "c_cf, the cross-flow yaw damping's |r*| r* coefficient at zero drift",
        minimum=0.0,
        maximum=100.0,
        default=0.0,
        source="the null value: no cross-flow drag until a fit finds it",
        null=0.0,
        material=0.05,
    ),
)


@kernel
def _cube_part(side_velocity, drift):
    """F(s) of the closed form: the antiderivative of (s - v*) |s| s over s, times r*^2."""
    magnitude = abs(side_velocity)
    return side_velocity**3 * magnitude / 4.0 - drift * side_velocity * side_velocity * magnitude / 3.0


@kernel
def crossflow_integral(drift, normalised_rate):
    """I(v*, r*) = integral over xi in [-1/2, 1/2] of xi |v* + xi r*| (v* + xi r*) (module docstring)."""
    if abs(drift) >= 0.5 * abs(normalised_rate):
        return abs(drift) * normalised_rate / 6.0
    bow = drift + 0.5 * normalised_rate
    stern = drift - 0.5 * normalised_rate
    return (_cube_part(bow, drift) - _cube_part(stern, drift)) / (normalised_rate * normalised_rate)


@kernel
def restoring(normalised_rate, sway_velocity, scheduling_speed, coefficient):
    """The cross-flow part of H(r*): 32 c_cf I(v*, r*), v* = v / u."""
    return 32.0 * coefficient * crossflow_integral(sway_velocity / scheduling_speed, normalised_rate)


CONTRIBUTIONS = (Contribution("restoring", restoring),)
