"""Spikes and jumps in a log's channels: beyond a physical limit an error, an outlier a warning, naming the
file, the column, the row and the value; genuine manoeuvres (the Esso Osaka model tests) are clean."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ship_env.workbench import LogError, LogWarning, load_log, load_logs

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "esso_osaka"


def noisy_turn(samples: int = 200) -> pd.DataFrame:
    """A ship turning to starboard at 2 m/s, its sensors noisy, in the standard format (SI units)."""
    rng = np.random.default_rng(1)
    time = np.arange(samples) * 0.5
    return pd.DataFrame(
        {
            "time": time,
            "heading": 0.01 * time + rng.normal(0.0, 0.002, samples),
            "rudder": np.full(samples, 0.1),
            "rate_of_turn": 0.01 + rng.normal(0.0, 0.0005, samples),
            "north": 2.0 * time + rng.normal(0.0, 0.05, samples),
            "east": 0.1 * time + rng.normal(0.0, 0.05, samples),
            "speed": 2.0 + rng.normal(0.0, 0.01, samples),
        }
    )


def written(frame: pd.DataFrame, folder: Path) -> Path:
    path = folder / "run.csv"
    frame.to_csv(path, index=False)
    return path


def test_a_sample_beyond_a_physical_limit_is_an_error_naming_file_column_row_and_value(tmp_path):
    frame = noisy_turn()
    frame.loc[40, "north"] = 1e30  # the file's row 41
    path = written(frame, tmp_path)
    with pytest.raises(LogError) as error:
        load_log(path)
    assert str(path) in str(error.value)
    assert "column 'north'" in str(error.value) and "row 41" in str(error.value) and "1e+30" in str(error.value)

    frame = noisy_turn()
    frame.loc[9, "speed"] = 80.0
    with pytest.raises(LogError, match=r"column 'speed' \(speed\) holds 80 at row 10, beyond 50 m/s"):
        load_log(written(frame, tmp_path))


def test_an_outlier_within_the_limits_is_a_warning_naming_its_row(tmp_path):
    frame = noisy_turn()
    frame.loc[120, "heading"] += 0.3  # 17 deg away for one sample: possible, but not a ship's motion
    path = written(frame, tmp_path)
    with pytest.warns(LogWarning) as caught:
        log = load_log(path)
    (message,) = [str(w.message) for w in caught]
    assert str(path) in message and "column 'heading'" in message and "row 121" in message
    assert f"{frame.loc[120, 'heading']:g}" in message
    assert any("row 121" in note for note in log.notes)


def test_a_clean_log_and_a_step_do_not_warn(tmp_path):
    frame = noisy_turn()
    frame.loc[100:, "speed"] += 0.5  # a step, not out and back: no outlier
    with warnings.catch_warnings():
        warnings.simplefilter("error", LogWarning)
        load_log(written(frame, tmp_path))


@pytest.mark.skipif(not DATA.is_dir(), reason=f"the Esso Osaka data is not at {DATA}")
@pytest.mark.parametrize("kind", ["zigzag", "turning", "berthing"])
def test_the_esso_osaka_logs_have_no_spikes(kind):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", LogWarning)
        load_logs([DATA / kind])
    assert [str(w.message) for w in caught if "and back" in str(w.message)] == []
