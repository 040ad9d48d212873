"""Renders the mesh figures (Fig. 2-8 analogues) from paper_figures/data/ into out/.

Run under xvfb-run (make_figures.sh). Every figure is one PNG of labelled
panels; compared panels share one camera.
"""

import os
import sys

import numpy as np
import vtk

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figlib import (DATA, FIXED, GROUP1, GROUP2, MESH_GREY, MOVEABLE, OUT, ROOT, camera_for,
                    cubes_actor, lines_actor, load_json, lut_blue_red, lut_viridis, mesh_actor,
                    read_off, render_panels, spheres_actor)

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


def handle_lut():
    lut = vtk.vtkLookupTable()
    lut.SetNumberOfTableValues(3)
    lut.Build()
    for i, c in enumerate((MESH_GREY, FIXED, MOVEABLE)):
        lut.SetTableValue(i, c[0], c[1], c[2], 1.0)
    return lut


def handle_scalars(d, n):
    s = np.zeros(n)
    s[np.asarray(d["fixed"], dtype=int)] = 1
    s[np.asarray(d["moveable"], dtype=int)] = 2
    return s


def handles_mesh_actor(d, V, F, opacity=1.0):
    """Mesh with fixed handles blue and the moveable handle red."""
    lut = handle_lut()
    a = mesh_actor(V, F, scalars=handle_scalars(d, len(V)), lut=lut, rng=(0, 2), opacity=opacity)
    a.GetMapper().InterpolateScalarsBeforeMappingOff()
    return a


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
            label="%s: %d surface cells, %d interior" % (name, len(S), len(I)),
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


def nearest_node_values(V, P, values):
    """Per-vertex value of the nearest point of P (brute force in chunks)."""
    out = np.empty(len(V))
    for s in range(0, len(V), 2000):
        d2 = ((V[s:s + 2000, None, :] - P[None, :, :]) ** 2).sum(-1)
        out[s:s + 2000] = values[np.argmin(d2, axis=1)]
    return out


def fig4_rigidity():
    d, V, F, Vd = edit("edit_armadillo_foot_multiscale")
    P = np.asarray(d["dg1"]["positions"])
    e = np.asarray(d["dg1"]["e_prime"])
    T = d["threshold"]
    diag = d["diag"]
    view, up = (1, 0.15, -0.6), (0, 1, 0)  # three-quarter view: the lift shows
    cam = camera_for(np.vstack([V, Vd]), view, up, 0.9)
    r = 0.005 * diag
    n1 = int((e > T).sum())
    group = np.where(e > T, 1.0, 0.0)
    glut = vtk.vtkLookupTable()
    glut.SetNumberOfTableValues(2)
    glut.Build()
    glut.SetTableValue(0, *GROUP2, 1.0)
    glut.SetTableValue(1, *GROUP1, 1.0)
    elut = lut_blue_red()
    elut.SetTableRange(0, 1)
    cls = np.asarray(d["active"]["class"])
    counts = [(cls == k).sum() for k in (2, 1, 0)]
    panels = [
        dict(actors=[handles_mesh_actor(d, V, F)], camera=cam,
             label="(a) handles", texts=HANDLE_LEGEND),
        dict(actors=[mesh_actor(V, F, opacity=0.15),
                     spheres_actor(P, r, scalars=group, lut=glut, rng=(0, 1), resolution=8)],
             camera=cam, label="(b) two groups of particles",
             texts=[("orange: e' > T (group 1, %d), green: rigid (%d)\nT = %.3g"
                     % (n1, len(e) - n1, T), (0.02, 0.1), 13)]),
        dict(actors=[mesh_actor(V, F, scalars=nearest_node_values(V, P, np.minimum(e, 1.0)),
                                lut=elut, rng=(0, 1))],
             camera=cam, label="(c) deforming extent e'", bar=(elut, "e'"),
             texts=[("e' of the nearest DG1 node, clipped at 1", (0.02, 0.06), 13)]),
        dict(actors=[handles_mesh_actor(d, Vd, F)], camera=cam,
             label="(d) result, scale %d of %d" % (d["selected_scale"], d["num_scales"]),
             texts=[("%d totally free, %d half free, %d fixed nodes"
                     % tuple(counts), (0.02, 0.06), 13)]),
    ]
    if os.path.exists(os.path.join(DATA, "edit_armadillo_foot_static_dense.json")):
        d_dense, _, _, V_dense = edit("edit_armadillo_foot_static_dense")
        panels.append(dict(actors=[handles_mesh_actor(d_dense, V_dense, F)], camera=cam,
                           label="(e) reference: every DG1 node free",
                           texts=[("static_dense, %d variables" % d_dense["variables"],
                                   (0.02, 0.06), 13)]))
    render_panels(panels, os.path.join(OUT, "fig4_rigidity.png"), panel_size=(370, 500))


def fig5_ablation():
    runs = [("edit_camel_leg_bend_multiscale", "(b) ours"),
            ("edit_camel_leg_bend_keep_left_out", "(c) left-out terms kept"),
            ("edit_camel_leg_bend_fix_fixed", "(d) fixed-handle nodes fixed")]
    d0, V, F, V0 = edit(runs[0][0])
    diag = d0["diag"]
    # Zoom on the front-right leg (rest and bent), seen from the right side.
    leg = (V[:, 0] > 0.0) & (V[:, 2] > -0.1) & (V[:, 1] < 0.05)
    cam = camera_for(np.vstack([V[leg], V0[leg]]), (1, 0.1, 0.15), (0, 1, 0), 1.0)
    panels = [dict(actors=[handles_mesh_actor(d0, V, F)], camera=cam, label="(a) rest",
                   texts=HANDLE_LEGEND)]
    results = []
    for name, label in runs:
        d, V, F, Vd = edit(name)
        results.append((d, Vd, label))
        panels.append(dict(actors=[handles_mesh_actor(d, Vd, F)], camera=cam, label=label,
                           texts=[("scale %d, %d variables" % (d["selected_scale"], d["variables"]),
                                   (0.02, 0.06), 13)]))
    # Second row: how far each ablation lands from ours, per vertex.
    devs = [np.linalg.norm(Vd - V0, axis=1) / diag for _, Vd, _ in results[1:]]
    hi = max(1e-6, max(float(x.max()) for x in devs))
    lut = lut_viridis()
    lut.SetTableRange(0, hi)
    for (d, Vd, label), dev in zip(results[1:], devs):
        panels.append(dict(
            actors=[mesh_actor(Vd, F, scalars=dev, lut=lut, rng=(0, hi))], camera=cam,
            label=label + " vs (b)", label_size=15, bar=(lut, "dist./diag"),
            texts=[("max %.2g, mean %.2g of the diagonal" % (dev.max(), dev.mean()),
                    (0.02, 0.06), 13)]))
    render_panels(panels, os.path.join(OUT, "fig5_ablation.png"), panel_size=(400, 500),
                  columns=4)


def edits_figure(edits, path, panel_size=(400, 460)):
    """Rest and deformed panels per edit (name, title, view, up, zoom[, part]);
    the camera frames part(V) when given, else the rest and deformed meshes."""
    panels = []
    for name, title, view, up, zoom, *part in edits:
        d, V, F, Vd = edit(name)
        cam = camera_for(part[0](V) if part else np.vstack([V, Vd]), view, up, zoom)
        panels.append(dict(actors=[handles_mesh_actor(d, V, F)], camera=cam,
                           label="%s: rest" % title, label_size=16))
        panels.append(dict(actors=[handles_mesh_actor(d, Vd, F)], camera=cam,
                           label="%s: deformed" % title, label_size=16,
                           texts=[("scale %d of %d, %d variables" % (d["selected_scale"],
                                                                     d["num_scales"],
                                                                     d["variables"]),
                                   (0.02, 0.06), 13)]))
    render_panels(panels, path, panel_size=panel_size, columns=4)


def fig6_fig8():
    front = (0.25, 0.1, -1)
    extra = []  # experiments/' edits of other models, when generate_data.sh found them
    if os.path.exists(os.path.join(DATA, "edit_man_leg_lift_multiscale.json")):
        extra.append(("edit_man_leg_lift_multiscale", "man leg", (1, -0.6, 0.1), (0, 0, 1), 0.85))
    if os.path.exists(os.path.join(DATA, "edit_dino_tail_swing_multiscale.json")):
        extra.append(("edit_dino_tail_swing_multiscale", "dino tail", (0.3, -0.2, 1), (0, 1, 0),
                      1.0))
    edits_figure([
        ("edit_armadillo_arm_raise_multiscale", "arm raise", front, (0, 1, 0), 1.0),
        ("edit_armadillo_claw_multiscale", "claw", front, (0, 1, 0), 1.0),
        ("edit_camel_neck_multiscale", "camel neck", (1, 0.1, 0.2), (0, 1, 0), 1.0),
        ("edit_camel_leg_bend_multiscale", "camel leg", (1, 0.1, 0.2), (0, 1, 0), 1.0),
    ] + extra, os.path.join(OUT, "fig6_large_edits.png"))
    # Small edits: zoomed on the edited part.
    edits_figure([
        ("edit_armadillo_ear_multiscale", "armadillo ear", (-0.15, 0.25, -1), (0, 1, 0), 1.0,
         lambda V: V[(V[:, 1] > 62) & (np.abs(V[:, 0]) < 40)]),
        ("edit_hand_thumb_multiscale", "hand thumb", (-0.6, -0.3, 0.8), (0, 1, 0), 1.0,
         lambda V: V),
    ], os.path.join(OUT, "fig8_small_edits.png"))


def fig7_leakage():
    """One row per fine hand edit: rest, ours, the 220-node static graph, coloured
    by displacement on one scale per row."""
    rows = [("hand_thumb", "thumb tip pulled out", (0.3, -0.35, 1))]
    if os.path.exists(os.path.join(DATA, "edit_hand_finger_multiscale.json")):
        rows.append(("hand_finger", "middle knuckle pulled out", (0.45, -0.25, 1)))
    panels = []
    for key, title, view in rows:
        d_ms, V, F, V_ms = edit("edit_%s_multiscale" % key)
        d_st, _, _, V_st = edit("edit_%s_static" % key)
        diag = d_ms["diag"]
        disp_ms = np.asarray(d_ms["displacement"]) / diag
        disp_st = np.asarray(d_st["displacement"]) / diag
        hi = float(np.percentile(np.concatenate([disp_ms, disp_st]), 99.5))
        lut = lut_viridis()
        lut.SetTableRange(0, hi)
        cam = camera_for(V, view, (0, 1, 0), 1.0)
        watch = np.asarray(d_ms.get("watch", []), dtype=int)
        if len(watch):
            region, what = watch, "watched knuckles"
        else:  # vertices farther than 0.25 diag from the handle centroid
            c = V[np.asarray(d_ms["moveable"])].mean(0)
            region = np.where(np.linalg.norm(V - c, axis=1) > 0.25 * diag)[0]
            what = "far from the thumb"

        def stats(disp):
            return "%s: mean %.4f, max %.4f of diag" % (what, disp[region].mean(),
                                                        disp[region].max())

        rest_actors = [handles_mesh_actor(d_ms, V, F)]
        if len(watch):
            rest_actors.append(spheres_actor(V[watch], 0.006 * diag, color=(1.0, 0.8, 0.1),
                                             resolution=6))
        panels.append(dict(actors=rest_actors, camera=cam, label="%s: rest" % title,
                           label_size=16,
                           texts=[("blue: fixed, red: moveable" +
                                   (", yellow: watched" if len(watch) else ""),
                                   (0.02, 0.06), 13)]))
        panels.append(dict(actors=[mesh_actor(V_ms, F, scalars=disp_ms, lut=lut, rng=(0, hi))],
                           camera=cam, label="ours (multi-scale)", label_size=16,
                           bar=(lut, "|d|/diag"),
                           texts=[("scale %d, %d variables\n%s"
                                   % (d_ms["selected_scale"], d_ms["variables"], stats(disp_ms)),
                                   (0.02, 0.1), 13)]))
        panels.append(dict(actors=[mesh_actor(V_st, F, scalars=disp_st, lut=lut, rng=(0, hi))],
                           camera=cam, label="static graph, %d nodes"
                           % len(d_st["active"]["positions"]), label_size=16,
                           bar=(lut, "|d|/diag"),
                           texts=[("%d variables\n%s" % (d_st["variables"], stats(disp_st)),
                                   (0.02, 0.1), 13)]))
    render_panels(panels, os.path.join(OUT, "fig7_leakage.png"), panel_size=(500, 480),
                  columns=3)


def fig_leg_edits():
    """Open issue: leg edits where only the part near the handle is Totally Free,
    against the same edit with every DG1 node free (static_dense)."""
    rows = [("armadillo_foot", "armadillo foot", (1, 0.15, -0.6), (0, 1, 0), 1.0),
            ("man_leg_lift", "man leg", (1, -0.6, 0.1), (0, 0, 1), 0.85)]
    panels = []
    for key, title, view, up, zoom in rows:
        if not os.path.exists(os.path.join(DATA, "edit_%s_static_dense.json" % key)):
            continue
        d, V, F, Vd = edit("edit_%s_multiscale" % key)
        d2, _, _, V2 = edit("edit_%s_static_dense" % key)
        cam = camera_for(np.vstack([V, Vd]), view, up, zoom)
        cls = np.asarray(d["active"]["class"])
        panels.append(dict(actors=[handles_mesh_actor(d, V, F)], camera=cam,
                           label="%s: rest" % title, label_size=16, texts=HANDLE_LEGEND))
        panels.append(dict(actors=[handles_mesh_actor(d, Vd, F)], camera=cam,
                           label="ours, scale %d of %d" % (d["selected_scale"], d["num_scales"]),
                           label_size=16,
                           texts=[("%d totally free, %d half free, %d fixed nodes"
                                   % tuple((cls == k).sum() for k in (2, 1, 0)),
                                   (0.02, 0.06), 13)]))
        panels.append(dict(actors=[handles_mesh_actor(d2, V2, F)], camera=cam,
                           label="every DG1 node free (static_dense)", label_size=16,
                           texts=[("%d variables" % d2["variables"], (0.02, 0.06), 13)]))
    if panels:
        render_panels(panels, os.path.join(OUT, "fig_open_leg_edits.png"),
                      panel_size=(420, 480), columns=3)


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    only = sys.argv[1:]
    for f in (fig2_lattice, fig3_graphs, fig4_rigidity, fig5_ablation, fig6_fig8, fig7_leakage,
              fig_leg_edits):
        if not only or f.__name__ in only:
            f()
