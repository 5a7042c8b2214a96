"""The leaderboard: classic autopilots and learned policies on fixed, seeded suites.

- :mod:`ship_env.leaderboard.suites`: the suites (CourseChange per disturbance, TrackFollow) and
  the robustness conditions (K*, tau* off by 2x, half speed), dev (alias quick), full and test;
- :mod:`ship_env.leaderboard.entrants`: the controllers (:mod:`ship_env.baselines.presys`, SB3 policy
  files, one per training seed);
- :mod:`ship_env.leaderboard.sailing`: the seeded episode loop;
- :mod:`ship_env.leaderboard.evaluation`: jobs run in this process or on Ray;
- :mod:`ship_env.leaderboard.statistics`: IQM, normalised score and probability of improvement
  with stratified-bootstrap intervals (rliable);
- :mod:`ship_env.leaderboard.tables`: each suite's ranking and the learned entrants' verdicts;
- :mod:`ship_env.leaderboard.rendering`, :mod:`ship_env.leaderboard.plots`: the rankings as markdown and
  CSV tables, and drawings;
- :mod:`ship_env.leaderboard.board`: all of it together; :mod:`ship_env.leaderboard.cli`:
  ``ship-env leaderboard``.

Only the suites are imported here; the rest brings torch and the baselines and is imported from
its module.
"""

from ship_env.leaderboard.suites import SUITE_SPECS, Suite, SuiteSpec

__all__ = ["SUITE_SPECS", "Suite", "SuiteSpec"]
