"""The MMG standard's 3-DOF manoeuvring model in the form the workbench identifies by inverse dynamics.

Surge u, sway v (at midships) and yaw r, with the rigid body's mass matrix (Yasukawa & Yoshimura 2015,
"Introduction of MMG standard method for ship maneuvering predictions", J Mar Sci Technol 20:37-52, eq. 4):

    (m + m_x) du/dt - (m + m_y) v r - x_G m r^2                         = X
    (m + m_y) dv/dt + (m + m_x) u r + x_G m dr/dt                       = Y
    (I_zG + x_G^2 m + J_z) dr/dt + x_G m (dv/dt + u r)                  = N

and the forces, non-dimensional (X' = X / (1/2 rho L d U^2), N' = N / (1/2 rho L^2 d U^2), v' = v / U,
r' = r L / U, U^2 = u^2 + v^2):

- the hull (their eqs. 11-13), to the third order in v' and r':
  X_H' = X_vv v'^2 + X_vr v' r' + X_rr r'^2 + X_vvvv v'^4,
  Y_H' = Y_v v' + Y_r r' + Y_vvv v'^3 + Y_vvr v'^2 r' + Y_vrr v' r'^2 + Y_rrr r'^3, N_H' likewise;
- the propeller's inflow u_P = u (1 - w_P) / (1 - w_P0): the wake fraction w_P falls as the flow meets the
  propeller at a drift angle beta_P = beta - x_P' r' (their eq. 16, one C_2 for both signs):
  u_P = u (1 + c_w (1 - exp(-C_1 |beta_P|))), with C_1 = :data:`WAKE_DECAY` and x_P' = :data:`PROPELLER_POSITION`,
  c_w (``wake_drift``, their C_2 - 1) fitted. In KVLCC2's hard-over turn beta_P reaches 0.8 rad (a drift of 0.33
  rad at r' 0.9) and u_P 1.6 u, at which the propeller pushes less and its slipstream feeds the rudder more; fitted
  on the basin truth's zig-zags, the form without it predicted the steady rate of turn 9 % high
  (docs/results/free_running.md);
- the propeller's thrust at rate n (their eqs. 14-16, K_T quadratic in the advance ratio J), with the
  resistance R_0 u^2: X_P + X_R0 = (a_nn (n T)^2 + a_un u_P (n T) + a_uu u^2) / (1/2 rho L d), written with the
  draught T as the length n is multiplied by (the propeller's diameter, which a preset does not state, is
  absorbed in the coefficients; K_T's J^2 term, small beside the resistance, with it in a_uu u^2);
- the rudder's normal force F_N (their eqs. 17-27), lumped: F_N ~ U_R^2 sin(alpha_R) with the rudder's inflow
  u_R^2 = u_P^2 + b_un u_P (n T) + c_nn (n T)^2 (the propeller's slipstream), v_R = gamma_R U beta_R with
  beta_R = beta - l_R r' and beta = atan2(-v, u) (the hull's flow straightening; gamma_R one value for
  beta_R > 0, another for beta_R < 0, as their eq. 26), alpha_R = delta - atan2(v_R, u_R) and U_R^2 = u_R^2 +
  v_R^2. It enters X as -X_delta U_R^2 sin(alpha_R) sin(delta), Y and N as -Y_delta (N_delta) U_R^2
  sin(alpha_R) cos(delta) (their eq. 17: (1 - t_R), (1 + a_H), (x_R + a_H x_H) times F_N).

Every force is linear in its coefficients for given inflow parameters (b_un, c_nn, gamma_R+, gamma_R-, l_R,
c_w): :func:`force_regressors` gives the columns, which the identification
(:mod:`ship_env.workbench.fitting.inverse_dynamics`) fits by variable projection. The masses are not identified: they
come from the particulars (:class:`RigidBody`), the added masses from Clarke, Gedling & Hine (1983)'s
regressions on the hull's length, breadth, draught and block coefficient.

:class:`MmgForm` holds one fitted model; :func:`derivatives` and :func:`rk4_step` sail it
(:class:`~ship_env.model.mmg_fitted.MmgFitted` puts it behind the external-dynamics protocol).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ship_env.model.kernel import inlined_kernel, kernel

#: kg/m^3, the water's density; it cancels (forces and masses are both written with it).
RHO = 1025.0
#: Names of the surge force's coefficients (the columns of :func:`force_regressors`' first matrix).
SURGE_TERMS = ("a_nn", "a_un", "a_uu", "X_vv", "X_vr", "X_rr", "X_vvvv", "X_delta")
#: Names of the sway force's and the yaw moment's coefficients (the columns of the second matrix).
SWAY_TERMS = ("Y_v", "Y_r", "Y_vvv", "Y_vvr", "Y_vrr", "Y_rrr", "Y_delta")
YAW_TERMS = ("N_v", "N_r", "N_vvv", "N_vvr", "N_vrr", "N_rrr", "N_delta")
#: The propeller's and the rudder's inflow parameters (nonlinear in the forces): b_un, c_nn, gamma_R (beta_R > 0),
#: gamma_R (< 0), l_R, c_w.
INFLOW_TERMS = ("b_un", "c_nn", "gamma_plus", "gamma_minus", "l_R", "wake_drift")
#: x_P', the propeller's position over L from midships: at the stern (the MMG standard's KVLCC2: -0.48).
PROPELLER_POSITION = -0.5
#: C_1, how fast the wake fraction falls with the drift at the propeller (the MMG standard's KVLCC2: 2.0).
WAKE_DECAY = 2.0
#: Samples of a quantity, or one value.
Values = np.ndarray | float
#: A speed below which v' and r' are not formed (the ship at rest), m/s per m of length (U / L).
RESTING = 1e-6


@dataclass(frozen=True)
class RigidBody:
    """The mass matrix's numbers, kg and kg m^2, from the particulars.

    Attributes:
        length, breadth, draught: L, B, d, m.
        block_coefficient: C_B; the displaced volume is C_B L B d.
        centre_of_gravity: x_G, m forward of midships.
        gyration: the yaw radius of gyration over L (I_zG = m (k L)^2).
    """

    length: float
    breadth: float
    draught: float
    block_coefficient: float
    centre_of_gravity: float = 0.0
    gyration: float = 0.25

    def __post_init__(self) -> None:
        for name in ("length", "breadth", "draught"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name}: expected a positive length in m, got {value!r}")
        if not 0.3 <= self.block_coefficient <= 1.0:
            raise ValueError(f"block_coefficient: expected C_B from 0.3 to 1, got {self.block_coefficient!r}")
        if not 0.1 <= self.gyration <= 0.5:
            raise ValueError(f"gyration: expected k / L from 0.1 to 0.5, got {self.gyration!r}")

    @property
    def mass(self) -> float:
        return RHO * self.block_coefficient * self.length * self.breadth * self.draught

    @property
    def added_masses(self) -> tuple[float, float, float]:
        """m_x, m_y, J_z: m_y and J_z from Clarke, Gedling & Hine (1983), eqs. for Y_v-dot and N_r-dot; m_x 5 %
        of m (the usual estimate where no test gives it)."""
        length, breadth, draught, block = self.length, self.breadth, self.draught, self.block_coefficient
        slender = math.pi * (draught / length) ** 2
        sway = slender * (1.0 + 0.16 * block * breadth / draught - 5.1 * (breadth / length) ** 2)
        yaw = slender * (1.0 / 12.0 + 0.017 * block * breadth / draught - 0.33 * breadth / length)
        return 0.05 * self.mass, sway * 0.5 * RHO * length**3, yaw * 0.5 * RHO * length**5

    def matrix(self) -> np.ndarray:
        """The mass matrix of (du/dt, dv/dt, dr/dt) in the equations above."""
        mass, (m_x, m_y, j_z), x_g = self.mass, self.added_masses, self.centre_of_gravity
        inertia = mass * (self.gyration * self.length) ** 2
        return np.array(
            [[mass + m_x, 0.0, 0.0], [0.0, mass + m_y, x_g * mass], [0.0, x_g * mass, inertia + x_g**2 * mass + j_z]]
        )

    def inertial_forces(
        self, u: np.ndarray, v: np.ndarray, r: np.ndarray, du: np.ndarray, dv: np.ndarray, dr: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """X, Y, N that move the ship as (u, v, r, du/dt, dv/dt, dr/dt): the equations' left-hand sides."""
        mass, (m_x, m_y, j_z), x_g = self.mass, self.added_masses, self.centre_of_gravity
        inertia = mass * (self.gyration * self.length) ** 2
        surge = (mass + m_x) * du - (mass + m_y) * v * r - x_g * mass * r**2
        sway = (mass + m_y) * dv + (mass + m_x) * u * r + x_g * mass * dr
        yaw = (inertia + x_g**2 * mass + j_z) * dr + x_g * mass * (dv + u * r)
        return surge, sway, yaw


@dataclass(frozen=True)
class MmgForm:
    """One model of the form: its rigid body and its force coefficients.

    Attributes:
        body: the rigid body.
        inflow: the rudder's inflow parameters, :data:`INFLOW_TERMS` order.
        surge, sway, yaw: the coefficients, :data:`SURGE_TERMS`, :data:`SWAY_TERMS`, :data:`YAW_TERMS` order.
    """

    body: RigidBody
    inflow: np.ndarray
    surge: np.ndarray
    sway: np.ndarray
    yaw: np.ndarray

    @cached_property
    def compiled(self) -> tuple[np.ndarray, ...]:
        """What the compiled equations take: the inflow, surge, sway and yaw coefficients; L, d, m, m_x, m_y, x_G;
        the mass matrix's inverse."""
        body = self.body
        particulars = np.array([body.length, body.draught, body.mass, *body.added_masses[:2], body.centre_of_gravity])
        arrays = (self.inflow, self.surge, self.sway, self.yaw, particulars, np.linalg.inv(body.matrix()))
        return tuple(np.ascontiguousarray(array, dtype=float) for array in arrays)

    def forces(
        self, u: Values, v: Values, r: Values, rudder: Values, propeller_rate: Values
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """X, Y (N) and N (N m) on the ship."""
        surge_columns, sway_columns, yaw_columns = force_regressors(
            u, v, r, rudder, propeller_rate, self.inflow, self.body
        )
        scale = 0.5 * RHO * self.body.length * self.body.draught
        return (
            scale * surge_columns @ self.surge,
            scale * sway_columns @ self.sway,
            scale * self.body.length * yaw_columns @ self.yaw,
        )


@inlined_kernel
def _sample_columns(u, v, r, rudder, propeller_rate, inflow, length, draught, surge, lateral):
    """One sample's columns, written into ``surge`` (8) and ``lateral`` (7): the module docstring's forms times U^2."""
    speed_squared = u * u + v * v
    speed = math.sqrt(speed_squared)
    moving = max(speed, RESTING * length)
    sway, turn = v / moving, r * length / moving  # v' and r'
    n_t = propeller_rate * draught
    drift = math.atan2(-v, u)  # beta
    propeller_drift = drift - PROPELLER_POSITION * turn  # beta_P
    propeller_inflow = u * (1.0 + inflow[5] * (1.0 - math.exp(-WAKE_DECAY * abs(propeller_drift))))  # u_P
    inflow_squared = max(
        propeller_inflow * propeller_inflow + inflow[0] * propeller_inflow * n_t + inflow[1] * n_t * n_t, 0.0
    )  # u_R^2
    beta_r = drift - inflow[4] * turn
    lateral_inflow = (inflow[2] if beta_r >= 0.0 else inflow[3]) * speed * beta_r  # v_R, gamma_R of beta_R's sign
    attack = rudder - math.atan2(lateral_inflow, math.sqrt(inflow_squared))  # alpha_R
    normal = (inflow_squared + lateral_inflow * lateral_inflow) * math.sin(attack)  # U_R^2 sin(alpha_R)
    surge[0] = n_t * n_t
    surge[1] = propeller_inflow * n_t
    surge[2] = u * u
    surge[3] = speed_squared * sway * sway
    surge[4] = speed_squared * sway * turn
    surge[5] = speed_squared * turn * turn
    surge[6] = speed_squared * sway**4
    surge[7] = -normal * math.sin(rudder)
    lateral[0] = speed_squared * sway
    lateral[1] = speed_squared * turn
    lateral[2] = speed_squared * sway**3
    lateral[3] = speed_squared * sway * sway * turn
    lateral[4] = speed_squared * sway * turn * turn
    lateral[5] = speed_squared * turn**3
    lateral[6] = -normal * math.cos(rudder)


@kernel
def _columns(u, v, r, rudder, propeller_rate, inflow, length, draught):
    count = u.shape[0]
    surge = np.empty((count, len(SURGE_TERMS)))
    lateral = np.empty((count, len(SWAY_TERMS)))
    for k in range(count):
        _sample_columns(u[k], v[k], r[k], rudder[k], propeller_rate[k], inflow, length, draught, surge[k], lateral[k])
    return surge, lateral


def force_regressors(
    u: Values, v: Values, r: Values, rudder: Values, propeller_rate: Values, inflow: np.ndarray, body: RigidBody
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The columns X / (1/2 rho L d), Y / (1/2 rho L d) and N / (1/2 rho L^2 d) are linear in: (samples, 8) for the
    surge coefficients, (samples, 7) for the sway's and the yaw's (the module docstring's forms times U^2)."""
    arrays = np.broadcast_arrays(
        *(np.atleast_1d(np.asarray(x, dtype=float)) for x in (u, v, r, rudder, propeller_rate))
    )
    contiguous = [np.ascontiguousarray(array) for array in arrays]
    surge, lateral = _columns(*contiguous, np.asarray(inflow, dtype=float), body.length, body.draught)
    return surge, lateral, lateral


@kernel
def _derivatives(state, rudder, propeller_rate, inflow, surge_terms, sway_terms, yaw_terms, body, inverse, out):
    """d/dt of (u, v, r, north, east, heading) into ``out``; ``body`` holds L, d, m, m_x, m_y, x_G and ``inverse`` the
    mass matrix's inverse."""
    u, v, r, heading = state[0], state[1], state[2], state[5]
    length, draught, mass, m_x, m_y, x_g = body[0], body[1], body[2], body[3], body[4], body[5]
    surge = np.empty(len(SURGE_TERMS))
    lateral = np.empty(len(SWAY_TERMS))
    _sample_columns(u, v, r, rudder, propeller_rate, inflow, length, draught, surge, lateral)
    scale = 0.5 * RHO * length * draught
    x_force = scale * np.dot(surge, surge_terms) + (mass + m_y) * v * r + x_g * mass * r * r
    y_force = scale * np.dot(lateral, sway_terms) - (mass + m_x) * u * r
    n_moment = scale * length * np.dot(lateral, yaw_terms) - x_g * mass * u * r
    for k in range(3):
        out[k] = inverse[k, 0] * x_force + inverse[k, 1] * y_force + inverse[k, 2] * n_moment
    out[3] = u * math.cos(heading) - v * math.sin(heading)
    out[4] = u * math.sin(heading) + v * math.cos(heading)
    out[5] = r


@kernel
def _rk4(
    state, rudder_start, rudder_end, propeller_rate, dt, inflow, surge_terms, sway_terms, yaw_terms, body, inverse
):
    middle = 0.5 * (rudder_start + rudder_end)
    k1, k2, k3, k4 = np.empty(6), np.empty(6), np.empty(6), np.empty(6)
    arguments = (inflow, surge_terms, sway_terms, yaw_terms, body, inverse)
    _derivatives(state, rudder_start, propeller_rate, *arguments, k1)
    _derivatives(state + 0.5 * dt * k1, middle, propeller_rate, *arguments, k2)
    _derivatives(state + 0.5 * dt * k2, middle, propeller_rate, *arguments, k3)
    _derivatives(state + dt * k3, rudder_end, propeller_rate, *arguments, k4)
    return state + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


def derivatives(state: np.ndarray, rudder: float, propeller_rate: float, form: MmgForm) -> np.ndarray:
    """d/dt of (u, v, r, north, east, heading): the equations of motion solved for the accelerations."""
    out = np.empty(6)
    _derivatives(np.asarray(state, dtype=float), float(rudder), float(propeller_rate), *form.compiled, out)
    return out


def rk4_step(
    state: np.ndarray, rudder_start: float, rudder_end: float, propeller_rate: float, form: MmgForm, dt: float
) -> np.ndarray:
    """One classical Runge-Kutta step of ``dt`` s, the rudder moving linearly from ``rudder_start`` to
    ``rudder_end`` over it."""
    return _rk4(
        np.asarray(state, dtype=float), float(rudder_start), float(rudder_end), float(propeller_rate), float(dt),
        *form.compiled,
    )  # fmt: skip


__all__ = [
    "INFLOW_TERMS",
    "SURGE_TERMS",
    "SWAY_TERMS",
    "YAW_TERMS",
    "MmgForm",
    "RigidBody",
    "derivatives",
    "force_regressors",
    "rk4_step",
]
