"""On-line identification of a ship's steering dynamics: the papers' estimators, their excitation and their comparison.

Every estimator reads an :class:`ExcitationLog` (time, rudder, heading, rate of turn, speed as
numpy arrays in SI units and radians), runs over it sample by sample as it would on board, and
reports its parameters after each sample as a :class:`ParameterHistory`; a diverging estimator
raises :class:`~baselines.filter_health.FilterDivergenceError` instead of returning NaN.

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
  (:mod:`baselines.yaw_filter`).

Around them: ``excitation`` (zig-zag, turning, PRBS, white-noise and intermittent rudder; logs
sailed on the simulator, with speed and loading changes), ``perera_model`` (Perera's model
simulated directly), ``adaptation`` (forgetting factor and random walk), ``discrete_nomoto``
(K*, tau* from the sampled model), ``criteria`` (final error, time to within 10 %, J_p of thesis
6.1), ``adaptation_comparison`` (stelling 5 at matched noise), ``scenarios`` and ``bench`` (the
comparison run by ``ship-env identify-bench``, :mod:`~baselines.identification.cli`) and
``zigzag_trial`` (the preliminary identification trial of the thesis's simulator experiment).
"""

from baselines.identification.adaptation import ForgettingFactor, RandomWalk
from baselines.identification.criteria import final_errors, parameter_criterion, settling_times
from baselines.identification.estimator import Estimator
from baselines.identification.excitation import (
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
from baselines.identification.history import NOMOTO, PERERA, ParameterHistory
from baselines.identification.least_squares import NguyenRLS, RecursiveLeastSquares
from baselines.identification.log import ExcitationLog, ExcitationLogError, from_workbench_log
from baselines.identification.mras import CombinedMRAS
from baselines.identification.passenier_ekf import PassenierEKF
from baselines.identification.perera_ekf import PereraFilter, PereraFilterNoise
from baselines.identification.perera_model import PUBLISHED, PereraParameters, PereraSetting
from baselines.identification.song_ekf import SongFilter, SongFilterNoise

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
