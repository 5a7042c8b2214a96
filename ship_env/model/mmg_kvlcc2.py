"""shipmmg's MMG model of KVLCC2 behind the external-dynamics protocol (optional: ``pip install shipmmg``).

Reference: shipmmg 0.0.11 (``shipmmg.mmg_3dof.simulate_mmg_3dof``) with the KVLCC2 parameters of
Yasukawa & Yoshimura (2015), "Introduction of MMG standard method for ship maneuvering
predictions", J Mar Sci Technol 20:37-52, Tables 1-3, as shipmmg's own tests use them
(model L_pp = 7.00 m). The model-scale particulars are Froude-scaled to the full-scale ship
(lambda = 320 / 7 = 45.714: lengths x lambda, areas x lambda^2, displacement x lambda^3,
propeller rate / sqrt(lambda)); the MMG equations have no Reynolds-dependent term, so the
full-scale run is the model-scale run with time and speed scaled by sqrt(lambda).

:class:`MmgKvlcc2` steps it closed loop, one ``simulate_mmg_3dof`` call per step (the rudder
moves linearly over the step, towards the order at the SIMMAN rudder rate, which a two-point
natural spline reproduces exactly), the propeller at the rate that holds the service speed on a
straight course unless one is ordered. A uniform current carries the ship over the ground (the MMG
equations are written in the water). shipmmg's 3-DOF model has no wind forces: the wind's
(:func:`wind_forces`, constant coefficients on the apparent wind) act as an impulse after each MMG
step (Lie splitting, first order in dt: at 1 s against the ship's yaw time constant of a minute,
a small error). It has no wave forces: a reset in waves raises ``ValueError``.
``benchmarks/fit_kvlcc2.py`` fits the ``kvlcc2`` preset to this ship; the leaderboard's
unseen-physics suite sails it (``ship-env leaderboard --suite unseen``).
"""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np

from ship_env.model.external import ShipMotion
from ship_env.model.simulator import Conditions

KNOT = 1852.0 / 3600.0
MODEL_LENGTH = 7.00  # m, the MMG model of Yasukawa & Yoshimura (2015)
LENGTH = 320.0  # m, KVLCC2 L_pp full scale
SCALE = LENGTH / MODEL_LENGTH  # 45.714, SIMMAN's scale
RHO = 1025.0  # kg/m^3, sea water, used for both the masses and the forces
SERVICE_SPEED = 15.5 * KNOT  # m/s, SIMMAN approach speed (Fn = 0.142)
RUDDER_RATE = math.radians(2.32)  # rad/s, SIMMAN full-scale rudder rate
RUDDER_LIMIT = math.radians(35.0)
PROPELLER_DIAMETER = 0.216 * SCALE  # m, 9.87 m
RHO_AIR = 1.225  # kg/m^3
#: Wind: frontal and lateral windage areas (m^2) and force coefficients, assumed as in the ``kvlcc2``
#: preset's wind effects (loaded, 9.2 m freeboard plus the aft accommodation).
FRONTAL_AREA = 1200.0
LATERAL_AREA = 4000.0
SURGE_COEFFICIENT = 0.8
SWAY_COEFFICIENT = 0.9
#: The wind's yaw moment coefficient; positive: the aft accommodation turns the bow into the wind.
YAW_COEFFICIENT = 0.1
#: What to install where shipmmg is missing.
INSTALL_HINT = 'shipmmg is not installed; install it with: pip install shipmmg (or pip install -e ".[bench]")'


def kvlcc2_mmg(scale: float = SCALE, rho: float = RHO) -> tuple[Any, Any]:
    """shipmmg parameter objects for KVLCC2, Froude-scaled from the 7 m model by ``scale``.

    Model-scale values: Yasukawa & Yoshimura (2015) Tables 1-3, as in shipmmg's tests
    (``tests/test_mmg_3dof.py``, fixture ``ship_KVLCC2_L7_model``), with x_R' = -0.5. Unlike that
    fixture (which builds the masses with rho = 1.025 while ``simulate`` integrates the forces
    with rho = 1025), masses and forces here use the same density.
    """
    from shipmmg.mmg_3dof import Mmg3DofBasicParams, Mmg3DofManeuveringParams

    length = MODEL_LENGTH * scale
    draught = 0.46 * scale
    propeller_diameter = 0.216 * scale
    rudder_height = 0.345 * scale
    mass = rho * 3.27 * scale**3
    reference = 0.5 * rho * length**2 * draught
    basic = Mmg3DofBasicParams(
        L_pp=length,
        B=1.27 * scale,
        d=draught,
        x_G=0.25 * scale,
        D_p=propeller_diameter,
        m=mass,
        I_zG=mass * (0.25 * length) ** 2,
        A_R=0.0539 * scale**2,
        η=propeller_diameter / rudder_height,
        m_x=0.022 * reference,
        m_y=0.223 * reference,
        J_z=0.011 * reference * length**2,
        f_α=2.747,
        ϵ=1.09,
        t_R=0.387,
        x_R=-0.500 * length,
        a_H=0.312,
        x_H=-0.464 * length,
        γ_R_minus=0.395,
        γ_R_plus=0.640,
        l_R=-0.710,
        κ=0.50,
        t_P=0.220,
        w_P0=0.40,
        x_P=-0.690,
    )
    maneuvering = Mmg3DofManeuveringParams(
        k_0=0.2931,
        k_1=-0.2753,
        k_2=-0.1385,
        R_0_dash=0.022,
        X_vv_dash=-0.040,
        X_vr_dash=0.002,
        X_rr_dash=0.011,
        X_vvvv_dash=0.771,
        Y_v_dash=-0.315,
        Y_r_dash=0.083,
        Y_vvv_dash=-1.607,
        Y_vvr_dash=0.379,
        Y_vrr_dash=-0.391,
        Y_rrr_dash=0.008,
        N_v_dash=-0.137,
        N_r_dash=-0.049,
        N_vvv_dash=-0.030,
        N_vvr_dash=-0.294,
        N_vrr_dash=0.055,
        N_rrr_dash=-0.013,
    )
    return basic, maneuvering


def equilibrium_propeller_rate(basic: Any, maneuvering: Any, speed: float, rho: float = RHO) -> float:
    """The propeller rate (rps) at which X_H + X_R + X_P = 0 on a straight course at ``speed``."""
    from scipy.optimize import brentq
    from shipmmg.mmg_3dof import get_sub_values_from_simulation_result

    def surge_force(rate: float) -> float:
        x_h, x_r, x_p, *_ = get_sub_values_from_simulation_result(
            [speed], [0.0], [0.0], [0.0], [rate], basic, maneuvering, ρ=rho
        )
        return float(x_h[0] + x_r[0] + x_p[0])

    return float(brentq(surge_force, 1e-3, 100.0))


@functools.cache
def service_propeller_rate(scale: float = SCALE, speed: float | None = None) -> float:
    """The full-scale propeller rate (rps) that holds KVLCC2 at ``speed`` (default 15.5 kn, SIMMAN's
    condition, Froude-scaled to ``scale``) on a straight course."""
    basic, maneuvering = kvlcc2_mmg(scale)
    return equilibrium_propeller_rate(
        basic, maneuvering, SERVICE_SPEED * math.sqrt(scale / SCALE) if speed is None else speed
    )


def wind_forces(apparent_speed: float, angle: float, length: float = LENGTH) -> tuple[float, float, float]:
    """The wind's surge force X_W, sway force Y_W (N) and yaw moment N_W (N m) on the ship.

    ``apparent_speed``: the wind's speed relative to the ship V_A, m/s; ``angle``: the direction it
    comes from relative to the bow gamma_A, rad, positive from starboard. With q = rho_air V_A^2 / 2:
    X_W = -q A_F C_X cos(gamma_A), Y_W = -q A_L C_Y sin(gamma_A), N_W = q A_L L C_N sin(2 gamma_A).
    """
    pressure = 0.5 * RHO_AIR * apparent_speed**2
    return (
        -pressure * FRONTAL_AREA * SURGE_COEFFICIENT * math.cos(angle),
        -pressure * LATERAL_AREA * SWAY_COEFFICIENT * math.sin(angle),
        pressure * LATERAL_AREA * length * YAW_COEFFICIENT * math.sin(2.0 * angle),
    )


class MmgKvlcc2:
    """shipmmg's MMG KVLCC2, one ``simulate_mmg_3dof`` call per step (:class:`~ship_env.model.external.ShipDynamics`).

    Args:
        scale: the Froude scale from the 7 m model (default 45.714: the 320 m ship).
        rudder_rate: the steering machine's rate, rad/s (default: SIMMAN's 2.32 deg/s at full scale, Froude-scaled
            to ``scale``: 15.7 deg/s on the 7 m model).
        **solver_options: passed to ``solve_ivp`` through shipmmg (``rtol``, ``atol``, ...).

    ``ImportError`` with the install command where shipmmg is missing.
    """

    def __init__(self, scale: float = SCALE, rudder_rate: float | None = None, **solver_options: Any) -> None:
        try:
            from shipmmg.mmg_3dof import simulate_mmg_3dof
        except ImportError as error:
            raise ImportError(INSTALL_HINT) from error
        self._simulate = simulate_mmg_3dof
        self.scale = scale
        self.basic, self.maneuvering = kvlcc2_mmg(scale)
        #: m/s: 15.5 kn at full scale, Froude-scaled.
        self.service_speed = SERVICE_SPEED * math.sqrt(scale / SCALE)
        #: rad/s: a rate scales as 1 / sqrt(lambda).
        self.rudder_rate = RUDDER_RATE * math.sqrt(SCALE / scale) if rudder_rate is None else rudder_rate
        self.solver_options = solver_options
        self.reset(ShipMotion(0.0, 0.0, 0.0, 0.0, self.service_speed), Conditions(service_speed=self.service_speed), 0)

    def reset(self, start: ShipMotion, conditions: Conditions, seed: int) -> None:
        """Start at ``start`` in ``conditions`` (the propeller at the rate that holds their service
        speed); ``ValueError`` in waves, which the model has no forces for."""
        if conditions.wave_height > 0.0:
            raise ValueError(
                f"conditions: shipmmg's MMG 3-DOF model has no wave forces (H_s {conditions.wave_height} m); "
                "sail it in calm water, wind or a current"
            )
        speed = self.service_speed if conditions.service_speed is None else conditions.service_speed
        #: rps: the rate that holds the service speed on a straight course.
        self.propeller_rate = service_propeller_rate(self.scale, speed)
        self._current = (
            conditions.current_speed * math.cos(conditions.current_direction),
            conditions.current_speed * math.sin(conditions.current_direction),
        )
        #: The air's velocity over the ground, north and east, m/s (the wind blows from its direction).
        self._air = (
            -conditions.wind_speed * math.cos(conditions.wind_direction),
            -conditions.wind_speed * math.sin(conditions.wind_direction),
        )
        sway = -start.speed * math.tan(start.drift)
        #: u, v, r, x (north), y (east), psi: shipmmg's state.
        self.state = np.array([start.speed, sway, start.rate_of_turn, start.north, start.east, start.heading])
        self.rudder = start.rudder

    def step(self, rudder_order: float, propeller_rate: float | None, dt: float) -> ShipMotion:
        """Integrate [0, dt]: the rudder towards ``rudder_order`` at most ``rudder_rate * dt``, the
        propeller at ``propeller_rate`` (``None``: the service rate); the current carries the ship."""
        order = min(max(rudder_order, -RUDDER_LIMIT), RUDDER_LIMIT)
        largest = self.rudder_rate * dt
        rudder = self.rudder + min(max(order - self.rudder, -largest), largest)
        rate = self.propeller_rate if propeller_rate is None else propeller_rate
        u, v, r, x, y, psi = self.state
        solution = self._simulate(
            self.basic,
            self.maneuvering,
            [0.0, dt],
            [self.rudder, rudder],
            [rate, rate],
            u0=u,
            v0=v,
            r0=r,
            x0=x + self._current[0] * dt,
            y0=y + self._current[1] * dt,
            ψ0=psi,
            ρ=RHO,
            **self.solver_options,
        )
        self.state = np.array(solution.y[:6, -1])
        if self._air != (0.0, 0.0):
            self.state[:3] += self._wind_impulse(dt)
        self.rudder = rudder
        u, v, r, x, y, psi = self.state.tolist()
        return ShipMotion(psi, r, x, y, u, math.atan2(-v, u), rudder)

    def _wind_impulse(self, dt: float) -> np.ndarray:
        """The change of (u, v, r) the wind's forces (:func:`wind_forces`) give over ``dt``, through the
        MMG equations' mass matrix (added masses m_x, m_y, J_z and the centre of gravity x_G)."""
        u, v, r, _, _, psi = self.state.tolist()
        cos, sin = math.cos(psi), math.sin(psi)
        relative_north = self._air[0] - (u * cos - v * sin + self._current[0])
        relative_east = self._air[1] - (u * sin + v * cos + self._current[1])
        flow_u = relative_north * cos + relative_east * sin  # the air's flow past the ship, body axes
        flow_v = -relative_north * sin + relative_east * cos
        surge, sway, yaw = wind_forces(math.hypot(flow_u, flow_v), math.atan2(-flow_v, -flow_u), self.basic.L_pp)
        b = self.basic
        inertia = b.I_zG + b.J_z + b.x_G**2 * b.m
        sway_rate = (sway * inertia - yaw * b.x_G * b.m) / (inertia * (b.m + b.m_y) - (b.x_G * b.m) ** 2)
        yaw_rate = (yaw - b.x_G * b.m * sway_rate) / inertia
        return np.array([surge / (b.m + b.m_x), sway_rate, yaw_rate]) * dt
