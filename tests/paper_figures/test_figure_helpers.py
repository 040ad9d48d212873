"""paper_figures' plain helpers: the captions' numbers (captions.py), the cameras and the
chart labels (framing.py). Known answers; no VTK, matplotlib or figure data needed."""

import pathlib
import sys

import numpy as np
import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "paper_figures"))
from captions import diag_fraction, moves_by  # noqa: E402
from framing import place_labels, view_direction  # noqa: E402


def test_small_displacement_keeps_its_digits():
    # Fig. 6's camel leg: the other front leg moved by 0.000157 of the diagonal, which the
    # index printed as "moves by up to 0.000 of the diagonal".
    assert moves_by(0.0001574860118971278) == "moves by up to 0.00016 of the diagonal"
    assert moves_by(0.00948593929341281) == "moves by up to 0.0095 of the diagonal"
    assert diag_fraction(0.0009) == "0.0009"
    assert diag_fraction(1.3704302642092473e-05) == "1.4e-05"


def test_still_below_the_print_resolution():
    # The free-limb figure's watched leg: exactly 0, rounding (1e-17) and 1.4e-5.
    for x in (0.0, 9.690441361576213e-18, 1.3704302642092473e-05):
        assert moves_by(x) == "stays still (below 1e-4 of the diagonal)"
    assert diag_fraction(0.0) == "0"
    assert diag_fraction(9.690441361576213e-18) == "9.7e-18"


def elevation_deg(v, up):
    return np.degrees(np.arcsin(np.dot(v, up) / np.linalg.norm(v)))


def test_view_sees_a_sideways_swing_from_behind_not_from_above():
    # The dino tail swing: z up, the tail along +y swung along +x. Seen along the swing's
    # axis (z) would be from above; the view stays within 30 degrees of the horizon,
    # behind the tail (its tip faces +y), with the swing across the picture.
    up = np.array([0.0, 0.0, 1.0])
    v = view_direction(motion=(1, 0, 0), up=up, lever=(0, 1, 0), facing=(0, 0.24, -0.3))
    assert 0.0 <= elevation_deg(v, up) <= 30.0 + 1e-9
    assert elevation_deg(v, up) == pytest.approx(30.0, abs=2.0)
    assert abs(v[0]) < 0.08 and v[1] > 0.8  # 4000 sampled directions: ~0.06 apart


def test_view_sees_a_raised_arm_along_the_swing_axis():
    # A swing in the x-y plane (y up) with a lever along y: seen along z, from the side
    # the handle faces (+z here), level.
    up = np.array([0.0, 1.0, 0.0])
    v = view_direction(motion=(0.63, 0.77, 0), up=up, lever=(0.2, 1, 0), facing=(0, 0, 1))
    assert v[2] > 0.95
    assert 0.0 <= elevation_deg(v, up) <= 30.0 + 1e-9


def test_labels_do_not_overlap_labels_or_leaders():
    # The frame-time chart's columns near 10K: cylinder at 8,322 and camel at 9,770
    # vertices, 18 pixels apart, their labels about 40 pixels wide.
    anchors = [0.0, 76.0, 210.0, 296.0, 314.0, 385.0, 430.0]
    widths = [34.0, 45.0, 24.0, 40.0, 50.0, 45.0, 70.0]
    gap = 4.0
    places = place_labels(anchors, widths, gap)
    spans = [(a + dx - w / 2, a + dx + w / 2, row)
             for a, w, (row, dx) in zip(anchors, widths, places)]
    for i, (l1, r1, row1) in enumerate(spans):
        for j, (l2, r2, row2) in enumerate(spans):
            if i == j:
                continue
            if row1 == row2:
                assert r1 + gap <= l2 or r2 + gap <= l1, (i, j)
            if row2 > row1:  # j's leader runs down through row1
                assert not l1 - gap <= anchors[j] <= r1 + gap, (i, j)
        # Each label touches its own leader.
        assert l1 <= anchors[i] <= r1
    assert max(row for row, _ in places) <= 1


def test_rotation_read_from_the_scenario():
    from captions import rotation_deg
    scenarios = pathlib.Path(__file__).resolve().parents[2] / "experiments" / "scenarios"
    assert rotation_deg(scenarios / "camel_hoof_lift_free_leg.json") == 45
    assert rotation_deg(scenarios / "dino_tail_swing.json") is None  # a translation


def test_fig6_dino_seen_from_its_side_not_from_above():
    # The dino tail swing (z up, head towards -y, the tail tip moved by (0.199, -0.0004,
    # 0.00005) of the diagonal in paper_figures/data): the data's own view, edit_view's
    # (-0.05, 0.87, 0.49), looked down the tail from 30 degrees up. Fig. 6 sees the dino
    # in profile from its left rear, low, with most of the swing across the picture.
    from framing import FIG6_VIEWS, model_view, screen_fraction
    up = np.array([0.0, 0.0, 1.0])
    v = model_view(*FIG6_VIEWS["edit_dino_tail_swing_multiscale"])
    assert elevation_deg(v, up) <= 20.0
    assert abs(v[1]) <= np.cos(np.radians(30.0))  # not along the body (end-on)
    assert abs(v[0]) >= 0.5  # from a side
    assert screen_fraction((0.199, -0.00044, 0.00005), v) >= 0.6


def test_fig6_armadillo_seen_from_its_front_across_the_arm_raise():
    # The arm raise's hand moved by (0.094, 0.115, 0.00001) of the diagonal, the claw drag's
    # by (-0.05, 0.1, 0.15); the armadillo faces -z. edit_view's (-0.38, 0.16, 0.91) showed
    # its back, the arm behind the shell.
    from framing import FIG6_VIEWS, model_view, screen_fraction
    up = np.array([0.0, 1.0, 0.0])
    for name in ("edit_armadillo_arm_raise_multiscale", "edit_armadillo_claw_multiscale"):
        v = model_view(*FIG6_VIEWS[name])
        assert v @ np.array([0.0, 0.0, -1.0]) >= np.cos(np.radians(15.0))
        assert 0.0 <= elevation_deg(v, up) <= 15.0
    v = model_view(*FIG6_VIEWS["edit_armadillo_arm_raise_multiscale"])
    assert screen_fraction((0.094, 0.115, 0.00001), v) >= 0.95


def test_model_view_known_answers():
    from framing import model_view
    np.testing.assert_allclose(model_view((0, -1, 0), (0, 0, 1), 90.0, 0.0), (1, 0, 0),
                               atol=1e-12)
    np.testing.assert_allclose(model_view((0, 0, -1), (0, 1, 0), 0.0, 90.0), (0, 1, 0),
                               atol=1e-12)
    s = np.sqrt(0.5)
    np.testing.assert_allclose(model_view((0, 0, -1), (0, 1, 0), 0.0, 45.0), (0, s, -s),
                               atol=1e-12)
