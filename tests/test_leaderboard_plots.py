"""The leaderboard's drawings at the size the documentation shows them: no text smaller than a reader can
read, no title run into another text."""

from __future__ import annotations

import itertools
import math

import matplotlib.pyplot as pyplot
import pytest
from matplotlib.figure import Figure
from matplotlib.text import Text
from matplotlib.transforms import Bbox

from ship_env.leaderboard.plots import DPI, PAGE_WIDTH_PX, draw_aggregate, draw_scores
from ship_env.leaderboard.statistics import Estimate
from ship_env.leaderboard.suites import DEV, TRACK_FOLLOW
from ship_env.leaderboard.tables import Standing, SuiteRanking

#: The smallest text height, pixels, that the drawings may show on the page (a browser's smallest default
#: font is 9 to 10 pixels).
MIN_TEXT_PX = 9.0
COURSE_CHANGERS = ("PPO (shipped)", "PD, fixed gains", "PD, gain-scheduled", "indirect adaptive PD", "MRAC")
TRACK_FOLLOWERS = ("PPO (shipped)", "predictor course changer")


def standing(rank: int, entrant: str, normalised: Estimate) -> Standing:
    kind = "learned" if entrant.startswith("PPO") else "classic"
    return Standing(rank, entrant, kind, normalised, normalised, None, {}, 5, 10, 50)


def dev_tables() -> list[SuiteRanking]:
    """The dev suite's 16 suites, each with its entrants' names and scores like the quick leaderboard's."""
    tables = []
    for suite in DEV.suites():
        names = TRACK_FOLLOWERS if suite.env_id == TRACK_FOLLOW else COURSE_CHANGERS
        rows = [
            standing(k + 1, name, Estimate(0.9 + k / 20, 0.85 + k / 20, 1.0 + k / 20)) for k, name in enumerate(names)
        ]
        rows.append(standing(len(rows) + 1, "navigators, track predictor (thesis)", Estimate(math.nan)))
        tables.append(SuiteRanking(suite, tuple(rows)))
    return tables


def drawn_texts(figure: Figure) -> list[Text]:
    """Every text the figure draws: the figure's titles and texts, each shown panel's title, axis labels,
    tick labels and legend."""
    texts = [*figure.texts, figure._suptitle]  # the title, if any, once as the title, once among the texts
    for group in figure.subfigs:
        texts += [*group.texts, group._suptitle]
    for axes in figure.axes:
        if not axes.axison:
            continue
        texts += [axes.title, axes.xaxis.label, axes.yaxis.label]
        for coordinate, axis in enumerate((axes.xaxis, axes.yaxis)):  # the tick labels in view (those drawn)
            low, high = sorted(axis.get_view_interval())
            texts += [label for label in axis.get_ticklabels() if low <= label.get_position()[coordinate] <= high]
        legend = axes.get_legend()
        if legend is not None:
            texts += legend.get_texts()
    drawn = [text for text in texts if text is not None and text.get_visible() and text.get_text().strip()]
    return list({id(text): text for text in drawn}.values())


def shown_scale(figure: Figure, tight: bool) -> float:
    """The factor a browser scales the written PNG by to fit the page column (1 where it fits)."""
    figure.draw_without_rendering()
    width_in = figure.get_tightbbox().width if tight else figure.get_figwidth()
    return min(1.0, PAGE_WIDTH_PX / (width_in * DPI))


def smallest_text_px(figure: Figure, tight: bool) -> tuple[float, str]:
    """The height, pixels on the page, of the figure's smallest text, and that text."""
    scale = shown_scale(figure, tight)
    text = min(drawn_texts(figure), key=lambda text: text.get_fontsize())
    return text.get_fontsize() / 72 * DPI * scale, text.get_text()


def outside(figure: Figure) -> list[str]:
    """The figure's texts that reach beyond its edges (cut off when it is written)."""
    figure.draw_without_rendering()
    renderer = figure.canvas.get_renderer()  # type: ignore[attr-defined]
    inside = figure.bbox.padded(0.5)
    boxes = [(text.get_text(), text.get_window_extent(renderer)) for text in drawn_texts(figure)]
    return [text for text, box in boxes if not (inside.contains(*box.p0) and inside.contains(*box.p1))]


def overlapping(figure: Figure) -> list[tuple[str, str]]:
    """The pairs of the figure's texts whose drawn boxes share an area."""
    figure.draw_without_rendering()
    renderer = figure.canvas.get_renderer()  # type: ignore[attr-defined]
    boxes = [(text.get_text(), text.get_window_extent(renderer)) for text in drawn_texts(figure)]
    return [
        (first, second)
        for (first, one), (second, other) in itertools.combinations(boxes, 2)
        if (overlap := Bbox.intersection(one, other)) is not None and overlap.width > 0 and overlap.height > 0
    ]


@pytest.fixture
def headline() -> Figure:
    estimates = {name: [Estimate(0.95, 0.92, 0.97), Estimate(0.96, 0.93, 0.98)] for name in COURSE_CHANGERS}
    xlabel = "normalised score (1 = PD, fixed gains), lower is better"
    figure = draw_aggregate(estimates, ["IQM", "Mean"], xlabel, "CourseChange, nominal ship, all seas (container_226m)")
    yield figure
    pyplot.close(figure)


def test_the_headline_title_stands_clear_of_the_panel_titles(headline):
    title = headline._suptitle.get_text()
    assert [axes.title.get_text() for axes in headline.axes] == ["IQM", "Mean"]
    assert [pair for pair in overlapping(headline) if title in pair] == []


def test_no_headline_text_runs_into_another(headline):
    assert overlapping(headline) == []


def test_the_headline_is_legible_at_the_page_width(headline):
    height, text = smallest_text_px(headline, tight=True)
    assert height >= MIN_TEXT_PX, f"{text!r} is {height:.1f} pixels high on the page"


def test_every_suite_score_panel_is_legible_at_the_page_width():
    drawing = draw_scores(dev_tables())
    assert sum(axes.axison for axes in drawing.axes) == 16
    height, text = smallest_text_px(drawing, tight=False)
    assert height >= MIN_TEXT_PX, f"{text!r} is {height:.1f} pixels high on the page"
    assert overlapping(drawing) == []
    assert outside(drawing) == []
