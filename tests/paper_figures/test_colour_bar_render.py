"""The figures' colour bar (figlib.scalar_bar) rendered with VTK over a mesh that fills the
panel, as in the free-limb figure, and read back from the PNG: the title clears the top
label (Fig. 5's "E_i/N_i" above "0.1"), and every label and the title sit on a light
backing, not on the mesh. Needs VTK and an X display (ctest runs it under xvfb-run as
paper_figures/colour_bar_render_test); skipped without them."""

import os
import pathlib
import sys

import numpy as np
import pytest

vtk = pytest.importorskip("vtk")
PIL = pytest.importorskip("PIL.Image")
if not os.environ.get("DISPLAY"):
    pytest.skip("no X display (run under xvfb-run)", allow_module_level=True)

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "paper_figures"))
import figlib  # noqa: E402

MESH = (0.25, 0.1, 0.45)  # a dark purple, as the low end of viridis on the figures' meshes


def render_bar(path):
    V = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float) * 10
    F = np.array([[0, 1, 2], [0, 2, 3]])
    lut = figlib.lut_viridis()
    lut.SetTableRange(0, 0.1)
    cam = figlib.camera_for(V, (0, 0, 1), (0, 1, 0), zoom=3.0)  # the quad fills the panel
    figlib.render_panels([dict(actors=[figlib.mesh_actor(V, F, color=MESH)], camera=cam,
                               label="", bar=(lut, "E_i/N_i"))],
                         str(path), panel_size=(400, 480))
    return np.asarray(PIL.open(path).convert("RGB")).astype(int)


@pytest.fixture(scope="module")
def image(tmp_path_factory):
    return render_bar(tmp_path_factory.mktemp("bar") / "bar.png")


def bar_columns(img):
    """The columns and top row of the colour bar: viridis' yellow top (253, 231, 37)."""
    yellow = (np.abs(img - np.array([253, 231, 37])).sum(-1) < 60)
    rows, cols = np.nonzero(yellow)
    return cols.min(), cols.max(), rows.min()


def test_title_clears_the_top_label(image):
    left, right, top = bar_columns(image)
    ink = (image < 60).all(-1)  # black text
    region = ink[:top, left - 5:image.shape[1]]
    rows = np.nonzero(region.any(1))[0]
    # Above the bar's top: the title's rows, then the upper half of the top label's, with
    # blank rows between.
    bands = np.split(rows, np.nonzero(np.diff(rows) > 1)[0] + 1)
    assert len(bands) >= 2, rows
    gap = bands[-1][0] - bands[-2][-1] - 1
    assert gap >= 3, (bands[-2], bands[-1])


def test_labels_and_title_sit_on_a_light_backing(image):
    left, right, top = bar_columns(image)
    ink = (image < 60).all(-1)
    ink[:, :right + 1] = False  # the labels and the title's part right of the bar
    ink[:top - 60] = False  # below the panel label, the bar's title and labels only
    ys, xs = np.nonzero(ink)
    assert len(ys) > 50
    # The pixels one and two away from each ink pixel (left, above, right, below) that are
    # not ink themselves: the backing, or the text's grey anti-aliasing, not the mesh.
    mesh = image[5, 5]  # the panel's corner: the lit mesh
    near = []
    for dy, dx in ((0, -1), (-1, 0), (0, 1), (1, 0), (0, -2), (-2, 0), (0, 2), (2, 0)):
        y, x = ys + dy, xs + dx
        keep = ~ink[y, x]
        near.append(image[y[keep], x[keep]])
    on_mesh = (np.abs(np.concatenate(near) - mesh).sum(-1) < 40).mean()
    assert on_mesh < 0.02, on_mesh
