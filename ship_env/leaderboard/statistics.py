"""The leaderboard's statistics, computed with rliable (Agarwal et al. 2021, "Deep RL at the edge of the
statistical precipice").

An entrant's scores on a suite form a matrix of (training seeds x episodes): a row per training
seed of a learned entrant, a single row for a classic autopilot (deterministic: an episode gives
the same score every time). Per suite and entrant:

- **IQM**: rliable's interquartile mean of the suite's ranking metric over all the (seed, episode)
  scores, with a 95 % confidence interval from rliable's stratified bootstrap with task bootstrap:
  the episodes are resampled, and within each episode the training seeds. A classic autopilot's
  interval thus comes from its episodes; a learned entrant with one seed gets an interval over
  its episodes only (the tables say so).
- **Normalised score**: each episode's ranking metric divided by the reference autopilot's on
  the same episode (:data:`REFERENCES`: the fixed-gain PD on CourseChange, the predictor course
  changer on TrackFollow), so the reference scores 1 and lower is better; its IQM with the same
  interval.
- **Probability of improvement** over the best classic autopilot (the lowest IQM): rliable's
  definition, P(entrant's score better than the autopilot's) per episode (Mann-Whitney, ties
  counting half) averaged over the episodes. Against a deterministic autopilot that is the share
  of the entrant's (seed, episode) scores below the autopilot's on the same episode, computed so
  and bootstrapped like the IQM.
- A single score (one seed, one episode) gets **no interval**, never a made-up one.

The bootstrap draws from numpy's global generator (rliable's own sampling), seeded with
:data:`BOOTSTRAP_SEED` for each estimate and restored afterwards: the same scores give the same
intervals to the last digit, whatever was computed before.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

#: The reference autopilot of each environment's normalised score (it scores 1).
REFERENCES = {"ship_env/CourseChange-v0": "PD, fixed gains", "ship_env/TrackFollow-v0": "predictor course changer"}
#: The probability of improvement at parity.
PARITY = 0.5
#: The bootstrap's resamples, confidence level and seed.
BOOTSTRAP_REPS = 2000
CONFIDENCE = 0.95
BOOTSTRAP_SEED = 0


@dataclass(frozen=True)
class Estimate:
    """A point estimate with its 95 % confidence interval (``low``, ``high``), or ``None`` for
    both where a single score gives no interval."""

    value: float
    low: float | None = None
    high: float | None = None

    @property
    def has_interval(self) -> bool:
        return self.low is not None and self.high is not None

    @property
    def bounds(self) -> tuple[float, float]:
        """(low, high), or the value twice without an interval."""
        if self.low is None or self.high is None:
            return self.value, self.value
        return self.low, self.high

    def above(self, threshold: float) -> bool:
        """Whether the whole interval lies above ``threshold`` (``False`` without an interval)."""
        return self.low is not None and self.low > threshold

    def below(self, threshold: float) -> bool:
        """Whether the whole interval lies below ``threshold`` (``False`` without an interval)."""
        return self.high is not None and self.high < threshold

    def text(self, digits: int) -> str:
        """``"12.3 [11.0, 13.5]"``, or ``"12.3 (no interval)"``."""
        if math.isnan(self.value):
            return ""
        if not self.has_interval:
            return f"{self.value:.{digits}f} (no interval)"
        return f"{self.value:.{digits}f} [{self.low:.{digits}f}, {self.high:.{digits}f}]"


@contextmanager
def _seeded_global_generator(seed: int) -> Iterator[None]:
    """numpy's global generator seeded for rliable's bootstrap, restored afterwards."""
    state = np.random.get_state()
    np.random.seed(seed)
    try:
        yield
    finally:
        np.random.set_state(state)


#: The aggregates :func:`interval_estimates` computes: rliable's interquartile mean, or the plain mean.
AGGREGATES = ("iqm", "mean")


def interval_estimates(layers: np.ndarray, aggregates: Sequence[str]) -> list[Estimate]:
    """Per layer of a (seeds x episodes x layers) array, its aggregate (``"iqm"`` or ``"mean"``,
    one per layer) with a 95 % stratified-bootstrap interval (rliable: the episodes resampled and,
    within each, the seeds); no interval with a single score.

    The IQM is rliable's (``metrics.aggregate_iqm``: scipy's 25 %-trimmed mean of all the scores,
    a quarter of them cut at each end), taken of every layer at once with numpy so that one
    bootstrap serves a whole table.
    """
    from rliable import library

    unknown = sorted(set(aggregates) - set(AGGREGATES))
    if unknown or len(aggregates) != layers.shape[2]:
        raise ValueError(f"aggregates: expected one of {', '.join(AGGREGATES)} per layer, got {list(aggregates)}")
    iqm = np.array([aggregate == "iqm" for aggregate in aggregates])

    def func(scores: np.ndarray) -> np.ndarray:
        ordered = np.sort(scores.reshape(-1, scores.shape[2]), axis=0)
        cut = int(0.25 * len(ordered))  # as scipy.stats.trim_mean(proportiontocut=0.25)
        return np.where(iqm, ordered[cut : len(ordered) - cut].mean(axis=0), ordered.mean(axis=0))

    point = func(layers)
    if layers.shape[0] * layers.shape[1] < 2:
        return [Estimate(float(value)) for value in point]
    with _seeded_global_generator(BOOTSTRAP_SEED):
        _, intervals = library.get_interval_estimates(
            {"scores": layers}, func, task_bootstrap=True, reps=BOOTSTRAP_REPS, confidence_interval_size=CONFIDENCE
        )
    low, high = intervals["scores"]
    return [Estimate(float(v), float(lo), float(hi)) for v, lo, hi in zip(point, low, high, strict=True)]


def improvements(scores: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Per (seed, episode): 1 where ``scores`` is below (better than) the deterministic
    ``reference``'s score on the episode, 0.5 on a tie, 0 above; their mean is rliable's
    probability of improvement of ``scores`` over ``reference`` (lower is better)."""
    return np.where(scores < reference, 1.0, np.where(scores == reference, 0.5, 0.0))
