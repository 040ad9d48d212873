"""The energy figure (issue 29): one large edit, experiments' camel_hoof_lift_free_leg,
with the multi-scale method minimising Eq. 17 (--energy=ed), the mesh's ARAP energy in
the selected graph's subspace (--energy=arap), and CGAL's per-vertex ARAP, each coloured
by the local ARAP distortion E_i / N_i on one colour scale.

The data comes from generate_data.sh ("The energy figure"); render.py draws the PNG
(`render.py fig_energy`) and write_index.py takes the caption from `energy_caption()`.
Every number is computed here from the exported meshes (figlib.arap_energy_per_vertex,
experiments/metrics.h in numpy), so the caption matches the picture.
"""

import csv
import json
import os

import numpy as np

from captions import rotation_deg
from figlib import (DATA, OUT, ROOT, arap_energy_per_vertex, camera_for, handles_mesh_actor,
                    lut_viridis, mesh_actor, read_off, render_panels)

KEY = "camel_hoof_lift_free_leg"
PNG = "fig_energy_distortion.png"
TITLE = "One large edit under the ed energy, the subspace ARAP energy and CGAL's ARAP"
# (data file stem, panel label); the first two are msdeform_figure_data exports.
RUNS = (("edit_%s_energy_ed" % KEY, "ours, --energy=ed (Eq. 17)"),
        ("edit_%s_energy_arap" % KEY, "ours, --energy=arap"),
        ("cgal_arap_%s" % KEY, "CGAL ARAP"))
# The camera: from the lifted leg's side (+x), a little from the front (+z), y up.
VIEW, UP, ZOOM = (1, 0.1, 0.35), (0, 1, 0), 0.9
# The shared colour scale ends at this percentile of E_i / N_i over the three results.
PERCENTILE = 99.5


def _read(path):
    with open(path) as f:
        return json.load(f)


def energy_runs():
    """[(label, info json, rest V, F, deformed V, E, N)] of the three results, or None when
    any file is missing. `info` is the exporter's JSON for ours, msdeform's report for CGAL."""
    out = []
    V = F = None
    for stem, label in RUNS:
        cgal = stem.startswith("cgal_")
        info_path = os.path.join(DATA, stem + (".report.json" if cgal else ".json"))
        off = os.path.join(DATA, stem + ".off")
        if not (os.path.exists(info_path) and os.path.exists(off)):
            return None
        info = _read(info_path)
        if V is None:  # the rest mesh the exporter names (data/meshes/<name>.off)
            mesh = os.path.splitext(os.path.basename(info["mesh"]))[0]
            V, F = read_off(os.path.join(ROOT, "data", "meshes", mesh + ".off"))
        Vd, _ = read_off(off)
        E, N = arap_energy_per_vertex(V, F, Vd)
        out.append((label, info, V, F, Vd, E, N))
    return out


def converged_energy():
    """Table 2's converged ARAP energy on this edit (its full_arap row, the tables' reference),
    or None when experiments/results/table2.csv has no such row."""
    path = os.path.join(ROOT, "experiments", "results", "table2.csv")
    if not os.path.exists(path):
        return None
    with open(path, newline="") as f:
        for row in csv.DictReader(line for line in f if not line.startswith("#")):
            if row["scenario"] == KEY and row["method"] == "full_arap" and row["arap_energy"]:
                return float(row["arap_energy"])
    return None


def shared_range(runs):
    """The colour scale's upper end: PERCENTILE of E_i / N_i over the three results, to two
    significant digits."""
    local = np.concatenate([E / np.maximum(N, 1e-300) for _, _, _, _, _, E, N in runs])
    return float("%.2g" % np.percentile(local, PERCENTILE))


def _note(info):
    if info["method"] == "cgal_arap":
        return ("every free vertex: %d variables,\n%s iterations a frame"
                % (info["variables"], info["options"]["cgal.iterations"]))
    cls = np.asarray(info["active"]["class"])
    return ("scale %d of %d: %d Totally Free,\n%d Half Free nodes, %d variables"
            % (info["selected_scale"], info["num_scales"], (cls == 2).sum(), (cls == 1).sum(),
               info["variables"]))


def fig_energy():
    """Rest (handles) and the three results, coloured by E_i / N_i on one scale."""
    runs = energy_runs()
    if runs is None:
        return
    _, d_ed, V, F, _, _, _ = runs[0]
    hi = shared_range(runs)
    lut = lut_viridis()
    lut.SetTableRange(0, hi)
    # The front legs (below the body, front 25% along z), rest and deformed.
    legs = (V[:, 1] < -0.049) & (V[:, 2] > -0.05)
    P = np.vstack([V[legs]] + [r[4][legs] for r in runs])
    # Framed a little high: the numbers go below the hooves.
    c = 0.5 * (P.min(0) + P.max(0)) - 0.1 * np.linalg.norm(P.max(0) - P.min(0)) * np.asarray(UP)
    cam = camera_for(P, VIEW, UP, ZOOM, center=c)
    panels = [dict(actors=[handles_mesh_actor(d_ed, V, F)], camera=cam,
                   label="camel hoof lift: rest", label_size=16,
                   texts=[("blue: fixed body, red: the lifted hoof;\nthe other legs free",
                           (0.02, 0.06), 13)])]
    cgal_energy = runs[2][5].sum() / runs[2][6].sum()
    for label, info, _, _, Vd, E, N in runs:
        local = E / np.maximum(N, 1e-300)
        energy = E.sum() / N.sum()
        panels.append(dict(
            actors=[mesh_actor(Vd, F, scalars=np.minimum(local, hi), lut=lut, rng=(0, hi))],
            camera=cam, label=label, label_size=16,
            bar=(lut, "E_i/N_i") if info is runs[-1][1] else None,  # one scale: one bar
            texts=[("%s\nARAP energy %.3g (%.2fx CGAL's)\nmax E_i/N_i %.2g"
                    % (_note(info), energy, energy / cgal_energy, local.max()),
                    (0.02, 0.16), 13)]))
    render_panels(panels, os.path.join(OUT, PNG), panel_size=(420, 520), columns=4)


def energy_caption():
    runs = energy_runs()
    if runs is None:
        return "The data of this figure is missing; rerun make_figures.sh."
    energies = [E.sum() / N.sum() for _, _, _, _, _, E, N in runs]
    local_max = [float((E / np.maximum(N, 1e-300)).max()) for _, _, _, _, _, E, N in runs]
    diag = runs[0][1]["diag"]
    V_cgal = runs[2][4]
    to_cgal = [float(np.linalg.norm(r[4] - V_cgal, axis=1).mean()) / diag for r in runs[:2]]
    d_arap = runs[1][1]
    converged = converged_energy()
    against_converged = "" if converged is None else (
        " Against the converged ARAP energy of this edit (table 2's full_arap row, the tables' "
        "reference: %.3g): %.2fx (ed), %.2fx (arap) and %.2fx (CGAL's 20 iterations a frame)."
        % (converged, energies[0] / converged, energies[1] / converged,
           energies[2] / converged))
    return (
        "experiments/scenarios/camel_hoof_lift_free_leg.json (its 30 frames, as in table 2): the "
        "camel's body above the legs fixed (blue), the left front hoof (red) swung forward and up "
        "by %g degrees about the knee, every leg free. Left to right: the rest mesh; the "
        "multi-scale method with the defaults minimising Eq. 17 (`--energy=ed`, the paper's "
        "energy); the same method minimising the mesh's cotangent ARAP energy over the selected "
        "scale's free nodes (`--energy=arap`: %s rotation clusters of the skinning weights, "
        "handle and fixed vertices %s; docs/method.md §9); CGAL's per-vertex ARAP (table 2's "
        "cgal_arap). Colour is the local ARAP distortion E_i / N_i (experiments/metrics.h: the "
        "cotangent ARAP energy of vertex i's spokes with its best rotation, over their rest "
        "length sum), one scale for the three results, clipped at %.2g (the %.1fth percentile "
        "over them). Whole-mesh ARAP energy, sum E_i / sum N_i as table 2's arap_energy, "
        "computed from the exported meshes: %.3g (ed), %.3g (arap), %.3g (CGAL), that is %.2fx "
        "and %.2fx CGAL's; largest E_i / N_i %.2g, %.2g and %.2g. Mean distance to CGAL's "
        "result: %.2g (ed) and %.2g (arap) of the diagonal.%s"
        % (rotation_deg(os.path.join(ROOT, "experiments", "scenarios",
                                     "camel_hoof_lift_free_leg.json")),
           d_arap.get("arap_num_clusters", "?"), d_arap.get("arap_constraints", "?"),
           shared_range(runs), PERCENTILE, energies[0], energies[1], energies[2],
           energies[0] / energies[2], energies[1] / energies[2], local_max[0], local_max[1],
           local_max[2], to_cgal[0], to_cgal[1], against_converged))
