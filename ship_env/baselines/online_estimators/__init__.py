"""On-line identification of a ship's steering dynamics: the papers' estimators, their excitation and their comparison.

These run sample by sample, as on board. Off-line identification from measured logs (fit a model
of named physical effects, diagnose what is missing) is the workbench, :mod:`ship_env.workbench`.

Every estimator reads an :class:`ExcitationLog` (time, rudder, heading, rate of turn, speed as
numpy arrays in SI units and radians), runs over it sample by sample as it would on board, and
reports its parameters after each sample as a :class:`ParameterHistory`; a diverging estimator
raises :class:`~ship_env.baselines.filter_health.FilterDivergenceError` instead of returning NaN.

Estimators:

- :class:`PereraFilter` (``perera_ekf``): Perera et al. 2015, EKF on (psi, psi', psi'', a1, a2,
  a3, b1, b2, delta, delta') for psi''' = a1 psi'^3 + a2 psi' + a3 psi'' + b1 delta + b2 delta';
- :class:`NguyenRLS` (``least_squares``): Nguyen 2008, recursive least squares with a forgetting
  factor on x(k) = A x(k-1) + B delta(k), and K, T from it;
- :class:`SongFilter` (``song_ekf``): Song et al. 2022, EKF with forgetting factor, tanh-processed
  innovation and divergence guard, on the thesis's yaw model;
- :class:`CombinedMRAS` (``mras``): Passenier's combined Series-Parallel / Parallel MRAS
  identifier (thesis 4.83-4.94);
- :class:`PassenierEKF` (``passenier_ekf``): the thesis's yaw filter, parameters as random walks
  (:mod:`ship_env.baselines.yaw_filter`).

Around them: ``excitation`` (zig-zag, turning, PRBS, white-noise and intermittent rudder; logs
sailed on the simulator, with speed and loading changes), ``perera_model`` (Perera's model
simulated directly), ``adaptation`` (forgetting factor and random walk), ``discrete_nomoto``
(K*, tau* from the sampled model), ``criteria`` (final error, time to within 10 %, J_p of thesis
6.1), ``adaptation_comparison`` (stelling 5 at matched noise), ``scenarios`` and ``bench`` (the
comparison run by ``ship-env identify-bench``, :mod:`~ship_env.baselines.online_estimators.cli`) and
``zigzag_trial`` (the preliminary identification trial of the thesis's simulator experiment).
"""

from ship_env.baselines.online_estimators.adaptation import ForgettingFactor, RandomWalk
from ship_env.baselines.online_estimators.criteria import final_errors, parameter_criterion, settling_times
from ship_env.baselines.online_estimators.estimator import Estimator
from ship_env.baselines.online_estimators.excitation import (
    Intermittent,
    ModelChange,
    PseudoRandomBinary,
    SpeedChange,
    Trial,
    Turning,
    WhiteNoise,
    ZigZag,
    sail,
)
from ship_env.baselines.online_estimators.history import NOMOTO, PERERA, ParameterHistory
from ship_env.baselines.online_estimators.least_squares import NguyenRLS, RecursiveLeastSquares
from ship_env.baselines.online_estimators.log import ExcitationLog, ExcitationLogError, from_workbench_log
from ship_env.baselines.online_estimators.mras import CombinedMRAS
from ship_env.baselines.online_estimators.passenier_ekf import PassenierEKF
from ship_env.baselines.online_estimators.perera_ekf import PereraFilter, PereraFilterNoise
from ship_env.baselines.online_estimators.perera_model import PUBLISHED, PereraParameters, PereraSetting
from ship_env.baselines.online_estimators.song_ekf import SongFilter, SongFilterNoise

__all__ = [
    "NOMOTO",
    "PERERA",
    "PUBLISHED",
    "CombinedMRAS",
    "Estimator",
    "ExcitationLog",
    "ExcitationLogError",
    "ForgettingFactor",
    "Intermittent",
    "ModelChange",
    "NguyenRLS",
    "ParameterHistory",
    "PassenierEKF",
    "PereraFilter",
    "PereraFilterNoise",
    "PereraParameters",
    "PereraSetting",
    "PseudoRandomBinary",
    "RandomWalk",
    "RecursiveLeastSquares",
    "SongFilter",
    "SongFilterNoise",
    "SpeedChange",
    "Trial",
    "Turning",
    "WhiteNoise",
    "ZigZag",
    "final_errors",
    "from_workbench_log",
    "parameter_criterion",
    "sail",
    "settling_times",
]
