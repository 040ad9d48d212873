"""Writes paper_figures/out/index.md: every figure with its caption, numbers
filled in from paper_figures/data/ so the captions match the pictures."""

import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figlib import DATA, OUT, ROOT  # noqa: E402


def load(name):
    path = os.path.join(DATA, name + ".json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def main():
    g = load("graphs_armadillo") or {}
    foot = load("edit_armadillo_foot_multiscale") or {}
    leg = load("edit_camel_leg_bend_multiscale") or {}
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
    have_solvers = os.path.exists(os.path.join(ROOT, "experiments", "results", "solvers.csv"))
    figures = [
        ("fig2_lattice.png", "Fig. 2 analogue: models in their lattice",
         "The lattice of cell width w = diag / 48 (METHOD.md §1) over the armadillo, the camel "
         "(standing in for the paper's Horse) and the hand. Orange boxes are surface cells (a cell "
         "holding a vertex: one particle and one DG1 node each), blue points interior cells "
         "(enclosed by surface cells). The armadillo and the camel are cut away in front of a "
         "plane through the centre. " + hand_note),
        ("fig3_graphs.png", "Fig. 3 analogue: the armadillo's multi-scale deformation graphs",
         "DG1, a middle scale and the coarsest DG_N of the armadillo (P = 100, N = %s; %s) by "
         "shortest-edge collapse. Nodes are spheres on mesh vertices; two nodes are joined when both are among the k = 4 "
         "nearest nodes of some vertex (core/nearest_nodes.h). Drawn over the translucent mesh." % (g.get("num_scales", "?"), scales)),
        ("fig4_rigidity.png", "Fig. 4 analogue: handles, particle groups and deforming extent",
         "The armadillo with the left foot and the upper body held (blue) and the right foot "
         "dragged (red). (b) The DG1 particles split by T = %s (Eq. 7) into group 1 (e' > T, "
         "orange: the part that will bend) and the rigid group (green). (c) e' of the nearest "
         "DG1 node as a colour map. (d) The result at the selected scale %s of %s, seen like "
         "the other panels from the front right. The DG1 nodes from the foot up to the knee "
         "are Totally Free, yet the lower leg shortens with a fold above the ankle instead of "
         "bending at the knee, while (e), the same edit with every DG1 node free (static_dense), "
         "shortens the leg smoothly: the fold comes from the selected scale and its classes, "
         "an open issue (the foot is lifted by 0.08 and pulled forward by 0.06 of the "
         "diagonal by a pure translation)." % (foot.get("threshold", "?"), foot.get("selected_scale", "?"),
                                        foot.get("num_scales", "?"))),
        ("fig5_ablation.png", "Fig. 5 analogue: bending a leg near a joint, and two ablations",
         "The camel's front-right hoof swung back 70 degrees about the knee, with the body and a "
         "band just above the knee held. (b) ours; (c) keeping the coherence terms E(j, k) that "
         "the method leaves out for Half Free nodes j (keep_left_out_terms); (d) fixing the "
         "fixed-handle nodes completely instead of leaving them Half Free "
         "(fix_fixed_handle_nodes). All three use scale %s. The second row colours (c) and (d) by "
         "their distance from (b): the differences sit at the knee and are small (at most a few "
         "tenths of a percent of the diagonal), much smaller than the artefacts of the paper's "
         "Fig. 5." % leg.get("selected_scale", "?")),
        ("fig6_large_edits.png", "Fig. 6 analogue: large-scale edits, rest and deformed",
         "Armadillo: the left arm swung up about the shoulder, the right claw dragged (the "
         "default edit, data/scenarios/armadillo_claw.json); camel: the neck swung down about its "
         "base, the front leg bent at the knee; when experiments/scenarios/ has them, its man "
         "leg lift and dino tail swing (translations of the foot and the tail tip). Blue: fixed handles, red: the moveable handle. "
         "Each pair shares one camera; the selected scale and the number of optimised variables "
         "are printed under the result."),
        ("fig7_leakage.png", "Fig. 7 analogue: a fine edit of the hand, ours against the "
         "220-node static graph",
         "Colour is displacement over the bounding-box diagonal, on one scale per row. Top: the "
         "thumb tip pulled outwards (paper_figures/scenarios/hand_thumb.json); ours moves the "
         "thumb alone, the static graph (Sumner et al. 2007, 220 nodes, every node free) drags "
         "the whole fist along by about 1%% of the diagonal. Bottom, when experiments/scenarios/hand_finger.json exists: "
         "the middle knuckle pulled out with the neighbouring knuckles watched (yellow); the "
         "numbers under each panel are the mean and max displacement of the watched (or far) "
         "vertices. Ours at scale %s." % thumb_ms.get("selected_scale", "?")),
        ("fig8_small_edits.png", "Fig. 8 analogue: small-scale edits, rest and deformed",
         "An armadillo ear bent outwards about its base with everything below the head held, and "
         "the hand's thumb tip pulled out with the wrist held; zoomed on the edited part, one "
         "camera per pair."),
        ("fig_open_leg_edits.png", "Open issue: leg edits, ours against every DG1 node free",
         "Not a paper figure. The armadillo foot edit of Fig. 4 and the man leg lift of "
         "experiments/scenarios/man_leg_lift.json (a translation of the foot forward and up, "
         "waist band and other foot held): ours (left of each pair of results) leaves the "
         "knee and hip as Fixed nodes, so the thigh does not move, and folds the lower leg: "
         "above the ankle on the armadillo, sharply between mid-shin and the knee on the man "
         "(with the earlier cell-width length unit the man's lower leg was stretched into a "
         "thin spike); the same edit on DG1 with every node free (static_dense, right) swings "
         "the thigh and bends the knee. The rigidity estimate marks too little of the leg as "
         "flexible for these edits (e' > T only near the foot)."),
        ("chart_frame_time.png", "Median frame time against vertex count (log-log)",
         ("Left: the armadillo at 26K, 104K and 416K vertices (Loop subdivision) with the "
          "default claw edit, from docs/performance.md (bench/performance_table.sh: 30 frames, "
          "2 threads, whole-process runs); solid lines the Ceres solver, dashed the "
          "Gauss-Newton backend; CGAL ARAP as 20 times its time per iteration. The machine was "
          "shared (load average in the title). " if have_perf else
          "Left: the armadillo at 26K, 104K and 416K vertices (Loop subdivision, "
          "docs/decisions.md) with the default claw edit, 5 frames, 2 threads, measured by "
          "paper_figures/measure_timing.sh on a shared 2-core machine; CGAL ARAP at these "
          "sizes is pending. ") +
         ("Right: every scenario of experiments/results/table2.csv, CGAL ARAP included."
          if have_results else
          "Right: a preview from `msdeform_experiments --quick` (cactus and hand finger, 5 "
          "frames, 1 thread), CGAL ARAP included; experiments/results/ had no table2.csv yet."
          if have_quick else
          "CGAL ARAP is pending: it is measured by experiments/ (table2.csv), which had not "
          "written its results when this figure was made; rerun make_figures.sh to add it.")),
        ("chart_solvers.png", "Solver variants",
         "Median solve time per frame for each solver variant of " +
         ("experiments/results/solvers.csv" if have_solvers else
          "the `msdeform_experiments --quick` preview (the cactus only, 5 frames; "
          "experiments/results/ had no solvers.csv yet)") +
         ", with the median iterations and the final cost."),
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
