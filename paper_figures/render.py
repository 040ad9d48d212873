"""Renders the mesh figures (Fig. 2-8 analogues) from paper_figures/data/ into out/.

Run under xvfb-run (make_figures.sh). Every figure is one PNG of labelled
panels; compared panels share one camera.
"""

import os
import sys

import numpy as np
import vtk

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from energy_figure import fig_energy  # noqa: E402
from figlib import (DATA, FIXED, MOVEABLE, OUT, ROOT, arap_energy_per_vertex,
                    camera_for, cubes_actor, edit_metrics, group1_stats, handles_mesh_actor,
                    lines_actor, load_json, lut_viridis, mesh_actor, read_off, render_panels,
                    spheres_actor)
from captions import diag_fraction  # noqa: E402
from framing import FIG6_VIEWS, edit_view, model_view  # noqa: E402

MESHES = os.path.join(ROOT, "data", "meshes")
_mesh_cache = {}


def mesh(name):
    if name not in _mesh_cache:
        _mesh_cache[name] = read_off(os.path.join(MESHES, name + ".off"))
    return _mesh_cache[name]


def edit(name):
    """(json, rest V, F, deformed V) of an edit exported by msdeform_figure_data."""
    d = load_json(os.path.join(DATA, name + ".json"))
    mesh_name = os.path.splitext(os.path.basename(d["mesh"]))[0]
    V, F = mesh(mesh_name)
    Vd, _ = read_off(os.path.join(DATA, d["deformed_mesh"]))
    return d, V, F, Vd


HANDLE_LEGEND = [("blue: fixed handles, red: moveable handle", (0.02, 0.06), 13)]


def fig2_lattice():
    panels = []
    views = {"armadillo": ((0.35, 0.25, -1), (0, 1, 0), 1.0),
             "camel": ((1, 0.25, 0.35), (0, 1, 0), 1.0),
             "hand": ((0.3, -0.35, 1), (0, 1, 0), 1.0)}
    for name, (view, up, zoom) in views.items():
        g = load_json(os.path.join(DATA, "graphs_%s.json" % name))
        V, F = mesh(name)
        lat = g["lattice"]
        w = lat["cell_width"]
        S = np.asarray(lat["surface"])
        I = np.asarray(lat["interior"]) if lat["interior"] else np.zeros((0, 3))
        # Cut-away: drop the cells in front of a plane through the centre so the
        # interior cells show; the surface cells behind it are boxes.
        c = 0.5 * (V.min(0) + V.max(0))
        d = np.asarray(view, float)
        d /= np.linalg.norm(d)
        # The hand's edges are longer than a cell (median 1.5 w), so its surface
        # cells leave gaps, the flood fill gets in and no cell is interior:
        # show it whole.
        cut = len(I) > 0
        keep_s = (S - c) @ d < 0.0 if cut else np.ones(len(S), bool)
        actors = [cubes_actor(S[keep_s], 0.92 * w, (0.93, 0.62, 0.28))]
        if len(I):
            keep_i = (I - c) @ d < 0.0
            actors.append(spheres_actor(I[keep_i], 0.3 * w, color=(0.2, 0.35, 0.8), resolution=8))
        actors.append(mesh_actor(V, F, opacity=0.15))
        panels.append(dict(
            actors=actors, camera=camera_for(V, view, up, zoom),
            label="%s: %d surface particles, %d interior" % (name, len(S), len(I)),
            texts=[(("cut away in front of the centre;\n" if cut else
                     "edges ~1.5 w long leave gaps: no cell is enclosed;\n") +
                    "orange boxes: surface cells, blue points: interior cells\n"
                    "cell width w = diag / 48 = %.3g" % w, (0.02, 0.13), 13)]))
    render_panels(panels, os.path.join(OUT, "fig2_lattice.png"), panel_size=(560, 600))


def fig3_graphs():
    g = load_json(os.path.join(DATA, "graphs_armadillo.json"))
    V, F = mesh("armadillo")
    diag = g["diag"]
    cam = camera_for(V, (0.2, 0.1, -1), (0, 1, 0), 1.05)
    panels = []
    for gr in g["graphs"]:
        P = np.asarray(gr["positions"])
        n = gr["num_nodes"]
        r = diag * (0.0035 if n > 1500 else 0.006 if n > 300 else 0.009)
        actors = [mesh_actor(V, F, opacity=0.18),
                  lines_actor(P, gr["edges"], color=(0.35, 0.35, 0.35) if n > 1500 else (0.1, 0.1, 0.1),
                              width=0.8 if n > 1500 else 1.6),
                  spheres_actor(P, r, color=(0.85, 0.2, 0.15), resolution=8)]
        name = "DG1" if gr["scale"] == 1 else ("DG_N (N=%d)" % gr["scale"]
                                               if gr["scale"] == g["num_scales"] else
                                               "DG%d (middle)" % gr["scale"])
        panels.append(dict(actors=actors, camera=cam,
                           label="%s: %d nodes, %d edges" % (name, n, len(gr["edges"]))))
    render_panels(panels, os.path.join(OUT, "fig3_graphs.png"), panel_size=(540, 620))


def knn_interpolate(V, P, values, k=4):
    """Per-vertex value interpolated from the k nearest points of P with
    inverse-distance weights (brute force in chunks; no scipy)."""
    out = np.empty(len(V))
    k = min(k, len(P))
    for s in range(0, len(V), 2000):
        d2 = ((V[s:s + 2000, None, :] - P[None, :, :]) ** 2).sum(-1)
        idx = np.argpartition(d2, k - 1, axis=1)[:, :k]
        dk = np.sqrt(np.take_along_axis(d2, idx, axis=1)) + 1e-12
        w = 1.0 / dk
        out[s:s + 2000] = (w * values[idx]).sum(1) / w.sum(1)
    return out


def lut_threshold(T, steps=512):
    """e' in [0, 1] with a break at T: greens below T (rigid group, pale at 0),
    oranges above (group 1, light at T, dark at 1); below-range colour (fixed
    handles) blue, above-range (the moveable handle) red."""
    lut = vtk.vtkLookupTable()
    lut.SetNumberOfTableValues(steps)
    lut.SetTableRange(0.0, 1.0)
    lut.Build()
    lo0, lo1 = np.array((0.86, 0.90, 0.84)), np.array((0.36, 0.66, 0.36))
    hi0, hi1 = np.array((1.0, 0.86, 0.45)), np.array((0.62, 0.20, 0.02))
    for i in range(steps):
        x = (i + 0.5) / steps
        if x < T:
            c = lo0 + (lo1 - lo0) * (x / T)
        else:
            c = hi0 + (hi1 - hi0) * ((x - T) / (1.0 - T)) ** 0.7
        lut.SetTableValue(i, c[0], c[1], c[2], 1.0)
    lut.SetUseBelowRangeColor(True)
    lut.SetBelowRangeColor(*FIXED, 1.0)
    lut.SetUseAboveRangeColor(True)
    lut.SetAboveRangeColor(*MOVEABLE, 1.0)
    lut.SetAnnotation(T, "T = %.2g" % T)
    return lut


def rigidity_panel(d, V, F, cam, label, part_note):
    """Mesh coloured by e' (nearest DG1 nodes interpolated) with the break at T,
    fixed handles blue, the moveable handle red, group-1 nodes as dark dots."""
    P = np.asarray(d["dg1"]["positions"])
    e = np.minimum(np.asarray(d["dg1"]["e_prime"]), 1.0)
    T = d["threshold"]
    s = knn_interpolate(V, P, e)
    s[np.asarray(d["fixed"], dtype=int)] = -1.0
    s[np.asarray(d["moveable"], dtype=int)] = 2.0
    lut = lut_threshold(T)
    a = mesh_actor(V, F, scalars=s, lut=lut, rng=(0.0, 1.0))
    g1 = P[np.asarray(d["dg1"]["e_prime"]) > T]
    dots = spheres_actor(g1, 0.0045 * d["diag"], color=(0.12, 0.08, 0.25), resolution=8)
    return dict(actors=[a, dots], camera=cam, label=label, label_size=16,
                bar=(lut, "e'"), texts=[(part_note, (0.02, 0.1), 13)])


def fig4_rigidity():
    """Rows: a limb edit and a small edit; columns: the harmonic estimate (the
    default) and the paper's lattice shape matching (--rigidity=paper)."""
    rows = [("man_foot_drag", "man: foot lifted, body fixed", (-1, -0.35, 0.1), (0, 0, 1), 1.1,
             lambda V: V[V[:, 2] < 0.05], 2),
            ("armadillo_ear_band", "armadillo: ear tip pulled, a band fixed", (-0.25, 0.2, -1),
             (0, 1, 0), 1.1, lambda V: V[V[:, 1] > 30], None)]
    panels = []
    for key, title, view, up, zoom, part, axis in rows:
        runs = [("edit_%s_multiscale" % key, "harmonic e' (default)"),
                ("edit_%s_paper_rigidity" % key, "paper's e' (--rigidity=paper)")]
        if not all(os.path.exists(os.path.join(DATA, r + ".json")) for r, _ in runs):
            continue
        cam = None
        for name, what in runs:
            d, V, F, _ = edit(name)
            if cam is None:  # the part framed a little high: the numbers go below it
                Vp = part(V)
                c = 0.5 * (Vp.min(0) + Vp.max(0))
                c -= 0.1 * np.linalg.norm(Vp.max(0) - Vp.min(0)) * np.asarray(up, float)
                cam = camera_for(Vp, view, up, zoom, center=c)
            st = group1_stats(d, V, axis)
            panels.append(rigidity_panel(
                d, V, F, cam, "%s\n%s" % (title, what),
                "group 1 (e' > T = %.2g, dots): %d of %d DG1 nodes\n%s"
                % (d["threshold"], st["group1"], st["dg1"], st["where"])))
    if panels:
        render_panels(panels, os.path.join(OUT, "fig4_rigidity.png"), panel_size=(520, 560),
                      columns=2)


# (e), (f) and (h) act on Half Free nodes, which only an unpinned fixed region has:
# they change (d), not (b).
FIG5_RUNS = [("multiscale", "(b) default"),
             ("paper", "(c) paper mode"),
             ("no_pin", "(d) --pin_fixed_region=false"),
             ("keep_left_out", "(e) (d) + keep_left_out_terms"),
             ("fix_fixed", "(f) (d) + fix_fixed_handle_nodes"),
             ("border_fixed", "(g) --border=fixed"),
             ("half_free_every", "(h) (d) + every fixed-handle node HF")]
# experiments' man_knee_bend: a band around the left thigh just above the knee fixed,
# the foot moved back and up, so the knee bends right at the band. Seen from the left.
FIG5 = dict(key="man_knee_bend", view=(-1, 0.15, 0.0), up=(0, 0, 1), zoom=1.0,
            part=lambda V: (V[:, 0] < 0.0) & (V[:, 2] < 0.0), hi=0.1)
CLASS_COLOURS = ((0.55, 0.55, 0.55), (0.55, 0.2, 0.75), (0.95, 0.55, 0.1))  # F, HF, TF


def class_lut():
    lut = vtk.vtkLookupTable()
    lut.SetNumberOfTableValues(3)
    lut.Build()
    for i, c in enumerate(CLASS_COLOURS):
        lut.SetTableValue(i, c[0], c[1], c[2], 1.0)
    return lut


def fig5_ablation(cfg=None, out="fig5_ablation.png"):
    """A knee bent next to the fixed band: the default, paper mode and the
    ablations, coloured by the local ARAP distortion E_i / N_i; (i) the nodes of
    the unpinned run (d), where the Half Free ablations act, zoomed."""
    cfg = cfg or FIG5
    key = cfg["key"]
    runs = [(tag, label) for tag, label in FIG5_RUNS
            if os.path.exists(os.path.join(DATA, "edit_%s_%s.json" % (key, tag)))]
    if not runs:
        return
    d0, V, F, V0 = edit("edit_%s_%s" % (key, runs[0][0]))
    leg = cfg["part"](V)
    cam = camera_for(np.vstack([V[leg], V0[leg]]), cfg["view"], cfg["up"], cfg["zoom"])
    panels = [dict(actors=[handles_mesh_actor(d0, V, F)], camera=cam, label="(a) rest",
                   texts=HANDLE_LEGEND)]
    lut = lut_viridis()
    hi = cfg["hi"]
    lut.SetTableRange(0, hi)
    for tag, label in runs:
        d, _, _, Vd = edit("edit_%s_%s" % (key, tag))
        m = edit_metrics(d, V, F, Vd, V_ref=V0)
        cls = np.asarray(d["active"]["class"])
        panels.append(dict(
            actors=[mesh_actor(Vd, F, scalars=np.minimum(m["local"], hi), lut=lut, rng=(0, hi))],
            camera=cam, label=label, label_size=15 if len(label) < 30 else 13,
            bar=(lut, "E_i/N_i"),
            texts=[("scale %d: %d TF, %d HF nodes\nARAP %.3g, at the joint %.3g\n"
                    "max E_i/N_i %.2g; %.2g diag from (b)"
                    % (d["selected_scale"], (cls == 2).sum(), (cls == 1).sum(), m["arap"],
                       m["arap_joint"], m["local_max"], m["diff_max"]), (0.02, 0.14), 13)]))
    # (i) Where the ablations act: the unpinned run's nodes at the knee, on the rest mesh.
    unpinned = os.path.join(DATA, "edit_%s_no_pin.json" % key)
    if os.path.exists(unpinned):
        d0 = edit("edit_%s_no_pin" % key)[0]
    fixed = V[np.asarray(d0["fixed"], dtype=int)]
    c = fixed.mean(0)
    near = V[np.linalg.norm(V - c, axis=1) < 0.15 * d0["diag"]]
    kcam = camera_for(near, cfg["view"], cfg["up"], 1.1)
    P = np.asarray(d0["active"]["positions"])
    cls = np.asarray(d0["active"]["class"], dtype=float)
    show = np.linalg.norm(P - c, axis=1) < 0.15 * d0["diag"]
    panels.append(dict(
        actors=[handles_mesh_actor(d0, V, F, opacity=0.35),
                spheres_actor(P[show], 0.006 * d0["diag"], scalars=cls[show], lut=class_lut(),
                              rng=(0, 2), resolution=12)],
        camera=kcam, label="(i) (d)'s nodes at the knee", label_size=15,
        texts=[("scale %d nodes on the rest mesh: orange Totally\nFree, purple Half Free, "
                "grey Fixed; blue band fixed" % d0["selected_scale"], (0.02, 0.1), 13)]))
    render_panels(panels, os.path.join(OUT, out), panel_size=(400, 480), columns=5)


def edits_figure(edits, path, panel_size=(400, 460), ghost=False):
    """Rest and deformed panels per edit (name, title, view, up, zoom[, part]); view None:
    framing.edit_view's direction from the data (the handle's motion, the lever from the
    fixed region and the handle's normals). The camera frames part(V) when given, else the
    rest and deformed meshes. ghost: the rest mesh, faint and translucent, in each deformed
    panel, so that what moved shows against where it was."""
    panels = []
    for name, title, view, up, zoom, *part in edits:
        d, V, F, Vd = edit(name)
        if view is None:
            view = edit_view(V, Vd, F, d["moveable"], d["fixed"], up)
        cam = camera_for(part[0](V) if part else np.vstack([V, Vd]), view, up, zoom)
        panels.append(dict(actors=[handles_mesh_actor(d, V, F)], camera=cam,
                           label="%s: rest" % title, label_size=16))
        actors = [handles_mesh_actor(d, Vd, F)]
        if ghost:
            actors.append(mesh_actor(V, F, color=(0.45, 0.45, 0.45), opacity=GHOST_OPACITY))
        panels.append(dict(actors=actors, camera=cam,
                           label="%s: deformed" % title, label_size=16,
                           texts=[("scale %d of %d, %d variables" % (d["selected_scale"],
                                                                     d["num_scales"],
                                                                     d["variables"]),
                                   (0.02, 0.06), 13)]))
    render_panels(panels, path, panel_size=panel_size, columns=4)


GHOST_OPACITY = 0.18  # Fig. 6's rest pose behind the result: visible, not hiding it


def fig6_view(name, up):
    """Fig. 6's camera direction for an edit: framing.FIG6_VIEWS's where it names one, else
    None (edit_view's, from the data)."""
    if name in FIG6_VIEWS:
        front, model_up, azimuth, elevation = FIG6_VIEWS[name]
        assert tuple(model_up) == tuple(up), name
        return model_view(front, up, azimuth, elevation)
    return None


def fig6_fig8():
    # Fig. 6: the armadillo from its front and the dino from its left rear (framing.FIG6_VIEWS),
    # the others from their data (edit_view); up is each model's axis; the rest pose as a ghost.
    edits = [("edit_armadillo_arm_raise_multiscale", "arm raise", (0, 1, 0), 1.0),
             ("edit_armadillo_claw_multiscale", "claw", (0, 1, 0), 1.0),
             ("edit_camel_neck_multiscale", "camel neck", (0, 1, 0), 1.0),
             ("edit_camel_leg_bend_multiscale", "camel leg", (0, 1, 0), 1.0)]
    # experiments/' edits of other models, when generate_data.sh found them
    if os.path.exists(os.path.join(DATA, "edit_man_leg_lift_multiscale.json")):
        edits.append(("edit_man_leg_lift_multiscale", "man leg", (0, 0, 1), 0.85))
    if os.path.exists(os.path.join(DATA, "edit_dino_tail_swing_multiscale.json")):
        edits.append(("edit_dino_tail_swing_multiscale", "dino tail", (0, 0, 1), 1.0))
    edits_figure([(name, title, fig6_view(name, up), up, zoom)
                  for name, title, up, zoom in edits],
                 os.path.join(OUT, "fig6_large_edits.png"), ghost=True)
    # Small edits: zoomed on the edited part.
    edits_figure([
        ("edit_armadillo_ear_multiscale", "armadillo ear", (-0.15, 0.25, -1), (0, 1, 0), 1.0,
         lambda V: V[(V[:, 1] > 62) & (np.abs(V[:, 0]) < 40)]),
        ("edit_hand_thumb_multiscale", "hand thumb", (-0.6, -0.3, 0.8), (0, 1, 0), 1.0,
         lambda V: V),
    ], os.path.join(OUT, "fig8_small_edits.png"))


def fig7_leakage():
    """One row per fine hand edit: rest, ours (default and paper mode), the 220-node
    static graph, coloured by displacement on one scale per row."""
    rows = [("hand_thumb", "thumb tip pulled out", (0.3, -0.35, 1))]
    if os.path.exists(os.path.join(DATA, "edit_hand_finger_multiscale.json")):
        rows.append(("hand_finger", "middle knuckle pulled out", (0.45, -0.25, 1)))
    panels = []
    for key, title, view in rows:
        d_ms, V, F, _ = edit("edit_%s_multiscale" % key)
        runs = [(n, t) for n, t in (("multiscale", "ours, default"),
                                    ("paper", "ours, paper mode"),
                                    ("static", "static graph"))
                if os.path.exists(os.path.join(DATA, "edit_%s_%s.json" % (key, n)))]
        results = []
        for n, t in runs:
            d, _, _, Vd = edit("edit_%s_%s" % (key, n))
            results.append((d, Vd, t, np.asarray(d["displacement"]) / d["diag"]))
        diag = d_ms["diag"]
        hi = float(np.percentile(np.concatenate([r[3] for r in results]), 99.5))
        lut = lut_viridis()
        lut.SetTableRange(0, hi)
        cam = camera_for(V, view, (0, 1, 0), 0.85)  # room for the colour bar
        watch = np.asarray(d_ms.get("watch", []), dtype=int)
        if len(watch):
            region, what = watch, "watched knuckles"
        else:  # vertices farther than 0.25 diag from the handle centroid
            c = V[np.asarray(d_ms["moveable"])].mean(0)
            region = np.where(np.linalg.norm(V - c, axis=1) > 0.25 * diag)[0]
            what = "far from the thumb"

        def stats(disp):
            return "%s:\nmean %s, max %s of diag" % (what, diag_fraction(disp[region].mean()),
                                                     diag_fraction(disp[region].max()))

        rest_actors = [handles_mesh_actor(d_ms, V, F)]
        if len(watch):
            rest_actors.append(spheres_actor(V[watch], 0.006 * diag, color=(1.0, 0.8, 0.1),
                                             resolution=6))
        panels.append(dict(actors=rest_actors, camera=cam, label="%s: rest" % title,
                           label_size=16,
                           texts=[("blue: fixed, red: moveable" +
                                   (", yellow: watched" if len(watch) else ""),
                                   (0.02, 0.06), 13)]))
        for d, Vd, t, disp in results:
            if d["method"] == "multiscale":
                head = "scale %d of %d, %d variables" % (d["selected_scale"], d["num_scales"],
                                                         d["variables"])
                label = t
            else:
                head = "%d variables" % d["variables"]
                label = "%s, %d nodes" % (t, len(d["active"]["positions"]))
            panels.append(dict(actors=[mesh_actor(Vd, F, scalars=disp, lut=lut, rng=(0, hi))],
                               camera=cam, label=label, label_size=16,
                               bar=(lut, "|d|/diag"),
                               texts=[("%s\n%s" % (head, stats(disp)), (0.02, 0.13), 13)]))
    render_panels(panels, os.path.join(OUT, "fig7_leakage.png"), panel_size=(420, 430),
                  columns=4)


def fig_leg_edits():
    """Leg edits: the default and paper mode against every DG1 node free
    (static_dense). Per edit, a row of shapes (the rest mesh with the default's e'
    and group 1 as in Fig. 4, then the three results) and a row with the results
    coloured by the local ARAP distortion E_i / N_i; one camera per edit."""
    rows = [("armadillo_foot", "armadillo foot", (1, 0.15, -0.6), (0, 1, 0), 1.15,
             lambda V: V[:, 1] < 45, None),
            ("man_leg_lift", "man leg lift", (-1, -0.7, 0.1), (0, 0, 1), 1.1,
             lambda V: V[:, 2] < 0.1, 2)]
    methods = (("multiscale", "default"), ("paper", "paper mode"),
               ("static_dense", "every DG1 node free"))
    hi = 0.1
    lut = lut_viridis()
    lut.SetTableRange(0, hi)
    panels = []
    for key, title, view, up, zoom, part, axis in rows:
        names = ["edit_%s_%s" % (key, m) for m, _ in methods]
        if not all(os.path.exists(os.path.join(DATA, n + ".json")) for n in names):
            continue
        d0, V, F, Vd = edit(names[0])
        # The legs, rest and lifted, framed a little high: the numbers go below them.
        Vp = np.vstack([V[part(V)], Vd[part(V)]])
        c = 0.5 * (Vp.min(0) + Vp.max(0))
        c -= 0.08 * np.linalg.norm(Vp.max(0) - Vp.min(0)) * np.asarray(up, float)
        cam = camera_for(Vp, view, up, zoom, center=c)
        st = group1_stats(d0, V, axis)
        shapes = [rigidity_panel(d0, V, F, cam, "%s: rest, default's e'" % title,
                                 "group 1 (dots): %d of %d DG1 nodes\nblue: fixed, red: moveable"
                                 % (st["group1"], st["dg1"]))]
        distortion = [dict(actors=[], camera=cam, label="%s: distortion" % title, label_size=16,
                           texts=[("right: the results above, coloured by\ntheir local ARAP "
                                   "distortion E_i / N_i\n(experiments/metrics.h), clipped at "
                                   "%.2g" % hi, (0.04, 0.75), 15)])]
        for name, (method, what) in zip(names, methods):
            d, _, _, Vd = edit(name)
            cls = np.asarray(d["active"]["class"])
            E, N = arap_energy_per_vertex(V, F, Vd)
            local = E / np.maximum(N, 1e-300)
            if d["method"] == "multiscale":
                note = ("scale %d of %d: %d TF, %d HF, %d fixed nodes"
                        % (d["selected_scale"], d["num_scales"], (cls == 2).sum(),
                           (cls == 1).sum(), (cls == 0).sum()))
            else:
                note = "static_dense: %d variables" % d["variables"]
            shapes.append(dict(actors=[handles_mesh_actor(d, Vd, F)], camera=cam,
                               label=what, label_size=16, texts=[(note, (0.02, 0.06), 13)]))
            distortion.append(dict(
                actors=[mesh_actor(Vd, F, scalars=np.minimum(local, hi), lut=lut, rng=(0, hi))],
                camera=cam, label="%s: E_i/N_i" % what, label_size=16, bar=(lut, "E_i/N_i"),
                texts=[("ARAP energy %.3g, max E_i/N_i %.2g" % (E.sum() / N.sum(), local.max()),
                        (0.02, 0.06), 13)]))
        panels += shapes + distortion
    if panels:
        render_panels(panels, os.path.join(OUT, "fig_open_leg_edits.png"),
                      panel_size=(340, 380), columns=4)


def fig_free_limb():
    """A hoof lifted beside a free leg that touches it (experiments'
    camel_hoof_lift_free_leg): the rest mesh with the watched leg yellow, then
    ours (default and paper mode) and the 220-node static graph coloured by
    displacement, each with the watched leg's rest pose as a translucent ghost."""
    key = "camel_hoof_lift_free_leg"
    runs = [(n, t) for n, t in (("multiscale", "ours, default"), ("paper", "ours, paper mode"),
                                ("static", "static graph"))
            if os.path.exists(os.path.join(DATA, "edit_%s_%s.json" % (key, n)))]
    if not runs or runs[0][0] != "multiscale":
        return
    d_ms, V, F, _ = edit("edit_%s_multiscale" % key)
    diag = d_ms["diag"]
    watch = np.asarray(d_ms["watch"], dtype=int)
    in_watch = np.zeros(len(V), bool)
    in_watch[watch] = True
    watch_faces = F[in_watch[F].all(1)]
    results = []
    for n, t in runs:
        d, _, _, Vd = edit("edit_%s_%s" % (key, n))
        results.append((d, Vd, t, np.asarray(d["displacement"]) / d["diag"]))
    hi = float(np.percentile(np.concatenate([r[3] for r in results]), 99.5))
    lut = lut_viridis()
    lut.SetTableRange(0, hi)
    # The front legs (below the body, front 25% along z), rest and deformed.
    legs = (V[:, 1] < -0.049) & (V[:, 2] > -0.05)
    cam = camera_for(np.vstack([V[legs]] + [r[1][legs] for r in results]), (0.55, 0.05, 1),
                     (0, 1, 0), 0.8)
    rest_actors = [handles_mesh_actor(d_ms, V, F),
                   spheres_actor(V[watch], 0.004 * diag, color=(1.0, 0.8, 0.1), resolution=6)]
    panels = [dict(actors=rest_actors, camera=cam, label="camel hoof lift: rest", label_size=16,
                   texts=[("blue: fixed, red: moveable,\nyellow: watched (free right leg)",
                           (0.02, 0.06), 13)])]
    for d, Vd, t, disp in results:
        ghost = mesh_actor(V, watch_faces, color=(1.0, 0.8, 0.1), opacity=0.35)
        if d["method"] == "multiscale":
            head = "scale %d of %d, %d variables" % (d["selected_scale"], d["num_scales"],
                                                     d["variables"])
        else:
            head = "%d nodes, %d variables" % (len(d["active"]["positions"]), d["variables"])
        panels.append(dict(
            actors=[mesh_actor(Vd, F, scalars=disp, lut=lut, rng=(0, hi)), ghost], camera=cam,
            label=t, label_size=16, bar=(lut, "|d|/diag"),
            texts=[("%s\nwatched leg: max %s, mean %s of diag\nyellow ghost: its rest pose"
                    % (head, diag_fraction(disp[watch].max()), diag_fraction(disp[watch].mean())),
                    (0.02, 0.13), 13)]))
    render_panels(panels, os.path.join(OUT, "fig_free_limb.png"), panel_size=(420, 480),
                  columns=4)


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    only = sys.argv[1:]
    for f in (fig2_lattice, fig3_graphs, fig4_rigidity, fig5_ablation, fig6_fig8, fig7_leakage,
              fig_leg_edits, fig_free_limb, fig_energy):
        if not only or f.__name__ in only:
            f()
