"""The reference tracks of the thesis's simulator experiment and the distance of a ship to them.

Passenier (1989) 6.4.3: six tracks T1..T6, each with five course changes of 15, 30, 45, 75 and
105 deg in the order of Table 6.1.b, waypoints 2 to 2.5 nm apart so that the ship settles between
the changes. The navigators' score was the RMS perpendicular distance to the reference track,
sampled every 2 s (6.5), "corrected for the ship's inherent manoeuvrability": the reference track
turns at each waypoint on the ship's own turning circle (6.4.4.2). Here a reference track is the
polyline of waypoints with, at each corner, the arc of the ship's steady turn at the rudder limit
(10 deg in the experiment) tangent to both legs.

What the thesis does not give, chosen here and stated as such:

- **turn directions**: Table 6.1.b gives magnitudes only and Fig. 6.15 (the tracks' chart) is not
  in the text. The changes alternate starboard, port, starboard, port, starboard, so every leg
  stays within 105 deg of the first course: a track neither loops nor crosses itself, it runs
  like a passage through a fairway, and each track turns both ways;
- **leg lengths**: each track's six legs take the lengths 2.0, 2.1, ..., 2.5 nm in a different
  order (``THESIS_LEG_LENGTHS_NM``), so every track is 13.5 nm long, 44 min at 9.5 m/s through
  still water (the thesis: "each track took approximately 40 minutes");
- **first course**: north (000), the ship starting at the first waypoint, the origin.

Positions are (north, east) in metres, courses in radians clockwise from north, a positive course
change and a positive cross-track error to starboard (right of the direction of travel).
:func:`cross_track_error` is the distance the score uses, for the environments, baselines and a
leaderboard alike; its compiled core :func:`signed_cross_track` runs inside the environments' step.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ship_env.envs.checks import check_number
from ship_env.model import ShipModel
from ship_env.model.kernel import kernel

#: One nautical mile, m.
NAUTICAL_MILE = 1852.0

#: Table 6.1.a: the course changes C1 .. C5 of the experiment, deg.
THESIS_COURSE_CHANGES_DEG = (15.0, 30.0, 45.0, 75.0, 105.0)
#: Table 6.1.b: each track's five course changes in order, as the numbers of Table 6.1.a.
THESIS_TRACKS = {
    "T1": (4, 3, 2, 5, 1),
    "T2": (1, 4, 5, 2, 3),
    "T3": (3, 1, 5, 4, 2),
    "T4": (5, 2, 4, 1, 3),
    "T5": (2, 1, 3, 4, 5),
    "T6": (3, 5, 1, 2, 4),
}
#: The magnitudes of each track's course changes, deg, in order.
TRACK_COURSE_CHANGES_DEG = {
    track_id: tuple(THESIS_COURSE_CHANGES_DEG[number - 1] for number in numbers)
    for track_id, numbers in THESIS_TRACKS.items()
}
TRACK_IDS = tuple(TRACK_COURSE_CHANGES_DEG)
#: The turn directions, +1 starboard, -1 port (chosen: see the module docstring).
TURN_DIRECTIONS = (1.0, -1.0, 1.0, -1.0, 1.0)
#: The six legs' lengths of each track, nm: within the thesis's 2 to 2.5 nm (the order is chosen).
THESIS_LEG_LENGTHS_NM = {
    "T1": (2.0, 2.3, 2.1, 2.5, 2.2, 2.4),
    "T2": (2.2, 2.0, 2.4, 2.1, 2.5, 2.3),
    "T3": (2.4, 2.2, 2.0, 2.3, 2.1, 2.5),
    "T4": (2.1, 2.5, 2.3, 2.0, 2.4, 2.2),
    "T5": (2.3, 2.1, 2.5, 2.2, 2.0, 2.4),
    "T6": (2.5, 2.4, 2.2, 2.0, 2.3, 2.1),
}
#: The rudder limit of the experiment, deg (6.4.4.2).
THESIS_RUDDER_LIMIT_DEG = 10.0

# The leg table the compiled code reads: one row per leg k, from waypoint k to waypoint k + 1.
LEG_START_NORTH = 0  # m, waypoint k
LEG_START_EAST = 1
LEG_END_NORTH = 2  # m, waypoint k + 1
LEG_END_EAST = 3
LEG_COURSE = 4  # rad
LEG_LENGTH = 5  # m, waypoint to waypoint
STRAIGHT_START_NORTH = 6  # m, where the straight part begins: the end of the turn at waypoint k
STRAIGHT_START_EAST = 7
STRAIGHT_END_NORTH = 8  # m, where it ends: the start of the turn at waypoint k + 1
STRAIGHT_END_EAST = 9
TURN_CENTRE_NORTH = 10  # m, centre of the turn at waypoint k + 1
TURN_CENTRE_EAST = 11
TURN_RADIUS = 12  # m, 0 on the last leg
TURN_CHANGE = 13  # rad, the course change at waypoint k + 1, positive to starboard, 0 on the last leg
LEG_DIRECTION_NORTH = 14  # cos(course)
LEG_DIRECTION_EAST = 15  # sin(course)
LEG_FIELDS = 16


class TrackError(ValueError):
    """A reference track that cannot be drawn for a ship: its turns do not fit in the legs."""


@dataclass(frozen=True)
class ReferenceTrack:
    """A reference track: waypoints joined by legs, each corner rounded by a turning arc.

    Attributes:
        name: ``"T1"`` .. ``"T6"`` or a caller's name.
        waypoints: (M + 1, 2) north, east, m.
        course_changes: (M - 1,) rad, positive to starboard, at waypoints 1 .. M - 1.
        turn_radii: (M - 1,) m, the arcs' radii.
        legs: (M, ``LEG_FIELDS``) the leg table of the compiled code (layout above).
    """

    name: str
    waypoints: np.ndarray
    course_changes: np.ndarray
    turn_radii: np.ndarray
    legs: np.ndarray

    @property
    def courses(self) -> np.ndarray:
        """(M,) the legs' courses, rad."""
        return self.legs[:, LEG_COURSE].copy()

    @property
    def leg_lengths(self) -> np.ndarray:
        """(M,) waypoint-to-waypoint lengths, m."""
        return self.legs[:, LEG_LENGTH].copy()

    @property
    def arc_centres(self) -> np.ndarray:
        """(M - 1, 2) the turns' centres, north, east, m."""
        return self.legs[:-1, TURN_CENTRE_NORTH : TURN_CENTRE_EAST + 1].copy()

    @property
    def length(self) -> float:
        """The reference track's length, straights plus arcs, m."""
        straights = np.hypot(
            self.legs[:, STRAIGHT_END_NORTH] - self.legs[:, STRAIGHT_START_NORTH],
            self.legs[:, STRAIGHT_END_EAST] - self.legs[:, STRAIGHT_START_EAST],
        )
        return float(straights.sum() + np.sum(self.turn_radii * np.abs(self.course_changes)))

    def outline(self, points_per_radian: float = 20.0) -> np.ndarray:
        """(K, 2) north, east points along the reference track, the arcs sampled (for drawing)."""
        points = [self.legs[0, STRAIGHT_START_NORTH : STRAIGHT_START_EAST + 1]]
        for leg in self.legs:
            points.append(leg[STRAIGHT_END_NORTH : STRAIGHT_END_EAST + 1])
            change = leg[TURN_CHANGE]
            if change == 0.0:
                continue
            count = max(2, math.ceil(abs(change) * points_per_radian))
            # The radial direction from the centre to the arc's start is the course turned away
            # from the turn by 90 deg; it sweeps with the course.
            courses = leg[LEG_COURSE] + np.linspace(0.0, change, count + 1)[1:]
            radial = courses - math.copysign(0.5 * math.pi, change)
            points.extend(
                np.column_stack(
                    (
                        leg[TURN_CENTRE_NORTH] + leg[TURN_RADIUS] * np.cos(radial),
                        leg[TURN_CENTRE_EAST] + leg[TURN_RADIUS] * np.sin(radial),
                    )
                )
            )
        return np.vstack(points)


def build_track(
    name: str,
    course_changes: Sequence[float] | np.ndarray,
    leg_lengths: Sequence[float] | np.ndarray,
    starboard_radius: float,
    port_radius: float,
    first_course: float = 0.0,
) -> ReferenceTrack:
    """A reference track from the origin: legs of ``leg_lengths`` (m) joined by ``course_changes`` (rad).

    Each corner is rounded by an arc of ``starboard_radius`` or ``port_radius`` (m) tangent to both
    legs; its tangent points lie R tan(|change| / 2) before and after the waypoint. ``ValueError``
    if a change is not within (-180, 180) deg, :class:`TrackError` if the tangent points of a leg's
    two turns overlap.
    """
    changes = np.asarray(course_changes, dtype=np.float64)
    lengths = np.asarray(leg_lengths, dtype=np.float64)
    if changes.ndim != 1 or lengths.shape != (changes.size + 1,):
        raise ValueError(
            f"course_changes, leg_lengths: expected M - 1 changes and M legs, got {changes.size} and {lengths.size}"
        )
    if not (np.all(np.isfinite(changes)) and np.all(np.abs(changes) < math.pi) and np.all(changes != 0.0)):
        raise ValueError(f"course_changes: expected non-zero angles within (-pi, pi) rad, got {changes!r}")
    if not (np.all(np.isfinite(lengths)) and np.all(lengths > 0.0)):
        raise ValueError(f"leg_lengths: expected positive lengths in m, got {lengths!r}")
    check_number("starboard_radius", starboard_radius, 1e-6)
    check_number("port_radius", port_radius, 1e-6)

    courses = first_course + np.concatenate(([0.0], np.cumsum(changes)))
    directions = np.column_stack((np.cos(courses), np.sin(courses)))
    waypoints = np.vstack(([0.0, 0.0], np.cumsum(lengths[:, None] * directions, axis=0)))
    radii = np.where(changes > 0.0, starboard_radius, port_radius)
    tangents = radii * np.tan(0.5 * np.abs(changes))  # waypoint to tangent point, m
    before = np.concatenate((tangents, [0.0]))  # at the end of each leg
    after = np.concatenate(([0.0], tangents))  # at the start of each leg
    if np.any(before + after > lengths * (1.0 + 1e-12)):
        bad = int(np.flatnonzero(before + after > lengths)[0])
        raise TrackError(
            f"{name}: the turns at the ends of leg {bad} ({lengths[bad]:.0f} m) need {before[bad] + after[bad]:.0f} m"
        )

    legs = np.zeros((lengths.size, LEG_FIELDS))
    legs[:, LEG_START_NORTH : LEG_START_EAST + 1] = waypoints[:-1]
    legs[:, LEG_END_NORTH : LEG_END_EAST + 1] = waypoints[1:]
    legs[:, LEG_COURSE] = courses
    legs[:, LEG_DIRECTION_NORTH : LEG_DIRECTION_EAST + 1] = directions
    legs[:, LEG_LENGTH] = lengths
    legs[:, STRAIGHT_START_NORTH : STRAIGHT_START_EAST + 1] = waypoints[:-1] + after[:, None] * directions
    legs[:, STRAIGHT_END_NORTH : STRAIGHT_END_EAST + 1] = waypoints[1:] - before[:, None] * directions
    starboard = np.column_stack((-directions[:-1, 1], directions[:-1, 0]))  # the legs' right-hand normals
    turn = np.sign(changes)[:, None] * radii[:, None]
    legs[:-1, TURN_CENTRE_NORTH : TURN_CENTRE_EAST + 1] = (
        legs[:-1, STRAIGHT_END_NORTH : STRAIGHT_END_EAST + 1] + turn * starboard
    )
    legs[:-1, TURN_RADIUS] = radii
    legs[:-1, TURN_CHANGE] = changes
    return ReferenceTrack(name, waypoints, changes, radii, legs)


#: Steady turning radii already computed: (model record, service propeller rate, rudder angle, speed) -> m.
_RADII: dict[tuple[bytes, float, float, float | None], float] = {}


def steady_turn_radius(model: ShipModel, rudder: float, speed: float | None = None) -> float:
    """The radius of the model's steady turn at a constant rudder (rad, signed) in calm water, m.

    The circle fitted to the steady part of a simulated turning circle
    (:func:`ship_env.manoeuvres.turning_circle.turning_circle`): the model's own turn, with its
    Norrbin term, speed loss and drift, not the linear estimate L / (K* delta) (about 810 m for
    the container ship at 10 deg; the model turns on about 860 m). ``speed``: the approach speed,
    m/s (``None``: the service speed). :class:`TrackError` where the model settles in no steady turn.
    """
    # Imported here: the manoeuvres bring pandas, which the environments need only to build tracks.
    from ship_env.manoeuvres.settings import TrialSettings
    from ship_env.manoeuvres.turning_circle import turning_circle

    key = (model.record.tobytes(), model.service_propeller_rate, float(rudder), speed)
    if key not in _RADII:
        circle = turning_circle(model, float(rudder), TrialSettings(speed=speed))
        if not math.isfinite(circle.fitted_radius):
            raise TrackError(
                f"{model.ship.name}: the model does not settle in a steady turn at {math.degrees(rudder):g} deg rudder"
            )
        _RADII[key] = circle.fitted_radius
    return _RADII[key]


def reference_track(
    track_id: str,
    ship: str | ShipModel = "container_226m",
    rudder_limit_deg: float = THESIS_RUDDER_LIMIT_DEG,
    speed: float | None = None,
    first_course_deg: float = 0.0,
    scale: float = 1.0,
) -> ReferenceTrack:
    """Thesis track ``"T1"`` .. ``"T6"`` with the corners rounded by the ship's steady turns.

    :class:`TrackError` where a leg is too short for the ship's turns at its ends (a ship turning on
    a wider circle, in ship lengths, than the tracks' legs leave room for), naming the ship and its radii.

    Args:
        track_id: which track of Table 6.1.b.
        ship: a preset name or a :class:`~ship_env.model.ShipModel` whose steady turns at
            +-``rudder_limit_deg`` give the arcs' radii.
        rudder_limit_deg: the rudder of the turns, deg (the experiment's 10 deg).
        speed: the approach speed of the turns, m/s (``None``: the ship's service speed, 9.5 m/s
            for the container ship, the experiment's 19 kn).
        first_course_deg: the first leg's course, deg.
        scale: the legs' lengths times this (the tracks are drawn for the 226 m container ship: a
            ship of length L sails them in proportion at L / 226 m).
    """
    if track_id not in TRACK_COURSE_CHANGES_DEG:
        raise ValueError(f"track_id: expected one of {', '.join(TRACK_IDS)}, got {track_id!r}")
    model = ShipModel(ship) if isinstance(ship, str) else ship
    rudder = math.radians(check_number("rudder_limit_deg", rudder_limit_deg, 1e-3, 90.0))
    magnitudes = np.radians(TRACK_COURSE_CHANGES_DEG[track_id])
    radii = steady_turn_radius(model, rudder, speed), steady_turn_radius(model, -rudder, speed)
    try:
        return build_track(
            track_id,
            magnitudes * np.asarray(TURN_DIRECTIONS),
            np.asarray(THESIS_LEG_LENGTHS_NM[track_id]) * NAUTICAL_MILE * check_number("scale", scale, 1e-3),
            *radii,
            math.radians(check_number("first_course_deg", first_course_deg)),
        )
    except TrackError as error:
        in_lengths = " and ".join(f"{radius / model.length:.3g} L" for radius in radii)
        raise TrackError(
            f"{model.ship.name}: {error}: its steady turns at {rudder_limit_deg:g} deg rudder have radii "
            f"{radii[0]:.3g} m and {radii[1]:.3g} m ({in_lengths}), too wide for the legs scaled to its length"
        ) from None


@kernel
def nearest_on_track(north, east, legs):
    """The nearest point of a reference track to (north, east): (signed distance m, leg k, on its arc).

    The distance is positive to starboard of the track's direction of travel. The nearest point is
    searched on every straight part (clamped to its ends) and every arc (within its sector; outside
    it the nearest point is a straight part's end, which the straights cover). ``k`` is the leg
    whose straight part, or whose end turn's arc (``on_arc``), holds the point.
    """
    best = math.inf
    signed = 0.0
    nearest_leg = 0
    on_arc = False
    for k in range(legs.shape[0]):
        leg = legs[k]
        d_north, d_east = leg[LEG_DIRECTION_NORTH], leg[LEG_DIRECTION_EAST]
        start_north, start_east = leg[STRAIGHT_START_NORTH], leg[STRAIGHT_START_EAST]
        straight = (leg[STRAIGHT_END_NORTH] - start_north) * d_north + (leg[STRAIGHT_END_EAST] - start_east) * d_east
        along = (north - start_north) * d_north + (east - start_east) * d_east
        along = min(max(along, 0.0), straight)
        off_north = north - start_north - along * d_north
        off_east = east - start_east - along * d_east
        distance = math.hypot(off_north, off_east)
        if distance < best:
            best = distance
            signed = distance if -off_north * d_east + off_east * d_north >= 0.0 else -distance
            nearest_leg = k
            on_arc = False
        change = leg[TURN_CHANGE]
        if change == 0.0:
            continue
        turn = 1.0 if change > 0.0 else -1.0
        centre_north, centre_east = leg[TURN_CENTRE_NORTH], leg[TURN_CENTRE_EAST]
        # The sector from the arc's start (this straight's end) to its end (the next straight's
        # start), seen from the centre: turning with the ship, both cross products have its sign.
        w_north, w_east = north - centre_north, east - centre_east
        u0_north, u0_east = leg[STRAIGHT_END_NORTH] - centre_north, leg[STRAIGHT_END_EAST] - centre_east
        following = legs[k + 1]
        u1_north = following[STRAIGHT_START_NORTH] - centre_north
        u1_east = following[STRAIGHT_START_EAST] - centre_east
        if (
            turn * (u0_north * w_east - u0_east * w_north) >= 0.0
            and turn * (w_north * u1_east - w_east * u1_north) >= 0.0
        ):
            radius = leg[TURN_RADIUS]
            from_centre = math.hypot(w_north, w_east)
            if abs(from_centre - radius) < best:
                best = abs(from_centre - radius)
                signed = turn * (radius - from_centre)
                nearest_leg = k
                on_arc = True
    return signed, nearest_leg, on_arc


@kernel
def signed_cross_track(north, east, legs):
    """The signed distance from (north, east) to the nearest point of a reference track, m, positive
    to starboard (:func:`nearest_on_track`)."""
    return nearest_on_track(north, east, legs)[0]


@kernel
def path_ahead(north, east, legs, leg, on_arc):
    """The reference track at and ahead of its nearest point to (north, east) (``leg`` and ``on_arc``
    of :func:`nearest_on_track`): (its course there rad, its curvature there 1/m, the distance along
    the track to the next arc's start m (0 on an arc, infinite with no turn ahead), the next arc's
    curvature 1/m (the present arc's on one; 0 with no turn ahead)). Curvatures are positive to
    starboard: the rate of turn that sails the arc at speed u is u times it."""
    row = legs[leg]
    change = row[TURN_CHANGE]
    next_curvature = 0.0 if change == 0.0 else math.copysign(1.0 / row[TURN_RADIUS], change)
    if on_arc:
        turn = 1.0 if change > 0.0 else -1.0
        radial = math.atan2(east - row[TURN_CENTRE_EAST], north - row[TURN_CENTRE_NORTH])
        return radial + turn * 0.5 * math.pi, next_curvature, 0.0, next_curvature
    to_go = (row[STRAIGHT_END_NORTH] - north) * row[LEG_DIRECTION_NORTH] + (row[STRAIGHT_END_EAST] - east) * row[
        LEG_DIRECTION_EAST
    ]
    distance = math.inf if change == 0.0 else max(to_go, 0.0)
    return row[LEG_COURSE], 0.0, distance, next_curvature


@kernel
def point_ahead(north, east, legs, leg, on_arc, distance):
    """The point of a reference track ``distance`` m along it past its nearest point to (north, east)
    (``leg`` and ``on_arc`` of :func:`nearest_on_track`): (north, east) m, past the last waypoint
    on the last leg's line. A line-of-sight point: its bearing turns before the track does."""
    row = legs[leg]
    last = legs.shape[0] - 1
    if not on_arc:
        d_north, d_east = row[LEG_DIRECTION_NORTH], row[LEG_DIRECTION_EAST]
        to_go = max((row[STRAIGHT_END_NORTH] - north) * d_north + (row[STRAIGHT_END_EAST] - east) * d_east, 0.0)
        if distance <= to_go or leg == last:
            back = to_go - distance
            return row[STRAIGHT_END_NORTH] - back * d_north, row[STRAIGHT_END_EAST] - back * d_east
        distance -= to_go
        swept = 0.0
    else:
        turn = 1.0 if row[TURN_CHANGE] > 0.0 else -1.0
        start_north = row[STRAIGHT_END_NORTH] - row[TURN_CENTRE_NORTH]
        start_east = row[STRAIGHT_END_EAST] - row[TURN_CENTRE_EAST]
        w_north, w_east = north - row[TURN_CENTRE_NORTH], east - row[TURN_CENTRE_EAST]
        swept = turn * math.atan2(
            start_north * w_east - start_east * w_north, start_north * w_north + start_east * w_east
        )
        swept = min(max(swept, 0.0), abs(row[TURN_CHANGE]))
    while True:
        row = legs[leg]
        radius, change = row[TURN_RADIUS], row[TURN_CHANGE]
        turn = 1.0 if change > 0.0 else -1.0
        arc_left = radius * (abs(change) - swept)
        if distance <= arc_left:
            start = math.atan2(
                row[STRAIGHT_END_EAST] - row[TURN_CENTRE_EAST], row[STRAIGHT_END_NORTH] - row[TURN_CENTRE_NORTH]
            )
            radial = start + turn * (swept + distance / radius)
            return row[TURN_CENTRE_NORTH] + radius * math.cos(radial), row[TURN_CENTRE_EAST] + radius * math.sin(radial)
        distance -= arc_left
        leg += 1
        row = legs[leg]
        straight = (row[STRAIGHT_END_NORTH] - row[STRAIGHT_START_NORTH]) * row[LEG_DIRECTION_NORTH] + (
            row[STRAIGHT_END_EAST] - row[STRAIGHT_START_EAST]
        ) * row[LEG_DIRECTION_EAST]
        if distance <= straight or leg == last:
            return (
                row[STRAIGHT_START_NORTH] + distance * row[LEG_DIRECTION_NORTH],
                row[STRAIGHT_START_EAST] + distance * row[LEG_DIRECTION_EAST],
            )
        distance -= straight
        swept = 0.0


@kernel
def passed_waypoint(north, east, legs, leg):
    """Whether (north, east) is past the end of leg ``leg``: across the bisector of its corner with the
    next leg (the line through the waypoint and the turn's centre), or across the perpendicular at the
    last waypoint."""
    row = legs[leg]
    normal_north, normal_east = row[LEG_DIRECTION_NORTH], row[LEG_DIRECTION_EAST]
    if leg + 1 < legs.shape[0]:
        normal_north += legs[leg + 1][LEG_DIRECTION_NORTH]
        normal_east += legs[leg + 1][LEG_DIRECTION_EAST]
    return (north - row[LEG_END_NORTH]) * normal_north + (east - row[LEG_END_EAST]) * normal_east >= 0.0


@kernel
def _cross_track_errors(points, legs, out):
    for i in range(points.shape[0]):
        out[i] = signed_cross_track(points[i, 0], points[i, 1], legs)


def cross_track_error(position: ArrayLike, track: ReferenceTrack) -> np.ndarray:
    """Signed cross-track errors of positions from a reference track, m, positive to starboard.

    The perpendicular distance to the nearest point of the track, straights and arcs (the distance
    of the thesis's score, 6.5). ``position``: (..., 2) north, east, m; returns shape (...).
    """
    points = np.asarray(position, dtype=np.float64)
    if points.ndim < 1 or points.shape[-1] != 2:
        raise ValueError(f"position: expected (..., 2) north, east positions in m, got shape {points.shape}")
    flat = np.ascontiguousarray(points.reshape(-1, 2))
    errors = np.empty(flat.shape[0])
    _cross_track_errors(flat, track.legs, errors)
    return errors.reshape(points.shape[:-1])
