"""chart_frame_time's column labels (paper_figures/charts.py) as drawn from the committed
experiments/results/table2.csv: no label overlaps another label, another label's leader or a
data point (near 10K, cylinder at 8,322 and camel at 9,770 vertices, the labels ran over the
markers). The figure
is drawn with matplotlib's Agg backend and measured in display pixels; nothing is written.
Needs matplotlib and VTK's Python module (figlib imports it; no display)."""

import pathlib
import sys

import numpy as np
import pytest

pytest.importorskip("vtk")
matplotlib = pytest.importorskip("matplotlib")
ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "paper_figures"))
import charts  # noqa: E402


@pytest.fixture(scope="module")
def labels():
    """The table-2 panel's label boxes, leader boxes and data points, in display pixels."""
    figures = []
    saved = charts.save
    charts.save = lambda fig, name: figures.append(fig)
    try:
        charts.chart_frame_time()
    finally:
        charts.save = saved
    fig = figures[0]
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[-1]  # the table-2 panel
    # Every text of the panel (the column labels; the leaders are text-less annotations).
    boxes = [t.get_window_extent(renderer) for t in ax.texts if t.get_text().strip()]
    leaders = [a.arrow_patch.get_window_extent(renderer) for a in ax.texts
               if isinstance(a, matplotlib.text.Annotation) and a.arrow_patch is not None]
    assert len(boxes) >= 6
    points = np.vstack([ax.transData.transform(line.get_xydata()) for line in ax.lines
                        if line.get_marker() not in (None, "None", "", " ")])
    return boxes, leaders, points


def test_no_label_overlaps_another(labels):
    boxes, _, _ = labels
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert a.x1 <= b.x0 or b.x1 <= a.x0 or a.y1 <= b.y0 or b.y1 <= a.y0, (a, b)


def test_no_leader_crosses_another_label(labels):
    boxes, leaders, _ = labels
    for j, leader in enumerate(leaders):
        x = 0.5 * (leader.x0 + leader.x1)
        for i, box in enumerate(boxes):
            crosses = box.x0 < x < box.x1 and box.y0 < leader.y1 and leader.y0 < box.y1
            assert i == j or not crosses, (j, i, box, leader)  # its own label sits on it


def test_no_label_covers_a_data_point(labels):
    # The labels sit in a band above the data (the scenario names written up the columns
    # before covered the markers at 10K).
    boxes, _, points = labels
    for box in boxes:
        inside = ((points[:, 0] > box.x0) & (points[:, 0] < box.x1) &
                  (points[:, 1] > box.y0) & (points[:, 1] < box.y1))
        assert not inside.any(), (box, points[inside])
