"""The text tables fit a terminal of 100 columns: a wide table wraps its header's words, then prints its
last column under each row; every cell is still printed, and a narrow table is printed as it was."""

from __future__ import annotations

from ship_env.text_table import Table

DESCRIPTION = (
    "rudder offset (neutral rudder angle not zero: a constant yaw moment that a course-keeping autopilot "
    "cancels with a standing rudder)"
)
WIDE = Table(
    ("rank", "effect", "corr", "held-out heading [deg]", "held-out track [m]", "score", "physical effect"),
    (
        ("", "(current model)", "", "0.37", "0.04", "0.56", "effects: yaw, speed_loss, kinematics"),
        ("1", "rudder_offset", "0.512", "0.20", "0.03", "0.31", DESCRIPTION),
        ("2", "propeller_slipstream", "-", "-", "-", "nan", ""),
    ),
    words=2,
)


def test_a_wide_table_fits_100_columns_and_keeps_every_cell():
    assert max(len(line) for line in WIDE.text(width=1000).splitlines()) > 100  # as it printed before
    text = WIDE.text()
    lines = text.splitlines()
    assert max(map(len, lines)) <= 100
    words = text.split()
    for row in (WIDE.header, *WIDE.rows):
        for cell in row:
            assert all(word in words for word in cell.split()), cell
    first = next(i for i, line in enumerate(lines) if line.startswith("1 "))
    assert lines[first].split() == ["1", "rudder_offset", "0.512", "0.20", "0.03", "0.31"]
    assert " ".join(" ".join(lines[first + 1 : first + 3]).split()) == DESCRIPTION
    assert lines[first + 3].split() == ["2", "propeller_slipstream", "-", "-", "-", "nan"]


def test_a_table_that_fits_wraps_its_header_only_where_it_must():
    narrow = Table(("controller", "IQM"), (("PD", "1.000"), ("MRAC", "1.012")))
    assert narrow.text() == "controller    IQM\n----------  -----\nPD          1.000\nMRAC        1.012"
    errors = Table(("run", "held-out heading [deg]", "held-out rate of turn [deg/s]"), (("zigzag", "0.37", "0.050"),))
    assert len(errors.text().splitlines()[0]) == 61
    assert errors.text(width=50).splitlines() == [
        "                  held-out",
        "        held-out   rate of",
        "         heading      turn",
        "run        [deg]   [deg/s]",
        "------  --------  --------",
        "zigzag      0.37     0.050",
    ]


def test_columns_said_to_hold_numbers_are_right_aligned_whatever_their_cells():
    table = Table(
        ("controller", "IQM [95 % CI]", "verdict", "completed"),
        (("PPO", "0.912 [0.85, 0.97]", "better", "10/10"), ("PD", "1.000 [0.98, 1.02]", "", "")),
        numbers=(False, True, False, True),
    )
    assert table.markdown().splitlines()[:2] == [
        "| controller | IQM [95 % CI] | verdict | completed |",
        "|---|---:|---|---:|",
    ]
    assert table.markdown().splitlines()[3] == "| PD | 1.000 [0.98, 1.02] |  |  |"
    assert table.text().splitlines()[3] == "PD          1.000 [0.98, 1.02]"
