"""Numbers in the figures' captions and panel texts (write_index.py, render.py).

Lengths are printed over the bounding-box diagonal with significant digits, not a fixed
number of decimals, so a small displacement is not rounded to "0.000". Below STILL_BELOW a
displacement is said to stay still, with the bound: it is far below a pixel in every
figure (a panel's diagonal spans a few hundred pixels) and above the exported meshes'
rounding (6 significant digits: about 1e-6 of the diagonal).

Plain Python, no VTK or matplotlib: tests/paper_figures/ imports it.
"""

import json

# Displacements over the diagonal below this are "still" in running text.
STILL_BELOW = 1e-4


def _short_exponent(x):
    """1e-4 for 0.0001 (Python's %e writes 1e-04)."""
    mantissa, exponent = ("%.0e" % x).split("e")
    return "%se%d" % (mantissa, int(exponent))


def diag_fraction(x, digits=2):
    """x (a length over the diagonal) with `digits` significant digits: 0.0091, 0.00016,
    1.4e-05, and 0 only when x is exactly 0."""
    if x == 0:
        return "0"
    return "%.*g" % (digits, x)


def moves_by(x, qualifier="up to"):
    """A clause for the largest (or, with another qualifier, mean) displacement x over the
    diagonal: "moves by up to 0.00016 of the diagonal", or "stays still (below 1e-4 of the
    diagonal)" when x < STILL_BELOW."""
    if x < STILL_BELOW:
        return "stays still (below %s of the diagonal)" % _short_exponent(STILL_BELOW)
    return "moves by %s%s of the diagonal" % (qualifier + " " if qualifier else "",
                                              diag_fraction(x))


def rotation_deg(scenario_path):
    """The angle (degrees, unsigned) of a scenario file's rotation transform (core/scenario.h),
    e.g. 45 for experiments/scenarios/camel_hoof_lift_free_leg.json; None without one."""
    with open(scenario_path) as f:
        rotation = json.load(f).get("transform", {}).get("rotation")
    return abs(rotation["angle_deg"]) if rotation else None


def translation_rel(scenario_path):
    """A scenario file's translation over the diagonal (translation_rel, 3 numbers), or
    None without one."""
    with open(scenario_path) as f:
        return json.load(f).get("transform", {}).get("translation_rel")
