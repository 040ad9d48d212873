"""Writes paper_figures/out/index.md: every figure with its caption, numbers
filled in from paper_figures/data/ so the captions match the pictures."""

import csv
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figlib import DATA, OUT, ROOT, edit_metrics, group1_stats, read_off  # noqa: E402
import energy_figure  # noqa: E402
from captions import diag_fraction, moves_by, rotation_deg, translation_rel  # noqa: E402
import charts  # noqa: E402
from framing import FIG6_VIEWS  # noqa: E402

_meshes = {}


def load(name):
    path = os.path.join(DATA, name + ".json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def load_edit(name):
    """(json, rest V, F, deformed V) of an exported edit, or None."""
    d = load(name)
    if d is None:
        return None
    mesh = os.path.splitext(os.path.basename(d["mesh"]))[0]
    if mesh not in _meshes:
        _meshes[mesh] = read_off(os.path.join(ROOT, "data", "meshes", mesh + ".off"))
    V, F = _meshes[mesh]
    Vd, _ = read_off(os.path.join(DATA, d["deformed_mesh"]))
    return d, V, F, Vd


def pct(x):
    return "%.0f%%" % (100 * x)


def solver_table(name):
    """Rows (dicts) of the solver lab's <name> from experiments/results/, else from the
    --quick preview in data/experiments_quick/; and where they came from. (None, None) if
    neither exists."""
    for folder, label in ((os.path.join(ROOT, "experiments", "results"),
                           "experiments/results/" + name),
                          (os.path.join(DATA, "experiments_quick"),
                           "the `msdeform_experiments --solver_lab --quick` preview (the "
                           "cactus, 5 frames; experiments/results/ had no " + name + " yet)")):
        path = os.path.join(folder, name)
        if os.path.exists(path):
            with open(path) as f:
                lines = [l for l in f if not l.startswith("#") and l.strip()]
            return list(csv.DictReader(lines)), label
    return None, None


def solver_scenario(rows):
    present = {r["scenario"] for r in rows}
    return next((s for s in ("claw_104k", "cactus") if s in present), None)


def solver_traces_caption():
    rows, label = solver_table("solver_traces.csv")
    scenario = solver_scenario(rows) if rows else None
    if scenario is None:
        return "The solver lab's traces are missing; run `msdeform_experiments --solver_lab`."
    last = max(int(r["frame"]) for r in rows if r["scenario"] == scenario)
    return ("The energy gap (E - E*) / E* of each solver variant against the time within the "
            "last frame's solve (frame %d of the %s drag, budget converged: at most 200 "
            "iterations, the default tolerances), one point per iteration; E* is that frame's "
            "minimum from a tightly converged reference run (Gauss-Newton, a factorisation every "
            "iteration, tolerances 1e-14). Gaps below 1e-12 are drawn at 1e-12; the dotted line "
            "is the lab's equal-quality threshold 1e-3. From %s (experiments/solver_lab.h)."
            % (last, scenario, label))


def solver_budgets_caption():
    rows, label = solver_table("solvers.csv")
    scenario = solver_scenario(rows) if rows else None
    if scenario is None or "energy_gap_max" not in rows[0]:
        return "The solver lab's table is missing; run `msdeform_experiments --solver_lab`."
    rows = [r for r in rows if r["scenario"] == scenario]

    def clean(r):
        return r["failed_frames"] == "0" and r["nonfinite_frames"] == "0"

    equal = [r for r in rows if clean(r) and float(r["energy_gap_max"] or "inf") <= 1e-3]
    best = min(equal, key=lambda r: float(r["frame_ms"])) if equal else None
    text = ("Median frame time against the largest energy gap over the drag's frames for each "
            "solver variant on the %s drag, one marker per per-frame iteration budget (1, 2, 3, "
            "5, 10, converged); left of the dotted line (gap 1e-3) a run is of equal quality (the "
            "lab's winner criterion). "
            % scenario)
    if best is not None:
        text += ("The fastest run at equal quality is %s with budget %s: %s ms per frame, "
                 "%s iterations per frame, largest gap %s. " % (
                     best["variant"], best["budget"], best["frame_ms"], best["iterations"],
                     best["energy_gap_max"]))
    return text + "From %s (experiments/solver_lab.h)." % label


def table2_columns():
    """The frame-time chart's columns in words: each mesh with its vertex count and
    scenarios, from experiments/results/table2.csv (charts.table2_meshes)."""
    rows = charts.read_table(os.path.join(ROOT, "experiments", "results", "table2.csv"))
    return "; ".join("%s (%d vertices): %s" % (mesh, x, ", ".join(names))
                     for x, mesh, names in charts.table2_meshes(rows))


def fig4_caption():
    """Numbers of Fig. 4 from its four edits."""
    runs = {k: load_edit(k) for k in (
        "edit_man_foot_drag_multiscale", "edit_man_foot_drag_paper_rigidity",
        "edit_armadillo_ear_band_multiscale", "edit_armadillo_ear_band_paper_rigidity")}
    if any(v is None for v in runs.values()):
        return "The data of this figure is missing; rerun make_figures.sh."
    st = {}
    for k, (d, V, F, _) in runs.items():
        st[k] = group1_stats(d, V, 2 if "man_" in k else None)
        st[k]["T"] = d["threshold"]
    h, p = st["edit_man_foot_drag_multiscale"], st["edit_man_foot_drag_paper_rigidity"]
    eh, ep = st["edit_armadillo_ear_band_multiscale"], st["edit_armadillo_ear_band_paper_rigidity"]
    # The harmonic e' along the free leg: medians over DG1 nodes on free vertices by height.
    d, V, _, _ = runs["edit_man_foot_drag_multiscale"]
    P = np.asarray(d["dg1"]["positions"])
    e = np.asarray(d["dg1"]["e_prime"])
    free = np.ones(len(V), bool)
    free[np.asarray(d["fixed"], dtype=int)] = False
    nearest = np.concatenate([np.argmin(((P[i:i + 100, None, :] - V[None]) ** 2).sum(-1), axis=1)
                              for i in range(0, len(P), 100)])
    on_free = free[nearest]  # DG1 nodes sit on vertices
    hn = (P[:, 2] - V[:, 2].min()) / (V[:, 2].max() - V[:, 2].min())
    bands = [float(np.median(e[on_free & (hn >= lo) & (hn < lo + 0.05)]))
             for lo in (0.20, 0.30, 0.35)]
    # The paper's group 1 on the ear edit: nodes far from the handle, near the watched ear.
    d, V, _, _ = runs["edit_armadillo_ear_band_paper_rigidity"]
    P = np.asarray(d["dg1"]["positions"])
    g1 = P[np.asarray(d["dg1"]["e_prime"]) > d["threshold"]]
    far = np.linalg.norm(g1 - V[np.asarray(d["moveable"])].mean(0), axis=1) > 0.1 * d["diag"]
    watch = V[np.asarray(d["watch"], dtype=int)].mean(0)
    near_watch = int((np.linalg.norm(g1[far] - watch, axis=1) < 0.05 * d["diag"]).sum())
    return (
        "e' (Eq. 7's deforming extent) of the DG1 nodes, interpolated over the rest mesh: green "
        "below T (the rigid group), orange above (group 1, the part that will bend; group-1 "
        "nodes are the dark dots), fixed handles blue, the moveable handle red. Left: the "
        "harmonic estimate (the default, `--rigidity=harmonic`); right: the paper's lattice "
        "shape matching (`--rigidity=paper`); T = %.2g in all four. Top, a limb edit "
        "(experiments/scenarios/man_foot_drag.json: everything but the left leg below the hip "
        "fixed, the foot lifted forward and up): group 1 has %d DG1 nodes and reaches %s of the "
        "body height with the harmonic estimate, through the knee into the thigh, against %d "
        "nodes up to %s (about the knee) with the paper's. The free leg reaches %s of the height, "
        "so the top of the thigh stays below T even with the harmonic estimate: group 1 spans "
        "%s of the free leg's height, not all of it: along the leg the harmonic e' is not linear "
        "(median over the free DG1 nodes %.2f at 20-25%% of the height, %.2f at 30-35%%, %.2f at "
        "35-40%%). Bottom, a small edit (experiments/scenarios/"
        "armadillo_ear.json: only a band under the head fixed, the arms, legs and body free): "
        "group 1 stays on the ear with the harmonic estimate (%d nodes, all within %.2f of the "
        "diagonal of the handle); the paper's has %d nodes, %d of them on the tip of the other, "
        "watched ear (%.2f of the diagonal away), which the kick's wave reaches."
        % (h["T"], h["group1"], pct(h["top"]), p["group1"], pct(p["top"]), pct(h["free_top"]),
           pct(h["top"] / h["free_top"]), *bands, eh["group1"], eh["reach"], ep["group1"],
           near_watch, ep["reach"]))


FIG5_LABELS = [("multiscale", "(b) default"), ("paper", "(c) paper mode"),
               ("no_pin", "(d) fixed region not pinned"),
               ("keep_left_out", "(e) (d) + keep_left_out_terms"),
               ("fix_fixed", "(f) (d) + fix_fixed_handle_nodes"),
               ("border_fixed", "(g) border fixed"),
               ("half_free_every", "(h) (d) + half_free_every_fixed_node")]


def fig5_numbers():
    """{tag: metrics} of Fig. 5's runs (experiments' man_knee_bend), or None."""
    base = load_edit("edit_man_knee_bend_multiscale")
    unpinned = load_edit("edit_man_knee_bend_no_pin")
    if base is None:
        return None
    out = {}
    for tag, _ in FIG5_LABELS:
        e = load_edit("edit_man_knee_bend_%s" % tag)
        if e is None:
            continue
        d, V, F, Vd = e
        m = edit_metrics(d, V, F, Vd, V_ref=base[3])
        if unpinned is not None:  # how far from (d), which the Half Free ablations change
            m["diff_unpinned"] = edit_metrics(d, V, F, Vd, V_ref=unpinned[3])["diff_max"]
        m["scale"] = d["selected_scale"]
        cls = np.asarray(d["active"]["class"])
        m["tf"], m["hf"] = int((cls == 2).sum()), int((cls == 1).sum())
        out[tag] = m
    return out


def fig5_caption():
    n = fig5_numbers()
    if not n:
        return "The data of this figure is missing; rerun make_figures.sh."
    rows = "; ".join("%s %.3g / %.3g (max E_i/N_i %.2g, %.2g diag from (b), fixed vertices "
                     "%.2g)" % (label, n[t]["arap"], n[t]["arap_joint"], n[t]["local_max"],
                                n[t]["diff_max"], n[t]["fixed_max"])
                     for t, label in FIG5_LABELS if t in n)
    b = n["multiscale"]
    text = (
        "experiments/scenarios/man_knee_bend.json (the paper's Fig. 5 set-up): a band around "
        "the left thigh just above the knee fixed (blue), the foot moved back and up (red), so "
        "the knee bends right at the band; 10 frames. (b) the default, (c) paper mode (the "
        "paper's rigidity estimate, every fixed-handle node Half Free, Fixed border nodes, no "
        "Position terms on fixed vertices, the fixed region not pinned, one lattice particle "
        "per cell), (d) the default with the fixed region not pinned (`--pin_fixed_region="
        "false`: the nodes at the band are Half Free, as in the paper), then the paper's "
        "ablations, which act on those Half Free nodes and so change (d): (e) keeping the "
        "coherence terms E(j, k) that the method leaves out for Half Free nodes j (the paper's "
        "Deformed 2), (f) fixing the fixed-handle nodes (Deformed 3), (h) every fixed-handle "
        "node Half Free; and (g) `--border=fixed` on the default. Colour: the local ARAP "
        "distortion E_i / N_i of each vertex (experiments/metrics.h, clipped at 0.1), so "
        "differences at the joint show even where the shapes differ by a few tenths of a "
        "percent of the diagonal. (i) where the Half Free ablations act: (d)'s scale-%d nodes "
        "around the band (Half Free ones purple). ARAP energy of the whole mesh / of the joint "
        "band (vertices within 0.05 diagonals of the fixed band along edges, experiments' "
        "arap_energy_joint): %s. Joint energy: %.2g for the default (scale %d, %d Half Free "
        "nodes), %.2g unpinned (%d Half Free), %.2g in paper mode."
        % (n.get("no_pin", b)["scale"], rows, b["arap_joint"], b["scale"], b["hf"],
           n.get("no_pin", b)["arap_joint"], n.get("no_pin", b)["hf"],
           n["paper"]["arap_joint"]))
    if all(t in n for t in ("keep_left_out", "fix_fixed", "half_free_every")) and \
            "diff_unpinned" in n["keep_left_out"]:
        text += (" On (d), keeping the left-out terms moves the result by at most %.2g of the "
                 "diagonal (joint energy %.2g), fixing the fixed-handle nodes by %.2g (%.2g), "
                 "every fixed-handle node Half Free by %.2g (%.2g)."
                 % (n["keep_left_out"]["diff_unpinned"], n["keep_left_out"]["arap_joint"],
                    n["fix_fixed"]["diff_unpinned"], n["fix_fixed"]["arap_joint"],
                    n["half_free_every"]["diff_unpinned"], n["half_free_every"]["arap_joint"]))
    if "border_fixed" in n:
        text += (" A Fixed border (g): max E_i/N_i %.2g against the default's %.2g, joint "
                 "energy %.2g." % (n["border_fixed"]["local_max"], b["local_max"],
                                   n["border_fixed"]["arap_joint"]))
    return text


def fig6_caption():
    text = ("Armadillo: the left arm swung up about the shoulder, the right claw dragged (the "
            "default edit, data/scenarios/armadillo_claw.json); camel: the neck swung down about "
            "its base, the front leg bent at the knee; when experiments/scenarios/ has them, its "
            "man leg lift and dino tail swing (translations of the foot and the tail tip). Blue: "
            "fixed handles, red: the moveable handle; in each result the rest pose is a faint "
            "grey ghost, so what moved shows against where it was. Each pair shares one camera "
            "(paper_figures/framing.py): the armadillo from its front, %d degrees up, and the "
            "dino from its left rear, %d degrees up (FIG6_VIEWS), the camels and the man from "
            "their edit's data (edit_view: the handle's motion and the lever from the fixed "
            "region to the handle across the picture, from the side the handle's normals face, "
            "at most 30 degrees above the model's horizon); the selected scale and the number of "
            "optimised variables are printed under the result."
            % (FIG6_VIEWS["edit_armadillo_arm_raise_multiscale"][3],
               FIG6_VIEWS["edit_dino_tail_swing_multiscale"][3]))
    arm, claw = load_edit("edit_armadillo_arm_raise_multiscale"), load_edit(
        "edit_armadillo_claw_multiscale")
    if arm and claw:
        def top(e):
            d, V, _, _ = e
            h = (V[:, 1] - V[:, 1].min()) / (V[:, 1].max() - V[:, 1].min())
            return float((np.asarray(d["displacement"])[h > 0.85] / d["diag"]).mean())
        text += (" With only the feet fixed, the harmonic estimate puts nearly the whole "
                 "armadillo in group 1 (%d and %d of %d DG1 nodes) and the default selects scale "
                 "%d and %d: the upper body leans with the arm and the claw (the top 15%% of the "
                 "height, head and ears, moves by %s and %s of the diagonal on average)."
                 % (arm[0]["group1"], claw[0]["group1"], len(arm[0]["dg1"]["e_prime"]),
                    arm[0]["selected_scale"], claw[0]["selected_scale"], diag_fraction(top(arm)),
                    diag_fraction(top(claw))))
    leg, leg_paper = load_edit("edit_camel_leg_bend_multiscale"), load_edit(
        "edit_camel_leg_bend_paper")
    if leg and leg_paper:
        def other(e):
            d, V, _, Vd = e
            sel = (V[:, 0] < 0) & (V[:, 2] > -0.1) & (V[:, 1] < 0.0)
            sel[np.asarray(d["fixed"], dtype=int)] = False
            return float(np.linalg.norm(Vd[sel] - V[sel], axis=1).max()) / d["diag"]
        text += (" The camel leg: the other front leg, free and touching the edited one at the "
                 "knee (lattice cells there hold both knees: the default splits them into one "
                 "particle per knee, paper mode keeps one per cell), %s under the default; in "
                 "paper mode it %s "
                 "(paper_figures/scenarios/camel_leg_bend.json fixes only the body and a band "
                 "above the edited knee)." % (moves_by(other(leg)), moves_by(other(leg_paper))))
    return text


def fig7_caption():
    th = {k: load("edit_hand_thumb_%s" % k) for k in ("multiscale", "paper", "static")}
    fi = {k: load("edit_hand_finger_%s" % k) for k in ("multiscale", "paper", "static")}
    text = ("Colour is displacement over the bounding-box diagonal, on one scale per row; ours "
            "with the defaults and in paper mode, and the static graph of Sumner et al. 2007 "
            "(220 nodes, every node free).")
    if all(th.values()):
        V, _ = _meshes.get("hand") or read_off(os.path.join(ROOT, "data", "meshes", "hand.off"))

        def far(d):
            disp = np.asarray(d["displacement"]) / d["diag"]
            c = V[np.asarray(d["moveable"])].mean(0)
            return disp[np.linalg.norm(V - c, axis=1) > 0.25 * d["diag"]].mean()
        text += (" Top: the thumb tip pulled outwards with only the wrist fixed "
                 "(paper_figures/scenarios/hand_thumb.json). Mean displacement of the vertices "
                 "more than 0.25 diagonals from the handle: %s (default), %s (paper mode), "
                 "%s (static graph). With the wrist the only fixed region, the harmonic "
                 "estimate puts the whole fist between the thumb and the wrist in group 1 (%d of "
                 "%d DG1 nodes, against %d with the paper's), the default selects scale %d of %d "
                 "and moves the far vertices %.1fx as much as paper mode (scale %d) and %.2f "
                 "times as much as the static graph."
                 % (diag_fraction(far(th["multiscale"])), diag_fraction(far(th["paper"])),
                    diag_fraction(far(th["static"])),
                    th["multiscale"]["group1"], len(th["multiscale"]["dg1"]["e_prime"]),
                    th["paper"]["group1"], th["multiscale"]["selected_scale"],
                    th["multiscale"]["num_scales"],
                    far(th["multiscale"]) / far(th["paper"]), th["paper"]["selected_scale"],
                    far(th["multiscale"]) / far(th["static"])))
    if all(fi.values()):
        def watch(d):
            disp = np.asarray(d["displacement"]) / d["diag"]
            return disp[np.asarray(d["watch"], dtype=int)].mean()
        text += (" Bottom (experiments/scenarios/hand_finger.json): the middle knuckle pulled "
                 "out, a band across the palm fixed, the neighbouring knuckles watched (yellow): "
                 "mean watched displacement %s (default, scale %d), %s (paper mode), %s "
                 "(static graph)."
                 % (diag_fraction(watch(fi["multiscale"])), fi["multiscale"]["selected_scale"],
                    diag_fraction(watch(fi["paper"])), diag_fraction(watch(fi["static"]))))
    return text


def leg_numbers():
    """{(edit, method): numbers} of the leg edits figure."""
    out = {}
    for key, axis in (("armadillo_foot", 1), ("man_leg_lift", 2)):
        for m in ("multiscale", "paper", "static_dense"):
            e = load_edit("edit_%s_%s" % (key, m))
            if e is None:
                continue
            d, V, F, Vd = e
            r = edit_metrics(d, V, F, Vd)
            h = (V[:, axis] - V[:, axis].min()) / (V[:, axis].max() - V[:, axis].min())
            free = np.ones(len(V), bool)
            free[np.asarray(d["fixed"], dtype=int)] = False
            moved = free & (np.linalg.norm(Vd - V, axis=1) > 0.01 * d["diag"])
            r["moved_top"] = float(h[moved].max()) if moved.any() else 0.0
            r["group1"] = d.get("group1", 0)
            out[(key, m)] = r
    return out


def leg_caption():
    n = leg_numbers()
    if len(n) < 6:
        return ("The armadillo foot lift of chart_nodes_vs_p and experiments' man leg lift; the "
                "data of the man row is missing (experiments/scenarios/man_leg_lift.json).")
    a = lambda m: n[("armadillo_foot", m)]  # noqa: E731
    b = lambda m: n[("man_leg_lift", m)]  # noqa: E731
    # The feet's translations from the scenario files: armadillo +y up, -z forward; man -y
    # forward, +z up.
    ta = translation_rel(os.path.join(ROOT, "paper_figures", "scenarios", "armadillo_foot.json"))
    tb = translation_rel(os.path.join(ROOT, "experiments", "scenarios", "man_leg_lift.json"))
    return (
        "Not a paper figure. Lifting a foot: paper_figures/scenarios/armadillo_foot.json (the "
        "other foot and the upper body fixed, the foot lifted by %g and pulled forward by %g "
        "of the diagonal) and experiments/scenarios/man_leg_lift.json (a waist band and the other "
        "foot fixed, the foot moved forward by %g and up by %g diagonals). Per edit, the top row "
        "shows the shapes (first the rest mesh with the default's e' and group 1, as in Fig. 4), "
        "the bottom row the same results coloured by the local ARAP distortion E_i / N_i. "
        "Paper mode, whose rigidity estimate makes group 1 only the lower leg (%d and %d DG1 "
        "nodes against the default's %d and %d), moves no free vertex above %s (armadillo) and "
        "%s (man: below the knee) of the height by more than 1%% of the diagonal and folds the "
        "lower leg: a crumpled ring above the ankle on the armadillo, a kink at mid-shin on the "
        "man (ARAP energy %.4f and %.4f, max E_i/N_i %.2g and %.2g). The default moves the leg up "
        "to %s and %s of the height, so the thigh swings forward and the knee and hip bend, close "
        "to the shape of every DG1 node free (static_dense: %s and %s); it distorts less than "
        "paper mode (ARAP %.4f and %.4f) but more than static_dense (%.4f and %.4f), with its "
        "distortion in the hip and thigh (max E_i/N_i %.2g and %.2g against %.2g and %.2g). "
        "On the man none of the three bends at a sharp knee: the default and static_dense both "
        "curve the whole leg like a hose (an embedded deformation knows no joints). The fold of "
        "the earlier figure, the open problem it showed, is paper mode's; the default does not "
        "fold."
        % (ta[1], -ta[2], -tb[1], tb[2],
           a("paper")["group1"], b("paper")["group1"], a("multiscale")["group1"],
           b("multiscale")["group1"], pct(a("paper")["moved_top"]), pct(b("paper")["moved_top"]),
           a("paper")["arap"], b("paper")["arap"], a("paper")["local_max"],
           b("paper")["local_max"], pct(a("multiscale")["moved_top"]),
           pct(b("multiscale")["moved_top"]), pct(a("static_dense")["moved_top"]),
           pct(b("static_dense")["moved_top"]), a("multiscale")["arap"],
           b("multiscale")["arap"], a("static_dense")["arap"], b("static_dense")["arap"],
           a("multiscale")["local_max"], b("multiscale")["local_max"],
           a("static_dense")["local_max"], b("static_dense")["local_max"]))


def free_components(V, F, fixed, seeds):
    """The vertices connected to `seeds` by edges between free (not fixed) vertices: with the
    body fixed, the leg that holds the seeds."""
    free = np.ones(len(V), bool)
    free[np.asarray(fixed, dtype=int)] = False
    E = np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    E = E[free[E[:, 0]] & free[E[:, 1]]]
    adj = [[] for _ in range(len(V))]
    for a, b in E.tolist():
        adj[a].append(b)
        adj[b].append(a)
    seen = np.zeros(len(V), bool)
    stack = [int(v) for v in seeds]
    seen[stack] = True
    while stack:
        for u in adj[stack.pop()]:
            if not seen[u]:
                seen[u] = True
                stack.append(u)
    return np.where(seen)[0]


def surface_distance(V, F, a, b):
    """The shortest path from vertex a to vertex b along the mesh's edges (Dijkstra)."""
    import heapq
    E = np.unique(np.sort(np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1), axis=0)
    length = np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1)
    adj = [[] for _ in range(len(V))]
    for (p, q), l in zip(E.tolist(), length.tolist()):
        adj[p].append((q, l))
        adj[q].append((p, l))
    dist = np.full(len(V), np.inf)
    dist[a] = 0.0
    heap = [(0.0, a)]
    while heap:
        d, v = heapq.heappop(heap)
        if v == b:
            return d
        if d > dist[v]:
            continue
        for u, l in adj[v]:
            if d + l < dist[u]:
                dist[u] = d + l
                heapq.heappush(heap, (d + l, u))
    return float("inf")


def legs_contact(d, V, F):
    """(in space, along the surface) over the diagonal: the closest pair of vertices of the
    leg that holds the moveable handle and the leg that holds the watched vertices."""
    lifted = free_components(V, F, d["fixed"], d["moveable"][:1])
    watched = free_components(V, F, d["fixed"], d["watch"][:1])
    gaps = [np.linalg.norm(V[watched] - V[v], axis=1) for v in lifted]
    i = int(np.argmin([g.min() for g in gaps]))
    j = int(np.argmin(gaps[i]))
    return (float(gaps[i][j]) / d["diag"],
            surface_distance(V, F, int(lifted[i]), int(watched[j])) / d["diag"])


def free_limb_caption():
    runs = [(m, t, load("edit_camel_hoof_lift_free_leg_%s" % m))
            for m, t in (("multiscale", "the default"), ("paper", "paper mode"),
                         ("static", "the 220-node static graph"))]
    runs = [(m, t, d) for m, t, d in runs if d]
    edit = load_edit("edit_camel_hoof_lift_free_leg_multiscale")
    space, surface = legs_contact(*edit[:3]) if edit else (float("nan"), float("nan"))
    text = ("experiments/scenarios/camel_hoof_lift_free_leg.json: the camel's body above the legs "
            "fixed (blue), the left front hoof (red) swung forward and up by %g degrees about the "
            "knee, every leg free. The right front leg (yellow dots at rest; a translucent yellow "
            "ghost of its rest pose in the results) touches the left at the knee, %s "
            "diagonals apart in space and %.2f along the surface (their closest vertices), and "
            "no handle acts on it, so it should stay where it is. Colour is displacement over "
            "the bounding-box diagonal, on one scale." % (rotation_deg(os.path.join(
                ROOT, "experiments", "scenarios", "camel_hoof_lift_free_leg.json")),
                diag_fraction(space), surface))
    table2 = os.path.join(ROOT, "experiments", "results", "table2.csv")
    if os.path.exists(table2):
        with open(table2) as f:
            rows = [r for r in csv.DictReader(l for l in f if not l.startswith("#"))
                    if r["scenario"] == "camel_hoof_lift_free_leg" and r["method"] == "cgal_arap"]
        if rows:
            text += (" CGAL's ARAP moves it by %s of the diagonal at most "
                     "(experiments/results/table2.csv)."
                     % diag_fraction(float(rows[0]["leakage_max_rel"])))
    if runs:
        parts, largest = [], 0.0
        for m, t, d in runs:
            disp = np.asarray(d["displacement"]) / d["diag"]
            w = disp[np.asarray(d["watch"], dtype=int)]
            largest = max(largest, float(w.max()))
            parts.append("%s (%s%s; mean %s)" % (
                diag_fraction(w.max()), t,
                ", scale %d" % d["selected_scale"] if m != "static" else "",
                diag_fraction(w.mean())))
        text += (" The watched leg's largest displacement over the diagonal: " +
                 ", ".join(parts) + "; under %s it %s." % (
                     "all three" if len(runs) == 3 else "each", moves_by(largest)))
    return text


def main():
    g = load("graphs_armadillo") or {}
    thumb_ms = load("edit_hand_thumb_multiscale") or {}
    hand = load("graphs_hand") or {}
    if hand and not hand["lattice"]["interior"]:
        hand_note = ("The hand has no interior cells: its edges are about 1.5 w long, so cells "
                     "crossed by a triangle but holding no vertex leave gaps in the surface "
                     "layer and the flood fill from outside gets in; it is shown whole.")
    else:
        hand_note = ("Cells a triangle crosses without holding a vertex close the surface for "
                     "the flood fill and count as interior particles, so some blue points sit "
                     "in the surface layer, most visibly on the coarse hand (edges about 1.5 w "
                     "long).")
    scales = ", ".join("DG%d: %d nodes" % (x["scale"], x["num_nodes"]) for x in g.get("graphs", []))
    have_results = os.path.exists(os.path.join(ROOT, "experiments", "results", "table2.csv"))
    have_quick = os.path.exists(os.path.join(DATA, "experiments_quick", "table2.csv"))
    have_perf = os.path.exists(os.path.join(ROOT, "docs", "performance.md"))
    figures = [
        ("fig2_lattice.png", "Fig. 2 analogue: models in their lattice",
         "The lattice of cell width w = diag / 48 (docs/method.md §1) over the armadillo, the camel "
         "(standing in for the paper's Horse) and the hand. Orange boxes are surface cells (a cell "
         "holding a vertex: one particle and one DG1 node each), blue points interior cells "
         "(enclosed by surface cells). The armadillo and the camel are cut away in front of a "
         "plane through the centre. " + hand_note),
        ("fig3_graphs.png", "Fig. 3 analogue: the armadillo's multi-scale deformation graphs",
         "DG1, a middle scale and the coarsest DG_N of the armadillo (P = 100, N = %s; %s) by "
         "shortest-edge collapse. Nodes are spheres on mesh vertices; two nodes are joined when both are among the k = 4 "
         "nearest nodes of some vertex (core/nearest_nodes.h). Drawn over the translucent mesh." % (g.get("num_scales", "?"), scales)),
        ("fig4_rigidity.png", "Fig. 4 analogue: deforming extent e' and group 1, the harmonic "
         "estimate against the paper's", fig4_caption()),
        ("fig5_ablation.png", "Fig. 5 analogue: a knee bent next to the fixed band, paper mode "
         "and the ablations", fig5_caption()),
        ("fig6_large_edits.png", "Fig. 6 analogue: large-scale edits, rest and deformed",
         fig6_caption()),
        ("fig7_leakage.png", "Fig. 7 analogue: fine edits of the hand, ours (default and paper "
         "mode) against the 220-node static graph", fig7_caption()),
        ("fig8_small_edits.png", "Fig. 8 analogue: small-scale edits, rest and deformed",
         "An armadillo ear bent outwards about its base with everything below the head held, and "
         "the hand's thumb tip pulled out with the wrist held; zoomed on the edited part, one "
         "camera per pair. The thumb's result is the default's of Fig. 7 (scale %s of %s), which "
         "moves the fist as well." % (thumb_ms.get("selected_scale", "?"),
                                     thumb_ms.get("num_scales", "?"))),
        ("fig_open_leg_edits.png", "Leg edits: the default, paper mode and every DG1 node free",
         leg_caption()),
        ("fig_free_limb.png", "A hoof lifted beside a free leg that touches it: the untouched "
         "leg before and after", free_limb_caption()),
        (energy_figure.PNG, energy_figure.TITLE, energy_figure.energy_caption()),
        ("chart_frame_time.png", "Median frame time against vertex count (log-log)",
         ("Left: the armadillo at 26K, 104K and 416K vertices (Loop subdivision) with the "
          "default claw edit, from docs/performance.md (bench/performance_table.sh: 30 frames, "
          "2 threads, whole-process runs); solid lines the Ceres solver, dashed the "
          "Gauss-Newton backend; orange the multi-scale method with Eq. 17's w_con raised to 10^4; "
          "CGAL ARAP as 20 times its time per iteration. The machine was "
          "shared (load average in the title). " if have_perf else
          "Left: the armadillo at 26K, 104K and 416K vertices (Loop subdivision, "
          "docs/decisions/meshes.md) with the default claw edit, 5 frames, 2 threads, measured by "
          "paper_figures/measure_timing.sh on a shared 2-core machine; CGAL ARAP at these "
          "sizes is pending. ") +
         ("Right: every scenario of experiments/results/table2.csv, CGAL ARAP included; "
          "one column per mesh, labelled with its name and number of scenarios: " +
          table2_columns() + "." if have_results else
          "Right: a preview from `msdeform_experiments --quick` (cactus and hand finger, 5 "
          "frames, 1 thread), CGAL ARAP included; experiments/results/ had no table2.csv yet."
          if have_quick else
          "CGAL ARAP is pending: it is measured by experiments/ (table2.csv), which had not "
          "written its results when this figure was made; rerun make_figures.sh to add it.")),
        ("chart_solver_traces.png", "Solver lab: convergence within a frame",
         solver_traces_caption()),
        ("chart_solver_budgets.png", "Solver lab: frame time against quality per iteration "
         "budget", solver_budgets_caption()),
        ("chart_nodes_vs_p.png", "Optimised nodes against P",
         "For P = 25 .. 1600 nodes per scale step (graphs and Eq. 6 together), the nodes the "
         "method optimises (Totally Free + Half Free) and the nodes of the selected scale, for "
         "the claw edit and the foot edit of the armadillo; right, the median frame time of a "
         "5-frame drag. P = 100 is the paper's value."),
    ]
    lines = ["# Paper figures", "",
             "Made by `bash paper_figures/make_figures.sh` (see paper_figures/README.md). "
             "Our meshes stand in for the paper's Horse and Penguin: the camel, the armadillo "
             "and the hand from Debian's libcgal-demo.", ""]
    missing = []
    for png, title, caption in figures:
        if not os.path.exists(os.path.join(OUT, png)):
            missing.append((png, title))
            continue
        lines += ["## " + title, "", "![%s](%s)" % (title, png), "", caption, ""]
    if missing:
        lines += ["## Not yet made", ""]
        for png, title in missing:
            lines.append("- `%s` (%s): its input in experiments/results/ does not exist yet; "
                         "rerun make_figures.sh after `msdeform_experiments`." % (png, title))
        lines.append("")
    with open(os.path.join(OUT, "index.md"), "w") as f:
        f.write("\n".join(lines))
    print("wrote", os.path.join(OUT, "index.md"))


if __name__ == "__main__":
    main()
