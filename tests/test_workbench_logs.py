"""Measurement logs: formats, unit conversion, and a clear error for every kind of bad log."""

from __future__ import annotations

import functools
import hashlib
import math

import numpy as np
import pandas as pd
import pytest

from ship_env.workbench import (
    Column,
    FormatError,
    Log,
    LogError,
    LogFormat,
    LogWarning,
    load_log,
    load_logs,
    write_log,
)
from ship_env.workbench.logs.formats import format_template, read_format
from ship_env.workbench.logs.logs import every_nth, log_from_frame


def standard_frame(samples: int = 50) -> pd.DataFrame:
    """A small log in the standard format: a ship turning slowly to starboard."""
    time = np.arange(samples) * 0.5
    return pd.DataFrame(
        {
            "time": time,
            "heading": 0.01 * time,
            "rudder": np.full(samples, 0.1),
            "rate_of_turn": np.full(samples, 0.01),
            "north": 2.0 * time,
            "east": 0.1 * time,
            "speed": np.full(samples, 2.0),
        }
    )


def trial_format(**changes) -> LogFormat:
    columns = {
        "time": Column("Time", "s"),
        "heading": Column("HDG", "deg"),
        "rudder": Column("Rudder", "deg", sign=-1.0),
        "rate_of_turn": Column("ROT", "deg/min"),
        "speed": Column("STW", "kn"),
    }
    columns.update(changes)
    return LogFormat("trial", columns)


def trial_frame(samples: int = 40) -> pd.DataFrame:
    """A log in degrees, knots and deg/min, port rudder positive, heading wrapped at 360 deg."""
    time = np.arange(samples) * 1.0
    heading = (350.0 + 2.0 * time) % 360.0
    return pd.DataFrame(
        {
            "Time": time,
            "HDG": heading,
            "Rudder": np.full(samples, -10.0),
            "ROT": np.full(samples, 120.0),
            "STW": np.full(samples, 10.0),
        }
    )


def test_standard_csv_and_parquet_round_trip(tmp_path):
    log = log_from_frame(standard_frame(), "standard", name="turn")
    for ending in ("csv", "parquet"):
        path = write_log(log, tmp_path / f"turn.{ending}")
        again = load_log(path)
        assert again.name == "turn" and again.channels() == log.channels()
        for channel in log.channels():
            np.testing.assert_allclose(getattr(again, channel), getattr(log, channel))
    assert load_log(tmp_path / "turn.csv").propeller_rate is None  # optional channels may be absent


def test_a_written_log_reads_back_bit_for_bit(tmp_path):
    """Nothing a log holds is lost on the way through a file: pandas' default CSV parser reads some
    17-digit numbers one or two units in the last place off (11.855149524425073 as ...071), which moved
    a constant propeller rate just outside the range a fit on the same runs covered (a CoverageWarning)."""
    frame = standard_frame()
    frame["heading"] += np.random.default_rng(3).uniform(-1e-3, 1e-3, len(frame))  # 17 digits
    frame["propeller_rate"] = 11.855149524425073
    log = log_from_frame(frame, "standard", name="turn")
    for ending in ("csv", "parquet"):
        again = load_log(write_log(log, tmp_path / f"turn.{ending}"))
        for channel in log.channels():
            np.testing.assert_array_equal(getattr(again, channel), getattr(log, channel), err_msg=channel)


def test_declared_units_signs_and_wrapped_heading_are_converted():
    log = log_from_frame(trial_frame(), trial_format(), name="trial")
    np.testing.assert_allclose(np.degrees(log.heading), 350.0 + 2.0 * log.time)  # unwrapped through north
    assert any("unwrapped 1 jumps" in note for note in log.notes)
    np.testing.assert_allclose(log.rudder, math.radians(10.0))  # port-positive log, starboard-positive model
    np.testing.assert_allclose(log.rate_of_turn, math.radians(2.0))  # 120 deg/min
    np.testing.assert_allclose(log.speed, 10.0 * 1852.0 / 3600.0)
    assert log.rudder_kind == "actual"


def test_format_from_yaml(tmp_path):
    path = tmp_path / "trial.yaml"
    path.write_text(
        "name: trial\nrudder_kind: ordered\ncolumns:\n"
        "  time: {column: Time, unit: s}\n  heading: {column: HDG, unit: deg}\n"
        "  rudder: {column: Rudder, unit: deg, sign: -1}\n  rate_of_turn: {column: ROT, unit: deg/min}\n"
        "  speed: {column: STW, unit: kn}\n  propeller_rate: {column: RPM, unit: rpm, optional: true}\n"
    )
    fmt = read_format(path)
    assert fmt.rudder_kind == "ordered" and fmt.columns["propeller_rate"].optional
    frame_path = tmp_path / "run.csv"
    trial_frame().to_csv(frame_path, index=False)
    log = load_log(frame_path, str(path))
    assert log.propeller_rate is None and log.rudder_kind == "ordered"


@pytest.mark.parametrize(
    "changes, message",
    [
        ({"bearing": Column("B", "deg")}, "unknown channel 'bearing'"),
        ({"heading": Column("HDG", "grad")}, "unit 'grad'; use one of rad, deg"),
        ({"north": Column("N", "m")}, "give both 'north' and 'east'"),
        ({"rudder": Column("Rudder", "deg", sign=2.0)}, "sign must be 1 or -1"),
    ],
)
def test_bad_formats_say_what_is_wrong(changes, message):
    with pytest.raises(FormatError, match=message):
        trial_format(**changes)


def test_missing_required_channel_in_a_format():
    with pytest.raises(FormatError, match="channels rudder are required"):
        LogFormat("x", {"time": Column("t", "s"), "heading": Column("h", "rad")})


def test_missing_column_is_named_with_a_suggestion(tmp_path):
    frame = trial_frame().rename(columns={"HDG": "HDG_true"})
    with pytest.raises(LogError, match=r"missing column 'HDG' \(heading\) \(did you mean 'HDG_true'\?\)"):
        log_from_frame(frame, trial_format(), name="trial")


def test_undetectable_format_lists_the_columns():
    with pytest.raises(LogError, match="no built-in log format fits the columns"):
        log_from_frame(trial_frame(), None, name="trial")


def test_undetectable_format_names_the_missing_channels_and_prints_a_format_file_that_reads_the_log(tmp_path):
    frame = trial_frame().rename(
        columns={"Time": "Time [s]", "HDG": "HDG [deg]", "Rudder": "Rudder (deg)", "ROT": "ROT [deg/min]"}
    )
    frame["Wind speed [kn]"] = 8.0  # a "speed" header the template must not take for the ship's speed
    frame["wind_dir (deg)"] = 90.0
    with pytest.raises(LogError) as error:
        log_from_frame(frame, None, name="trial", source="trial.csv")
    message = str(error.value)
    assert "a log needs the channels time, heading, rudder" in message
    assert "(missing: time, heading, rudder;" in message
    assert "pass it with --format FILE.yaml" in message
    template = message.split("check and fill in:\n\n", 1)[1]
    assert 'speed: {column: "STW", unit: m/s}' in template  # no unit in the header: the SI one, to check
    (tmp_path / "trial.yaml").write_text(template.replace('"STW", unit: m/s', '"STW", unit: kn'))
    log = log_from_frame(frame, str(tmp_path / "trial.yaml"), name="trial")
    expected = log_from_frame(trial_frame(), trial_format(rudder=Column("Rudder", "deg")), name="trial")
    for channel in ("time", "heading", "rudder", "rate_of_turn", "speed"):
        np.testing.assert_allclose(getattr(log, channel), getattr(expected, channel))
    np.testing.assert_allclose(log.wind_speed, 8.0 * 1852.0 / 3600.0)
    np.testing.assert_allclose(log.wind_direction, math.pi / 2.0)
    assert 'east: {column: "?", unit: m}' in format_template(["t", "psi", "rudder", "x"])  # north's partner


def test_a_template_fills_in_a_required_channel_no_header_suggests():
    with pytest.raises(LogError) as error:
        log_from_frame(trial_frame().rename(columns={"Rudder": "Helm"}), None, name="trial")
    assert 'rudder: {column: "?", unit: rad}   # no header named like it' in str(error.value)


def test_text_in_a_numeric_column():
    frame = trial_frame().astype({"STW": object})
    frame.loc[7, "STW"] = "n/a"
    with pytest.raises(LogError, match=r"column 'STW' \(speed\) holds 'n/a' at row 8, not a number"):
        log_from_frame(frame, trial_format(), name="trial")


@pytest.mark.parametrize(
    "times, message",
    [
        ([0.0, 1.0, 2.0, 2.0, 3.0], r"time column 'Time' repeats at row 4: t = 2 after 2"),
        ([0.0, 1.0, 2.0, 1.5, 3.0], r"time column 'Time' goes back at row 4: t = 1.5 after 2"),
    ],
)
def test_time_must_increase(times, message):
    frame = trial_frame()
    frame.loc[: len(times) - 1, "Time"] = times
    frame.loc[len(times) :, "Time"] = np.arange(len(frame) - len(times)) + 10.0
    with pytest.raises(LogError, match=message):
        log_from_frame(frame, trial_format(), name="trial")


def test_trailing_nan_rows_are_cut_with_a_warning():
    frame = trial_frame()
    frame.loc[30:, ["HDG", "Rudder"]] = np.nan
    with pytest.warns(LogWarning, match="dropped the last 10 rows: NaN in 'HDG', 'Rudder'"):
        log = log_from_frame(frame, trial_format(), name="trial")
    assert log.samples == 30 and "dropped the last 10 rows" in log.notes[0]


@pytest.mark.parametrize("rows, where", [(slice(12, 14), "inside the log"), (slice(0, 2), "at the start")])
def test_nan_gap_inside_or_at_the_start_is_an_error(rows, where):
    frame = trial_frame()
    frame.loc[rows, "ROT"] = np.nan
    first, last = rows.start + 1, rows.stop + 1
    with pytest.raises(LogError, match=rf"'ROT' \(rate_of_turn\) is NaN at rows {first}..{last} .* {where}"):
        log_from_frame(frame, trial_format(), name="trial")


def test_degrees_declared_as_radians_are_caught():
    frame = trial_frame()
    with pytest.raises(
        LogError, match=r"'Rudder' \(rudder\) is declared in rad but reaches 10, beyond 2 pi: it looks like degrees"
    ):
        log_from_frame(frame, trial_format(rudder=Column("Rudder", "rad")), name="trial")
    with pytest.raises(LogError, match=r"'HDG' \(heading\) is declared in rad but reaches .* looks like degrees"):
        log_from_frame(frame, trial_format(heading=Column("HDG", "rad")), name="trial")
    standard = standard_frame()
    standard["rate_of_turn"] = np.degrees(standard["rate_of_turn"])  # deg/s declared rad/s
    with pytest.raises(LogError, match=r"changes 0.0175 times as fast as the rate of turn"):
        log_from_frame(standard, "standard", name="turn")


def test_the_users_file_is_only_read(tmp_path):
    path = tmp_path / "run.csv"
    frame = trial_frame()
    frame.loc[30:, "HDG"] = np.nan
    frame.to_csv(path, index=False)
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    with pytest.warns(LogWarning):
        load_log(path, trial_format())
    assert hashlib.sha256(path.read_bytes()).hexdigest() == digest


def test_files_folders_and_their_errors(tmp_path):
    for name in ("a", "b"):
        standard_frame().to_csv(tmp_path / f"{name}.csv", index=False)
    (tmp_path / "notes.txt").write_text("not a log")
    assert [log.name for log in load_logs([tmp_path])] == ["a", "b"]
    with pytest.raises(LogError, match="no such file"):
        load_log(tmp_path / "c.csv")
    with pytest.raises(LogError, match=r"cannot read \.txt"):
        load_log(tmp_path / "notes.txt")
    with pytest.raises(LogError, match=r"the run names \['a'\] repeat"):
        load_logs([tmp_path / "a.csv", tmp_path / "a.csv"])


def test_a_folder_that_does_not_exist_is_named_so(tmp_path):
    with pytest.raises(LogError, match=r"runs: no such file or folder$"):  # was "cannot read files without an ending"
        load_logs([tmp_path / "runs"])


def test_a_folder_of_folders_names_those_that_hold_logs(tmp_path):
    for name in ("zigzag", "turning"):
        (tmp_path / name).mkdir()
        standard_frame().to_csv(tmp_path / name / "run.csv", index=False)
    (tmp_path / "empty").mkdir()
    (tmp_path / "README.txt").write_text("what ship-env demo-logs wrote")
    with pytest.raises(LogError) as error:
        load_logs([tmp_path])
    assert str(error.value) == (
        f"{tmp_path}: no .csv, .parquet, .pq files in this folder; its folders turning, zigzag hold logs: "
        f"pass one or several of them (say {tmp_path / 'turning'})"
    )


def test_every_nth_sample():
    log = log_from_frame(standard_frame(), "standard", name="turn")
    coarse = every_nth(log, 5)
    assert coarse.samples == 10 and coarse.time[1] == 2.5
    with pytest.raises(LogError, match="positive whole number"):
        every_nth(log, 0)


def test_a_log_built_in_code_is_checked():
    with pytest.raises(LogError, match="channel 'rudder' must be 20 finite values"):
        Log("x", np.arange(20.0), np.zeros(20), np.zeros(19))


@pytest.mark.parametrize("gyro", [True, False])
def test_a_log_does_not_change_once_made(gyro):
    """The fit's worker processes receive the logs by pickle, from a thread of their own while the fit reads them: a
    log that filled a cache on first use changed under that thread ("dictionary changed size during iteration",
    the Esso ladder's first parallel screening). Every property read leaves the log as it was made, with or without
    a rate gyro (whose absence the heading's smoothed rate stands in for)."""
    frame = standard_frame()
    log = log_from_frame(frame if gyro else frame.drop(columns="rate_of_turn"), name="turn")
    made = dict(vars(log))
    for name in dir(type(log)):
        if isinstance(getattr(type(log), name), (property, functools.cached_property)):
            getattr(log, name)
    assert vars(log).keys() == made.keys()
    assert all(vars(log)[key] is made[key] for key in made)
    np.testing.assert_allclose(log.rate_of_turn_or_smoothed, 0.01, rtol=1e-6)
