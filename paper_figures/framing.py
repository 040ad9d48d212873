"""Where things go in a picture, computed from the data: the direction a camera sees an
edit from (render.py's Fig. 6), and rows for chart labels that would overlap (charts.py).

numpy only, no VTK or matplotlib: tests/paper_figures/ imports it.
"""

import numpy as np


def vertex_normals(V, F):
    """Unit area-weighted vertex normals (#V x 3) of a consistently oriented triangle mesh;
    zero for a vertex without faces."""
    V = np.asarray(V, float)
    F = np.asarray(F, np.int64)
    face = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])  # |face| = 2 area
    N = np.zeros_like(V)
    for c in range(3):
        np.add.at(N, F[:, c], face)
    length = np.linalg.norm(N, axis=1, keepdims=True)
    return N / np.where(length > 0, length, 1.0)


def sphere_directions(n=4000):
    """n unit vectors spread evenly over the sphere (a Fibonacci lattice)."""
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    phi = np.pi * (1.0 + 5 ** 0.5) * i
    r = np.sqrt(1.0 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def view_direction(motion, up, lever=None, facing=None, elevation_deg=(0.0, 30.0),
                   facing_weight=0.25):
    """The unit direction from the subject to the camera that shows a motion best.

    Among directions between elevation_deg[0] and elevation_deg[1] degrees above the horizon
    of `up` (the model stands upright in the picture, seen neither from above nor from
    below), the one that maximises

        (1 - (v . m)^2) + (1 - (v . l)^2) + facing_weight * (v . f)

    with m, l, f the unit motion, lever and facing directions: the motion in the image plane
    (its on-screen length is |motion| sqrt(1 - (v . m)^2)), the lever (from what holds the
    part to the part) too, so that a swing is seen along its axis, and among views that show
    both alike the side `facing` (e.g. the handle's mean normal) points to. A missing or
    zero vector leaves its term constant.
    """
    def unit(x):
        if x is None:
            return np.zeros(3)
        x = np.asarray(x, float)
        n = np.linalg.norm(x)
        return x / n if n > 0 else np.zeros(3)

    up, m, l, f = unit(up), unit(motion), unit(lever), unit(facing)
    v = sphere_directions()
    lo, hi = np.sin(np.radians(elevation_deg[0])), np.sin(np.radians(elevation_deg[1]))
    v = v[(v @ up >= lo - 1e-12) & (v @ up <= hi + 1e-12)]
    score = (1.0 - (v @ m) ** 2) + (1.0 - (v @ l) ** 2) + facing_weight * (v @ f)
    return v[int(np.argmax(score))]


def edit_view(V, Vd, F, moveable, fixed, up, **kwargs):
    """view_direction for an edit: the moveable handle's mean displacement (deformed Vd
    minus rest V) as the motion, the lever from the fixed vertices' centroid to the
    handle's (rest), the handle's mean rest vertex normal as the facing direction."""
    moveable = np.asarray(moveable, dtype=np.int64)
    fixed = np.asarray(fixed, dtype=np.int64)
    V = np.asarray(V, float)
    motion = (np.asarray(Vd, float)[moveable] - V[moveable]).mean(0)
    lever = V[moveable].mean(0) - V[fixed].mean(0) if len(fixed) else None
    facing = vertex_normals(V, F)[moveable].mean(0)
    return view_direction(motion, up, lever=lever, facing=facing, **kwargs)


def model_view(front, up, azimuth_deg=0.0, elevation_deg=10.0):
    """The unit direction from a model to the camera that sees it from `front` (the way its
    face looks, e.g. -z for the armadillo) turned by azimuth_deg about `up` (right-handed:
    +90 turns a z-up model's front -y to +x) and raised elevation_deg above the horizon."""
    up = np.asarray(up, float) / np.linalg.norm(up)
    f = np.asarray(front, float)
    f = f - (f @ up) * up
    f /= np.linalg.norm(f)
    a = np.radians(azimuth_deg)
    h = np.cos(a) * f + np.sin(a) * np.cross(up, f)  # Rodrigues about up, f orthogonal to up
    e = np.radians(elevation_deg)
    return np.cos(e) * h + np.sin(e) * up


# Fig. 6's cameras where the edit's data alone picks a view a user would not (edit_view sees
# the armadillo's arm raise and claw drag from behind, along its back, and the dino's
# sideways tail swing from behind and 30 degrees above): (front, up, azimuth, elevation) for
# model_view. The armadillo from its front, level, where both edits swing across the picture;
# the dino from its left rear, 15 degrees up: in profile, the tail swinging out towards the
# viewer and across.
FIG6_VIEWS = {
    "edit_armadillo_arm_raise_multiscale": ((0, 0, -1), (0, 1, 0), 0.0, 10.0),
    "edit_armadillo_claw_multiscale": ((0, 0, -1), (0, 1, 0), 0.0, 10.0),
    "edit_dino_tail_swing_multiscale": ((0, -1, 0), (0, 0, 1), -135.0, 15.0),
}


def screen_fraction(motion, view):
    """The share of a motion's length that shows across a picture seen from `view`:
    sqrt(1 - (m . v)^2) for unit m and v."""
    m = np.asarray(motion, float) / np.linalg.norm(motion)
    v = np.asarray(view, float) / np.linalg.norm(view)
    return float(np.sqrt(max(0.0, 1.0 - (m @ v) ** 2)))


def place_labels(anchors, widths, gap=0.0):
    """Where labels go in rows above the points they name, each joined to its point by a
    vertical leader: anchors are the points' positions along one axis, widths the labels'
    extents (e.g. display pixels), gap the space kept between a label and a neighbouring
    label or leader. Returns (row, offset) per label: row 0 nearest the points, offset the
    label centre's shift from its anchor (0, or half its width to either side).

    No two labels in a row overlap, and no leader, which runs from its label down through
    the rows below, crosses a label. Among all choices of offsets (up to 8 labels; centred
    beyond), the one needing the fewest rows, then the fewest shifted labels; rows by
    lowest fit from the left.
    """
    import itertools
    n = len(anchors)
    order = sorted(range(n), key=lambda i: anchors[i])

    def rows_for(offsets):
        placed = []  # (row, left, right, anchor)
        rows = [0] * n
        for i in order:
            a, w = anchors[i], widths[i]
            left, right = a + offsets[i] - w / 2, a + offsets[i] + w / 2
            for row in range(n + 1):
                if row == n:
                    return None
                if all((r != row or right + gap <= pl or pr + gap <= left) and
                       (r <= row or not left - gap <= pa <= right + gap) and
                       (r >= row or not pl - gap <= a <= pr + gap)
                       for r, pl, pr, pa in placed):
                    break
            placed.append((row, left, right, a))
            rows[i] = row
        return rows

    best = None
    choices = itertools.product((0, -1, 1), repeat=n) if n <= 8 else [(0,) * n]
    for signs in choices:
        offsets = [sgn * w / 2 for sgn, w in zip(signs, widths)]
        rows = rows_for(offsets)
        if rows is None:
            continue
        key = (max(rows, default=0), sum(1 for sgn in signs if sgn))
        if best is None or key < best[0]:
            best = (key, list(zip(rows, offsets)))
    if best is None:  # only when more than 8 labels crowd together: centred, stacked
        return [(k, 0.0) for k in range(n)]
    return best[1]
