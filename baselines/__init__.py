"""Classic baselines for the ship_env environments: the thesis's PRESYS rebuilt (Passenier 1989, ch. 3-6).

- :mod:`baselines.controller`: the one interface every controller has (``reset``, ``act``), an
  adapter for the physical-unit autopilots and one for stable-baselines3 policies;
- :mod:`baselines.pd_autopilot`: PD course changing with gain scheduling (3.45, 3.52, 5.79, 5.80);
- :mod:`baselines.yaw_filter`, :mod:`baselines.position_filter`: the EKF of the yaw motions and the
  Kalman filter of speed, drift, current and position (5.3, 5.4);
- :mod:`baselines.adaptive_autopilot`, :mod:`baselines.mrac`: indirect adaptive and model-reference
  autopilots (5.5.2, 5.5.3);
- :mod:`baselines.track_predictor`, :mod:`baselines.track_scaling`: the adaptive track predictor
  (ch. 3, 5.6); :mod:`baselines.track_plot` draws it;
- :mod:`baselines.course_changer`: the predictor-based course changer for TrackFollow-v0;
- :mod:`baselines.identification`: on-line identification of the steering dynamics (the
  preliminary zig-zag trial; Perera's, Nguyen's, Song's and Passenier's estimators and their
  comparison); :mod:`baselines.instruments`: instruments on a bare simulator;
- :mod:`baselines.presys`: the configurations ready for an environment;
- :mod:`baselines.filter_health`: the filters' guard against bad input and divergence.
"""

from baselines.controller import Autopilot, AutopilotController, Controller, SB3Controller
from baselines.filter_health import FilterDivergenceError
from baselines.measurement import Measurement
from baselines.nomoto import NomotoParameters

__all__ = [
    "Autopilot",
    "AutopilotController",
    "Controller",
    "FilterDivergenceError",
    "Measurement",
    "NomotoParameters",
    "SB3Controller",
]
