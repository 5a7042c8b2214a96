"""Drawing a ship's episode with matplotlib: the track, the ship at scale, the rudder, the disturbances
and the task's guides (a new heading, a reference track). North is up, east to the right, distances
in metres.

``"rgb_array"`` draws off-screen (Agg canvas) and returns the frame; ``"human"`` draws into a pyplot
window and pauses for one frame at the environment's frame rate.

One figure is kept and its artists updated every frame. The view holds still while the ship's track
stays more than a ship length inside it, and is framed afresh (around the track, with two lengths to
spare) once it does not, so what does not move (the axes, their ticks and labels, the disturbances'
arrows) is drawn only when the view or the sea changes; ``"rgb_array"`` keeps that picture and draws
the moving artists (track, guides, hull, rudder and title, then the legend's pixels) over a copy of it each frame
(matplotlib's blitting): 600 x 600 frames at about 100 a second instead of 3 to 9 where every frame
was drawn afresh (2-core machine; ``benchmarks/bench_envs.py``).
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


class _View(NamedTuple):
    """The axes' limits, m: east and north of the frame's centre, and its side."""

    east: float
    north: float
    span: float

    @classmethod
    def framing(cls, track: np.ndarray, length: float) -> _View:
        """The view around ``track`` (k, 2) north/east positions: the track's bounding box's centre, a side
        of the box's larger extent (at least four lengths) plus four lengths."""
        span = max(np.ptp(track[:, 0]), np.ptp(track[:, 1]), 4.0 * length) + 4.0 * length
        return cls(0.5 * (track[:, 1].min() + track[:, 1].max()), 0.5 * (track[:, 0].min() + track[:, 0].max()), span)

    def holds(self, track: np.ndarray, margin: float) -> bool:
        """Whether every point of ``track`` lies at least ``margin`` inside the view."""
        reach = 0.5 * self.span - margin
        return bool(np.abs(track[:, 1] - self.east).max() <= reach and np.abs(track[:, 0] - self.north).max() <= reach)


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
        axes = self.axes
        axes.set_aspect("equal")
        axes.set_xlabel("east (m)")
        axes.set_ylabel("north (m)")
        # The moving artists, drawn over the still picture in "rgb_array" (animated: left out of it).
        animated = self._pyplot is None
        (self._track_line,) = axes.plot([], [], color="tab:blue", linewidth=1.0, label="track", animated=animated)
        (self._hull,) = axes.fill([], [], color="0.25", zorder=3, animated=animated)
        (self._rudder,) = axes.plot([], [], color="tab:red", linewidth=2.0, zorder=4, animated=animated)
        self._guide_lines: list = []
        self._legend = None
        self._title = axes.set_title("", fontsize=9, animated=animated)
        for spine in axes.spines.values():  # the axes' frame, drawn over the lines as in a whole drawing
            spine.set_animated(animated)
        self._sea: list = []  # the disturbances' arrows and labels
        self._view: _View | None = None
        self._conditions: Conditions | None = None
        self._background = None  # the still picture, for "rgb_array"
        self._legend_pixels: tuple[slice, slice, np.ndarray] = (slice(0), slice(0), np.zeros((0, 0, 4), np.uint8))

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
        north, east, heading = state[S.NORTH], state[S.EAST], state[S.HEADING]
        still_changed = self._frame(track, conditions, guides)
        self._track_line.set_data(track[:, 1], track[:, 0])
        hull_east, hull_north = _earth(north, east, heading, _HULL[:, 0] * self.length, _HULL[:, 1] * self.breadth)
        self._hull.set_xy(np.column_stack((hull_east, hull_north)))
        rudder = state[S.RUDDER]
        chord = _RUDDER_CHORD * self.length
        rudder_east, rudder_north = _earth(
            north,
            east,
            heading,
            np.array([-0.5 * self.length, -0.5 * self.length - chord * math.cos(rudder)]),
            np.array([0.0, chord * math.sin(rudder)]),
        )
        self._rudder.set_data(rudder_east, rudder_north)
        assert self._view is not None
        reach = 0.4 * self._view.span
        for guide, line in zip(guides, self._guide_lines, strict=True):
            if guide.heading is None:
                line.set_data(guide.east, guide.north)
            else:
                line.set_data(
                    [east, east + reach * math.sin(guide.heading)], [north, north + reach * math.cos(guide.heading)]
                )
        self._title.set_text(
            f"t = {state[S.TIME]:.0f} s   heading {math.degrees(heading) % 360.0:05.1f} deg   {caption}\n"
            f"rudder {math.degrees(rudder):+.1f} deg (ordered {math.degrees(ordered_rudder):+.1f}, "
            f"limit {math.degrees(self.rudder_limit):.0f})   "
            f"rate of turn {math.degrees(state[S.RATE_OF_TURN]) * 60.0:+.0f} deg/min"
        )
        if self._pyplot is not None:
            self._pyplot.pause(1.0 / self.render_fps)
            return None
        canvas = self.figure.canvas
        if still_changed or self._background is None:
            canvas.draw()  # the still picture: every artist not animated
            self._background = canvas.copy_from_bbox(self.figure.bbox)
            self._legend_pixels = self._legend_rows_columns()
        else:
            canvas.restore_region(self._background)
        # In the order of their zorder, as a whole drawing has them.
        for artist in (
            self._track_line,
            *self._guide_lines,
            *axes.spines.values(),
            self._hull,
            self._rudder,
            self._title,
        ):
            axes.draw_artist(artist)
        pixels = np.asarray(canvas.buffer_rgba())
        rows, columns, legend = self._legend_pixels
        pixels[rows, columns] = legend  # the legend over the lines, as drawn with the still picture
        return pixels[:, :, :3].copy()

    def _legend_rows_columns(self) -> tuple[slice, slice, np.ndarray]:
        """The legend's rows and columns in the canvas, and its pixels there (drawn with the still picture)."""
        assert self._legend is not None
        height = self.figure.canvas.get_width_height()[1]
        extent = self._legend.get_window_extent()  # pixels from the lower left
        rows = slice(height - math.ceil(extent.y1), height - math.floor(extent.y0))
        columns = slice(math.floor(extent.x0), math.ceil(extent.x1))
        return rows, columns, np.asarray(self.figure.canvas.buffer_rgba())[rows, columns].copy()

    def _frame(self, track: np.ndarray, conditions: Conditions, guides: list[Guide]) -> bool:
        """Set what does not move, where it changed: the view (framed afresh once the track comes
        within a ship length of its edge), the guides' lines and the legend, the disturbances'
        arrows. Whether any of it changed."""
        changed = False
        labels = [guide.label for guide in guides]
        if labels != [line.get_label() for line in self._guide_lines]:
            for line in self._guide_lines:
                line.remove()
            self._guide_lines = [
                self.axes.plot(
                    [], [], color="tab:green", linestyle="--", linewidth=1.0, label=label, animated=self._pyplot is None
                )[0]
                for label in labels
            ]
            if self._legend is not None:
                self._legend.remove()
            self._legend = self.axes.legend(loc="lower right", fontsize=8)
            changed = True
        if self._view is None or not self._view.holds(track, self.length):
            self._view = _View.framing(track, self.length)
            half = 0.5 * self._view.span
            self.axes.set_xlim(self._view.east - half, self._view.east + half)
            self.axes.set_ylim(self._view.north - half, self._view.north + half)
            changed = True
        if conditions != self._conditions:
            self._conditions = conditions
            self._draw_disturbances(conditions)
            changed = True
        return changed

    def _draw_disturbances(self, sea: Conditions) -> None:
        """Arrows in the corner: where the wind blows and the current sets to, where the waves run."""
        for artist in self._sea:
            artist.remove()
        self._sea = []
        arrows = {
            "wind": (sea.wind_speed, sea.wind_direction + math.pi, f"wind {sea.wind_speed:.1f} m/s"),
            "current": (sea.current_speed, sea.current_direction, f"current {sea.current_speed:.1f} m/s"),
            "waves": (sea.wave_height, sea.wave_direction + math.pi, f"waves Hs {sea.wave_height:.1f} m"),
        }
        for name, (size, towards, label) in arrows.items():
            if size <= 0.0:
                continue
            x, y = _ARROW_ORIGINS[name]
            arrow = self.axes.annotate(
                "",
                xy=(x + 0.07 * math.sin(towards), y + 0.07 * math.cos(towards)),
                xytext=(x, y),
                xycoords="axes fraction",
                arrowprops={"arrowstyle": "->", "color": "tab:purple"},
            )
            text = self.axes.text(x + 0.09, y, label, transform=self.axes.transAxes, fontsize=8, va="center")
            self._sea += [arrow, text]

    def close(self) -> None:
        """Release the figure (closes the ``"human"`` window)."""
        if self._pyplot is not None:
            self._pyplot.close(self.figure)
