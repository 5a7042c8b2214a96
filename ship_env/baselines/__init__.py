"""Classic baselines for the ship_env environments: the thesis's PRESYS rebuilt (Passenier 1989, ch. 3-6).

- :mod:`ship_env.baselines.controller`: the one interface every controller has (``reset``, ``act``), an
  adapter for the physical-unit autopilots and one for stable-baselines3 policies;
- :mod:`ship_env.baselines.pd_autopilot`: PD course changing with gain scheduling (3.45, 3.52, 5.79, 5.80);
- :mod:`ship_env.baselines.yaw_filter`, :mod:`ship_env.baselines.position_filter`: the EKF of the yaw motions and the
  Kalman filter of speed, drift, current and position (5.3, 5.4);
- :mod:`ship_env.baselines.adaptive_autopilot`, :mod:`ship_env.baselines.mrac`: indirect adaptive and model-reference
  autopilots (5.5.2, 5.5.3);
- :mod:`ship_env.baselines.track_predictor`, :mod:`ship_env.baselines.track_scaling`: the adaptive track predictor
  (ch. 3, 5.6); :mod:`ship_env.baselines.track_plot` draws it;
- :mod:`ship_env.baselines.course_changer`: the predictor-based course changer for TrackFollow-v0;
- :mod:`ship_env.baselines.online_estimators`: on-line identification of the steering dynamics (the
  preliminary zig-zag trial; Perera's, Nguyen's, Song's and Passenier's estimators and their
  comparison); :mod:`ship_env.baselines.instruments`: instruments on a bare simulator;
- :mod:`ship_env.baselines.presys`: the configurations ready for an environment;
- :mod:`ship_env.baselines.filter_health`: the filters' guard against bad input and divergence.
"""

if __name__ == "baselines":  # imported through the repository's top-level link, under the old name
    raise ImportError(
        "ship-env's classic baselines are imported as `ship_env.baselines` (e.g. "
        "`from ship_env.baselines import presys`); the top-level name `baselines` belongs to other "
        "packages (OpenAI's baselines) and is not installed by ship-env."
    )

from ship_env.baselines.controller import Autopilot, AutopilotController, Controller, SB3Controller
from ship_env.baselines.filter_health import FilterDivergenceError
from ship_env.baselines.measurement import Measurement
from ship_env.baselines.nomoto import NomotoParameters

__all__ = [
    "Autopilot",
    "AutopilotController",
    "Controller",
    "FilterDivergenceError",
    "Measurement",
    "NomotoParameters",
    "SB3Controller",
]
