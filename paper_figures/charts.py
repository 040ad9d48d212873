"""Charts (matplotlib) into paper_figures/out/:

  chart_frame_time.png      median frame time against vertex count (log-log)
  chart_solver_traces.png   energy gap against time within a frame, per solver variant
                            (experiments/results/solver_traces.csv)
  chart_solver_budgets.png  frame time against energy gap, per variant and iteration budget
                            (experiments/results/solvers.csv)
  chart_nodes_vs_p.png      optimised nodes (and frame time) against P

Reads experiments/results/*.csv when present (the '#' lines are provenance),
and paper_figures/data/ (generate_data.sh) otherwise or in addition.
"""

import csv
import glob
import json
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.lines  # noqa: E402
import matplotlib.ticker  # noqa: E402
import matplotlib.transforms  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figlib import DATA, OUT, ROOT, shrink_png  # noqa: E402
from framing import place_labels  # noqa: E402

RESULTS = os.path.join(ROOT, "experiments", "results")
# generate_data.sh's preview from `msdeform_experiments --quick`, used when RESULTS lacks a table.
QUICK = os.path.join(DATA, "experiments_quick")


def table_path(name):
    """experiments/results/<name>, else the quick preview, else None; and a label."""
    for folder, label in ((RESULTS, "experiments/results"),
                          (QUICK, "msdeform_experiments --quick preview")):
        path = os.path.join(folder, name)
        if os.path.exists(path):
            return path, label
    return None, None
METHOD_STYLE = {
    "multiscale": dict(color="#d62728", marker="o", label="multi-scale (ours)"),
    # docs/performance.md: the multi-scale method with w_con = 10^4 (--w_con=10000).
    "multiscale-wcon10000": dict(color="#ff7f0e", marker="v", label="multi-scale, w_con 1e4"),
    "static": dict(color="#1f77b4", marker="s", label="static graph, 220 nodes"),
    "static_dense": dict(color="#2ca02c", marker="^", label="static graph = DG1"),
    "cgal_arap": dict(color="#7f7f7f", marker="D", label="CGAL ARAP"),
    "cgal_sr_arap": dict(color="#8c564b", marker="d", label="CGAL SR-ARAP"),
    "fastlsm": dict(color="#17becf", marker="P", label="FastLSM, 20 steps"),
    "rigid_cells": dict(color="#bcbd22", marker="*", label="rigid cells [15]"),
    # The tables' reference: the mesh's ARAP energy minimised to convergence.
    "full_arap": dict(color="#000000", marker="X", label="converged ARAP (reference)"),
    # The graph methods with --energy=arap (table 2's energy column): hollow markers.
    "multiscale-arap": dict(color="#d62728", marker="o", markerfacecolor="none",
                            label="multi-scale, subspace ARAP"),
    "static-arap": dict(color="#1f77b4", marker="s", markerfacecolor="none",
                        label="static graph, subspace ARAP"),
    "static_dense-arap": dict(color="#2ca02c", marker="^", markerfacecolor="none",
                              label="static graph = DG1, subspace ARAP"),
}


def style_key(row):
    """METHOD_STYLE's key of a table-2 row: the method, with -arap for a graph method's
    --energy=arap row."""
    if row.get("energy") == "arap" and row["method"] in ("multiscale", "static", "static_dense"):
        return row["method"] + "-arap"
    return row["method"]


def read_table(path):
    """Rows of a CSV written by experiments/tables.cc, as dicts."""
    with open(path) as f:
        lines = [l for l in f if not l.startswith("#") and l.strip()]
    return list(csv.DictReader(lines))


def num(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return float("nan")


def save(fig, name):
    path = os.path.join(OUT, name)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    shrink_png(path)
    print("wrote", path, os.path.getsize(path) // 1024, "KB")


def markdown_tables(path):
    """Every pipe table of a Markdown file, as a list of row dicts."""
    tables, current, header = [], None, None
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line.startswith("|"):
                if current:
                    tables.append(current)
                current, header = None, None
                continue
            cells = [c.strip() for c in line.strip("|").split("|")]
            if header is None:
                header, current = cells, []
            elif all(set(c) <= set("-: ") for c in cells):
                continue
            else:
                current.append(dict(zip(header, cells)))
    if current:
        tables.append(current)
    return tables


def mesh_size(label):
    """'26K' -> 26002 (the armadillo variants), else a number."""
    sizes = {"26K": 26002, "104K": 104002, "416K": 416002}
    return sizes.get(label, num(label.rstrip("Kk")) * 1000)


def performance_series():
    """{(method, solver): [(vertices, frame ms)]} and CGAL ARAP frames from
    docs/performance.md (bench/performance_table.sh), or None when absent."""
    path = os.path.join(ROOT, "docs", "performance.md")
    if not os.path.exists(path):
        return None
    series, load = {}, ""
    for table in markdown_tables(path):
        for row in table:
            if {"mesh", "method", "solver", "threads", "frame ms"} <= row.keys():
                if row["threads"] != "2":
                    continue
                series.setdefault((row["method"], row["solver"]), []).append(
                    (mesh_size(row["mesh"]), num(row["frame ms"])))
            elif {"mesh", "CGAL ARAP ms per iteration"} <= row.keys():
                series.setdefault(("cgal_arap", "20 iterations"), []).append(
                    (mesh_size(row["mesh"]), 20 * num(row["CGAL ARAP ms per iteration"])))
    with open(path) as f:
        for line in f:
            if "Load average before" in line:
                load = line.split("Load average before:")[1].split(";")[0].strip(" `")
    return (series, load) if series else None


def table2_meshes(rows):
    """[(vertices, mesh, [scenarios])] of table-2 rows, by vertex count: the mesh that
    experiments/scenarios/<scenario>.json names, else the scenario name's first word."""
    groups = {}
    for r in rows:
        path = os.path.join(ROOT, "experiments", "scenarios", r["scenario"] + ".json")
        mesh = r["scenario"].split("_")[0]
        if os.path.exists(path):
            with open(path) as f:
                mesh = os.path.splitext(os.path.basename(json.load(f)["mesh"]))[0]
        these = groups.setdefault((num(r["vertices"]), mesh), [])
        if r["scenario"] not in these:
            these.append(r["scenario"])
    return [(x, mesh, names) for (x, mesh), names in sorted(groups.items())]


def label_columns(ax, groups, tops, fontsize=8, gap_px=4):
    """One horizontal label per column of a log-x scatter ("camel (3)": the mesh and its
    number of scenarios) in a band above the data, joined to its column's highest point by
    a thin leader; rows and sideways shifts from framing.place_labels on the labels'
    rendered widths, so that no label overlaps another or a leader. Call after the
    figure's layout is final."""
    renderer = ax.figure.canvas.get_renderer()
    texts, anchors, widths = [], [], []
    for x, mesh, names in groups:
        t = ax.text(x, 1.0, "%s (%d)" % (mesh, len(names)) if len(names) > 1 else mesh,
                    transform=ax.get_xaxis_transform(), fontsize=fontsize, color="#444444",
                    ha="center", va="bottom")
        box = t.get_window_extent(renderer)
        texts.append(t)
        anchors.append(ax.transData.transform((x, 1.0))[0])
        widths.append(box.width)
    places = place_labels(anchors, widths, gap=gap_px)
    # The band: one text line per row (in axes fraction) over the data, which keeps its
    # log range below it.
    line = 1.4 * fontsize / 72 * ax.figure.dpi / ax.get_window_extent(renderer).height
    band = 0.02 + line * (max(row for row, _ in places) + 1)
    lo, hi = np.log10(ax.get_ylim())
    ax.set_ylim(10 ** lo, 10 ** (lo + (hi - lo) / (1 - band)))
    for t, (x, _, _), (row, offset), top in zip(texts, groups, places, tops):
        y = 1 - band + 0.01 + line * row
        t.set_position((x, y))
        t.set_transform(ax.get_xaxis_transform() + matplotlib.transforms.ScaledTranslation(
            offset / ax.figure.dpi, 0, ax.figure.dpi_scale_trans))
        ax.annotate("", xy=(x, top), xycoords="data", xytext=(x, y),
                    textcoords=ax.get_xaxis_transform(),
                    arrowprops=dict(arrowstyle="-", color="#aaaaaa", lw=0.6, shrinkA=0,
                                    shrinkB=4))


def chart_frame_time():
    own = sorted(glob.glob(os.path.join(DATA, "timing", "*.json")))
    perf = performance_series()
    if perf:
        own = []  # docs/performance.md supersedes our own timing runs
    table2, table2_label = table_path("table2.csv")
    have_table2 = table2 is not None
    ncols = int(bool(own or perf)) + int(have_table2)
    fig, axes = plt.subplots(1, ncols, figsize=(6.5 * ncols, 6.0), squeeze=False)
    col = 0
    notes = []
    if perf:
        ax = axes[0][col]
        col += 1
        series, load = perf
        for (method, solver), pts in sorted(series.items()):
            pts.sort()
            style = dict(METHOD_STYLE.get(method, dict(color="#9467bd", marker="x",
                                                       label=method)))
            if solver == "gauss_newton":
                style.update(linestyle="--", markerfacecolor="white",
                             label=style["label"] + ", Gauss-Newton")
            elif solver == "ceres":
                style.update(label=style["label"] + ", Ceres")
            else:
                style.update(label=style["label"] + ", " + solver)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], **style)
        ax.set_title("Armadillo 26K / 104K / 416K, claw edit, 2 threads\n"
                     "(docs/performance.md; load avg before %s)" % load, fontsize=10)
        ax.set_xticks([26002, 104002, 416002])
        ax.set_xticklabels(["26K", "104K", "416K"])
    if own:
        ax = axes[0][col]
        col += 1
        series = {}
        loads = []
        for path in own:
            load_path = path[:-len(".json")] + ".load"
            if os.path.exists(load_path):
                with open(load_path) as f:
                    loads.append(float(f.read().split()[0]))
            with open(path) as f:
                r = json.load(f)
            series.setdefault(r["method"], []).append(
                (r["vertices"], r["timings_ms"]["frame_median"]))
        for method, pts in series.items():
            pts.sort()
            ax.plot([p[0] for p in pts], [p[1] for p in pts], **METHOD_STYLE[method])
        load = (", load avg %.1f-%.1f" % (min(loads), max(loads))) if loads else ""
        ax.set_title("Armadillo 26K / 104K / 416K (Loop), claw edit,\n"
                     "median of 5 frames, 2 threads on 2 shared cores%s" % load)
        if "cgal_arap" not in series:
            notes.append("CGAL ARAP at these sizes: pending (experiments/)")
            ax.text(0.98, 0.03, "CGAL ARAP at these sizes: pending", transform=ax.transAxes,
                    fontsize=9, color="#555555", ha="right")
    if have_table2:
        ax = axes[0][col]
        rows = read_table(table2)
        for method, style in METHOD_STYLE.items():
            pts = sorted((num(r["vertices"]), num(r["frame_ms"]), r["scenario"])
                         for r in rows if style_key(r) == method)
            pts = [p for p in pts if p[1] == p[1]]
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], linestyle="none", **style)
        ax.set_title("Every scenario of table2.csv, by mesh (number of scenarios)\n(%s)"
                     % table2_label)
        groups = table2_meshes(rows)
        tops = [max((num(r["frame_ms"]) for r in rows
                     if num(r["vertices"]) == x and num(r["frame_ms"]) == num(r["frame_ms"])),
                    default=float("nan")) for x, _, _ in groups]
        xs = [x for x, _, _ in groups]
        ax.set_xlim(min(xs) / 1.6, max(xs) * 1.8)
        table2_ax = ax
    for ax in axes[0]:
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("mesh vertices")
        ax.set_ylabel("median frame time (ms)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
    if have_table2:
        table2_ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(
            lambda x, _: "%gK" % (x / 1000) if x >= 1000 else "%g" % x))
        table2_ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    if own or perf:
        axes[0][0].set_xticks([26002, 104002, 416002])
        axes[0][0].set_xticklabels(["26K", "104K", "416K"])
        axes[0][0].minorticks_off()
    fig.tight_layout()
    if have_table2:
        label_columns(table2_ax, groups, tops)
    save(fig, "chart_frame_time.png")
    return notes


# The solver lab's charts (experiments/solver_lab.h): the 104K claw drag, else the cactus (the
# --quick lab).
SOLVER_SCENARIOS = ("claw_104k", "cactus")
# Gaps at or below this are drawn at it (a converged run reaches the reference to rounding).
GAP_FLOOR = 1e-12
BUDGET_MARKERS = {"1": "o", "2": "s", "3": "^", "5": "D", "10": "v", "converged": "*"}


def solver_scenario(rows):
    """The first of SOLVER_SCENARIOS the rows have, or None."""
    present = {r["scenario"] for r in rows}
    return next((s for s in SOLVER_SCENARIOS if s in present), None)


def variant_styles(variants):
    """Colour and line style per variant, distinct within each backend's panel: Gauss-Newton
    solid (dash-dot after ten), Ceres dashed."""
    cmap = plt.get_cmap("tab10")
    styles = {}
    for _, members in solver_panels(variants):
        for i, v in enumerate(members):
            gn = v.startswith("gn_")
            styles[v] = dict(color=cmap(i % 10),
                             linestyle=("-" if i < 10 else "-.") if gn else "--")
    return styles


def solver_legend(ax):
    ax.legend(fontsize=8, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.13),
              frameon=False)


def log_axis_labels(axis):
    """Plain numbers on a log axis, minor ticks at 2 and 5 labelled too."""
    axis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
    axis.set_minor_locator(matplotlib.ticker.LogLocator(subs=(2.0, 5.0)))
    axis.set_minor_formatter(matplotlib.ticker.FormatStrFormatter("%g"))


def solver_panels(variants):
    """(title, variants) for the Gauss-Newton and the Ceres panel of Eq. 17, and the panel of
    the subspace ARAP energy's solvers (variants arap_*, gaps to that energy's own reference)."""
    panels = [("Gauss-Newton backend, Eq. 17", [v for v in variants if v.startswith("gn_")]),
              ("Ceres backend, Eq. 17",
               [v for v in variants if not v.startswith("gn_") and not v.startswith("arap")])]
    arap = [v for v in variants if v.startswith("arap")]
    if arap:
        panels.append(("Subspace ARAP energy (--energy=arap)", arap))
    return panels


def chart_solver_traces():
    path, label = table_path("solver_traces.csv")
    if path is None:
        print("charts: no solver_traces.csv yet: solver trace chart skipped")
        return None
    rows = read_table(path)
    scenario = solver_scenario(rows)
    if scenario is None:
        print("charts: solver_traces.csv has none of %s: skipped" % (SOLVER_SCENARIOS,))
        return None
    rows = [r for r in rows if r["scenario"] == scenario]
    last = max(int(r["frame"]) for r in rows)
    rows = [r for r in rows if int(r["frame"]) == last]
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    styles = variant_styles(variants)
    panels = solver_panels(variants)
    fig, axes = plt.subplots(1, len(panels), figsize=(6.75 * len(panels), 6.6), sharey=True)
    for ax, (title, members) in zip(axes, panels):
        for v in members:
            pts = [r for r in rows if r["variant"] == v]
            ms = [num(r["ms"]) for r in pts]
            gap = [max(num(r["energy_gap"]), GAP_FLOOR) for r in pts]
            ax.plot(ms, gap, marker=".", markersize=5, linewidth=1.4, label=v, **styles[v])
        ax.set_yscale("log")
        ax.set_xlim(left=0)
        ax.axhline(1e-3, color="#555555", linestyle=":", linewidth=1)
        ax.set_xlabel("time within the frame's solve (ms)")
        ax.set_title(title)
        ax.grid(True, which="major", alpha=0.3)
        solver_legend(ax)
    axes[0].set_ylabel("energy gap (E - E*) / E*  (floor %g)" % GAP_FLOOR)
    axes[0].text(0.02, 1.2e-3, "1e-3", fontsize=8, color="#555555",
                 transform=matplotlib.transforms.blended_transform_factory(axes[0].transAxes,
                                                                          axes[0].transData))
    fig.suptitle("Convergence within the last frame (%d) of %s, budget converged, one point per "
                 "iteration\n(solver_traces.csv, %s)" % (last, scenario, label), fontsize=11)
    fig.tight_layout()
    save(fig, "chart_solver_traces.png")
    return scenario


def chart_solver_budgets():
    path, label = table_path("solvers.csv")
    if path is None:
        print("charts: no solvers.csv yet: solver budget chart skipped")
        return None
    rows = read_table(path)
    if "energy_gap_max" not in rows[0]:
        print("charts: %s is not the solver lab's: skipped" % path)
        return None
    scenario = solver_scenario(rows)
    if scenario is None:
        print("charts: solvers.csv has none of %s: skipped" % (SOLVER_SCENARIOS,))
        return None
    rows = [r for r in rows if r["scenario"] == scenario]
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    styles = variant_styles(variants)
    panels = solver_panels(variants)
    fig, axes = plt.subplots(1, len(panels), figsize=(6.75 * len(panels), 6.8), sharex=True,
                             sharey=True)
    for ax, (title, members) in zip(axes, panels):
        for v in members:
            pts = [r for r in rows if r["variant"] == v]
            gap = [max(num(r["energy_gap_max"]), GAP_FLOOR) for r in pts]
            ms = [num(r["frame_ms"]) for r in pts]
            ax.plot(gap, ms, linewidth=1.0, alpha=0.7, label=v, **styles[v])
            for r, x, y in zip(pts, gap, ms):
                ax.plot([x], [y], marker=BUDGET_MARKERS.get(r["budget"], "x"), markersize=6,
                        color=styles[v]["color"], linestyle="none")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.axvline(1e-3, color="#555555", linestyle=":", linewidth=1)
        ax.set_xlabel("largest energy gap over the frames, (E - E*) / E*  (floor %g)" % GAP_FLOOR)
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.25)
        solver_legend(ax)
        log_axis_labels(ax.yaxis)
    axes[0].set_ylabel("median frame time (ms)")
    # The budget markers, once.
    handles = [matplotlib.lines.Line2D([], [], marker=m, color="#333333", linestyle="none",
                                       label="budget " + b)
               for b, m in BUDGET_MARKERS.items() if any(r["budget"] == b for r in rows)]
    fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 0.93),
               ncol=len(handles), fontsize=8, frameon=False)
    fig.suptitle("Frame time against quality per iteration budget, %s; the dotted line is "
                 "equal quality (gap 1e-3)\n(solvers.csv, %s)" % (scenario, label), fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 0.94))
    save(fig, "chart_solver_budgets.png")
    return scenario


def chart_nodes_vs_p():
    files = sorted(glob.glob(os.path.join(DATA, "nodes_vs_p_*.json")))
    if not files:
        return
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.6))
    for path, color in zip(files, ["#d62728", "#1f77b4", "#2ca02c"]):
        with open(path) as f:
            d = json.load(f)
        rows = d["rows"]
        P = [r["P"] for r in rows]
        ax1.plot(P, [r["optimised_nodes"] for r in rows], marker="o", color=color,
                 label="%s: optimised (TF + HF)" % d["name"])
        ax1.plot(P, [r["scale_nodes"] for r in rows], marker="x", linestyle="--", color=color,
                 alpha=0.6, label="%s: nodes of the selected scale" % d["name"])
        ax2.plot(P, [r["frame_ms_median"] for r in rows], marker="o", color=color,
                 label=d["name"])
        ax1.axhline(rows[0]["dg1_nodes"], color="#999999", linewidth=0.8)
    ax1.text(P[0], rows[0]["dg1_nodes"] * 1.05, "DG1 = %d nodes" % rows[0]["dg1_nodes"],
             fontsize=8, color="#666666")
    for ax in (ax1, ax2):
        ax.set_xscale("log", base=2)
        ax.set_xlabel("P (nodes per scale step)")
        ax.grid(True, which="both", alpha=0.3)
        ax.axvline(100, color="#999999", linestyle=":", linewidth=1)
        ax.set_xticks(P)
        ax.set_xticklabels([str(p) for p in P])
        ax.minorticks_off()
    ax1.set_yscale("log")
    ax1.set_ylabel("nodes")
    ax1.set_title("Optimised nodes against P (paper: P = 100, dotted)")
    ax1.legend(fontsize=8)
    ax2.set_ylabel("median frame time (ms), 5 frames")
    ax2.set_title("Frame time against P (shared 2-core machine: noisy)")
    ax2.legend(fontsize=8)
    fig.tight_layout()
    save(fig, "chart_nodes_vs_p.png")


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    chart_frame_time()
    chart_solver_traces()
    chart_solver_budgets()
    chart_nodes_vs_p()
