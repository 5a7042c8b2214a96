"""Drawing a ship's episode with matplotlib: the track, the ship at scale, the rudder, the disturbances
and the task's guides (a new heading, a reference track). North is up, east to the right, distances
in metres.

``"rgb_array"`` draws off-screen (Agg canvas) and returns the frame; ``"human"`` draws into a pyplot
window and pauses for one frame at the environment's frame rate.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ship_env.model import Conditions
from ship_env.model import state as S

FRAME_INCHES = 6.0
FRAME_DPI = 100  # 600 x 600 pixel frames

# The hull in the ship's frame, in lengths (forward) and breadths (starboard): a transom stern,
# parallel sides, a pointed bow.
_HULL = np.array([[-0.5, -0.5], [0.3, -0.5], [0.5, 0.0], [0.3, 0.5], [-0.5, 0.5], [-0.5, -0.5]])
_RUDDER_CHORD = 0.08  # drawn rudder length, in ship lengths (exaggerated to be seen)
_ARROW_ORIGINS = {"wind": (0.12, 0.88), "current": (0.12, 0.70), "waves": (0.12, 0.52)}


def _earth(
    north: float, east: float, heading: float, forward: np.ndarray, starboard: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Ship-frame points (``forward``, ``starboard``, m) to (east, north) plot coordinates."""
    cos, sin = math.cos(heading), math.sin(heading)
    return east + forward * sin + starboard * cos, north + forward * cos - starboard * sin


class Guide(NamedTuple):
    """A dashed line drawn beside the ship: a polyline through (``north``, ``east``) points, m, or, with
    ``heading`` set (rad), a ray from the ship on that heading."""

    label: str
    north: np.ndarray = np.zeros(0)
    east: np.ndarray = np.zeros(0)
    heading: float | None = None


class ShipRenderer:
    """Draws frames of one ship's episode.

    Args:
        render_mode: ``"human"`` or ``"rgb_array"``.
        render_fps: frames per second of the ``"human"`` window.
        length, breadth: the ship's length and breadth, m (drawn at scale).
        rudder_limit: delta_max, rad.
    """

    def __init__(self, render_mode: str, render_fps: float, length: float, breadth: float, rudder_limit: float) -> None:
        self.render_fps = render_fps
        self.length = length
        self.breadth = breadth
        self.rudder_limit = rudder_limit
        self._pyplot = None
        if render_mode == "human":
            import matplotlib.pyplot

            self._pyplot = matplotlib.pyplot
            self.figure = self._pyplot.figure(figsize=(FRAME_INCHES, FRAME_INCHES), dpi=FRAME_DPI)
        else:
            # matplotlib is imported here, not with the module: an environment that is never drawn
            # starts without it (0.8 s).
            from matplotlib.backends.backend_agg import FigureCanvasAgg
            from matplotlib.figure import Figure

            self.figure = Figure(figsize=(FRAME_INCHES, FRAME_INCHES), dpi=FRAME_DPI)
            FigureCanvasAgg(self.figure)
        self.axes = self.figure.add_axes((0.1, 0.08, 0.86, 0.78))

    def draw(
        self,
        track: np.ndarray,
        state: np.ndarray,
        conditions: Conditions,
        ordered_rudder: float,
        guides: list[Guide],
        caption: str,
    ) -> np.ndarray | None:
        """Draw one frame: ``track`` (k, 2) north/east positions, the true ``state``, the episode's
        ``conditions``, the task's ``guides`` and ``caption`` (the title's task part).

        Returns the frame (H, W, 3) uint8 for ``"rgb_array"``, None for ``"human"``.
        """
        axes = self.axes
        axes.clear()
        north, east, heading = state[S.NORTH], state[S.EAST], state[S.HEADING]
        axes.plot(track[:, 1], track[:, 0], color="tab:blue", linewidth=1.0, label="track")
        hull_east, hull_north = _earth(north, east, heading, _HULL[:, 0] * self.length, _HULL[:, 1] * self.breadth)
        axes.fill(hull_east, hull_north, color="0.25", zorder=3)
        rudder = state[S.RUDDER]
        chord = _RUDDER_CHORD * self.length
        rudder_east, rudder_north = _earth(
            north,
            east,
            heading,
            np.array([-0.5 * self.length, -0.5 * self.length - chord * math.cos(rudder)]),
            np.array([0.0, chord * math.sin(rudder)]),
        )
        axes.plot(rudder_east, rudder_north, color="tab:red", linewidth=2.0, zorder=4)

        span = max(np.ptp(track[:, 0]), np.ptp(track[:, 1]), 4.0 * self.length) + 4.0 * self.length
        centre_north = 0.5 * (track[:, 0].min() + track[:, 0].max())
        centre_east = 0.5 * (track[:, 1].min() + track[:, 1].max())
        reach = 0.4 * span
        for guide in guides:
            if guide.heading is None:
                guide_east, guide_north = guide.east, guide.north
            else:
                guide_east = np.array([east, east + reach * math.sin(guide.heading)])
                guide_north = np.array([north, north + reach * math.cos(guide.heading)])
            axes.plot(guide_east, guide_north, color="tab:green", linestyle="--", linewidth=1.0, label=guide.label)
        axes.set_xlim(centre_east - 0.5 * span, centre_east + 0.5 * span)
        axes.set_ylim(centre_north - 0.5 * span, centre_north + 0.5 * span)
        axes.set_aspect("equal")
        axes.set_xlabel("east (m)")
        axes.set_ylabel("north (m)")
        axes.legend(loc="lower right", fontsize=8)
        self._draw_disturbances(conditions)
        axes.set_title(
            f"t = {state[S.TIME]:.0f} s   heading {math.degrees(heading) % 360.0:05.1f} deg   {caption}\n"
            f"rudder {math.degrees(rudder):+.1f} deg (ordered {math.degrees(ordered_rudder):+.1f}, "
            f"limit {math.degrees(self.rudder_limit):.0f})   "
            f"rate of turn {math.degrees(state[S.RATE_OF_TURN]) * 60.0:+.0f} deg/min",
            fontsize=9,
        )
        if self._pyplot is not None:
            self._pyplot.pause(1.0 / self.render_fps)
            return None
        canvas = self.figure.canvas
        canvas.draw()
        return np.asarray(canvas.buffer_rgba())[:, :, :3].copy()

    def _draw_disturbances(self, sea: Conditions) -> None:
        """Arrows in the corner: where the wind blows and the current sets to, where the waves run."""
        arrows = {
            "wind": (sea.wind_speed, sea.wind_direction + math.pi, f"wind {sea.wind_speed:.1f} m/s"),
            "current": (sea.current_speed, sea.current_direction, f"current {sea.current_speed:.1f} m/s"),
            "waves": (sea.wave_height, sea.wave_direction + math.pi, f"waves Hs {sea.wave_height:.1f} m"),
        }
        for name, (size, towards, label) in arrows.items():
            if size <= 0.0:
                continue
            x, y = _ARROW_ORIGINS[name]
            self.axes.annotate(
                "",
                xy=(x + 0.07 * math.sin(towards), y + 0.07 * math.cos(towards)),
                xytext=(x, y),
                xycoords="axes fraction",
                arrowprops={"arrowstyle": "->", "color": "tab:purple"},
            )
            self.axes.text(x + 0.09, y, label, transform=self.axes.transAxes, fontsize=8, va="center")

    def close(self) -> None:
        """Release the figure (closes the ``"human"`` window)."""
        if self._pyplot is not None:
            self._pyplot.close(self.figure)
