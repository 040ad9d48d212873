"""Formats msdeform's reports at several thread counts: docs/performance_threads.md.

    python3 bench/thread_scaling_table.py REPORT_DIR OUT.md

REPORT_DIR holds either the runs of bench/thread_scaling_table.sh,
<mesh stem>_t<threads>_r<repetition>.json with /usr/bin/time -v logs beside
them (<same name>.time: peak memory), or those of the device kit's run.sh
(bench/device_kit.sh), <mesh stem>_t<threads>.json, one run each, and
machine.txt naming the machine they ran on. Optional: load_before.txt and
load_after.txt.

For each mesh a table of every stage at each thread count: the median over the
repetitions, the speedup against 1 thread and the parallel efficiency
(speedup / threads). The stages are those of the reports (timings_ms and
timings_ms.stages), in the order of the 1-thread report; a stage missing at a
thread count is blank. Amdahl's serial fraction of each stage comes from its
1 -> 2 thread speedup S: f = 2 / S - 1, clipped to [0, 1]; with no run at 16
threads or more, each stage is projected to 16 threads, 1 / (f + (1 - f) / 16)
times faster than on 1.
"""
import json
import os
import re
import statistics
import sys

import machine  # noqa: E402  (bench/machine.py, beside this script)

PROJECTED_THREADS = 16
REPEATED = re.compile(r"^(?P<stem>.+)_t(?P<threads>\d+)_r(?P<rep>\d+)\.json$")
SINGLE = re.compile(r"^(?P<stem>.+)_t(?P<threads>\d+)\.json$")
# Where a stage of timings_ms.stages goes: under the row of its prefix.
GROUP_OF_PREFIX = {"load": "load", "precompute": "precompute", "layout": "layout",
                   "session": "layout"}


def peak_mb(path):
    if not os.path.exists(path):
        return None
    with open(path) as f:
        m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", f.read())
    return int(m.group(1)) / 1024.0 if m else None


def read_runs(run_dir):
    """{mesh stem: {threads: [{"report": dict, "peak_mb": float or None}, ...]}}."""
    runs = {}
    for name in sorted(os.listdir(run_dir)):
        m = REPEATED.match(name) or SINGLE.match(name)
        if m is None:
            continue
        with open(os.path.join(run_dir, name)) as f:
            report = json.load(f)
        rep = int(m.groupdict().get("rep") or 1)
        runs.setdefault(m.group("stem"), {}).setdefault(int(m.group("threads")), []).append(
            (rep, {"report": report, "peak_mb": peak_mb(os.path.join(run_dir, name[:-5] + ".time"))}))
    for by_threads in runs.values():
        for threads, reps in by_threads.items():
            by_threads[threads] = [run for _, run in sorted(reps, key=lambda r: r[0])]
    return runs


def rows_of(first_report, other_reports):
    """[(label, value(run) -> ms or None)]: the report's stages, each under its total."""
    def timing(key):
        return lambda run: run["report"]["timings_ms"].get(key)

    def stage(key):
        return lambda run: run["report"]["timings_ms"].get("stages", {}).get(key)

    def layout_change(run):
        t = run["report"]["timings_ms"]
        return t["rigidity"] + t["setup"] if "rigidity" in t and "setup" in t else None

    def first_frame(run):
        t = run["report"]["timings_ms"]
        keys = ("load", "precompute", "rigidity", "setup")
        return sum(t[k] for k in keys) if all(k in t for k in keys) else None

    names = list(first_report["timings_ms"].get("stages", {}))
    for report in other_reports:  # stages only some thread counts have, after the others
        names += [n for n in report["timings_ms"].get("stages", {}) if n not in names]
    groups = {"load": [], "precompute": [], "layout": [], "other": []}
    for name in names:
        groups[GROUP_OF_PREFIX.get(name.split(".")[0], "other")].append(name)
    rows = [("load", timing("load"))]
    rows += [("`%s`" % n, stage(n)) for n in groups["load"]]
    rows.append(("precompute", timing("precompute")))
    rows += [("`%s`" % n, stage(n)) for n in groups["precompute"]]
    rows.append(("layout change (rigidity + setup)", layout_change))
    rows += [("`%s`" % n, stage(n)) for n in groups["layout"] + groups["other"]]
    rows.append(("**start to first frame** (load + precompute + layout change)", first_frame))
    rows += [("**frame** (median)", timing("frame_median")), ("solve (median)", timing("solve_median")),
             ("skin (median)", timing("skin_median"))]
    return rows


def median_of(runs, value):
    values = [v for v in (value(run) for run in runs) if v is not None]
    return statistics.median(values) if values else None


def ms(value):
    if value is None:
        return ""
    return "{:,.0f}".format(value) if value >= 100 else "%.1f" % value if value >= 10 else "%.2f" % value


def serial_fraction(t1, t2):
    if not t1 or not t2:
        return None
    return min(1.0, max(0.0, 2.0 * t2 / t1 - 1.0))


def amdahl_speedup(f, threads):
    return 1.0 / (f + (1.0 - f) / threads)


def vertices_label(vertices):
    return "%.2fM" % (vertices / 1e6) if vertices >= 1e6 else "%dK" % round(vertices / 1e3)


def machine_line(run_dir):
    """The machine.txt of the device kit, else this machine (the runs were made here)."""
    path = os.path.join(run_dir, "machine.txt")
    if not os.path.exists(path):
        return machine.describe()
    fields = {}
    with open(path) as f:
        for line in f:
            key, _, value = line.partition(":")
            fields[key.strip()] = value.strip()
    details = [x for x in ("family %s" % fields["cpu family"] if fields.get("cpu family") else "",
                           "model %s" % fields["model"] if fields.get("model") else "",
                           fields.get("simd", "")) if x]
    return "%s%s, %s logical cores" % (fields.get("cpu", "unknown CPU"),
                                       " (%s)" % ", ".join(details) if details else "",
                                       fields.get("cores", "?"))


def optional_line(run_dir, name):
    path = os.path.join(run_dir, name)
    return open(path).read().strip() if os.path.exists(path) else "not recorded"


def mesh_table(by_threads):
    """The markdown lines of one mesh and its summary values."""
    counts = sorted(by_threads)
    first = by_threads[counts[0]][0]["report"]
    others = [run["report"] for t in counts for run in by_threads[t]]
    rows = rows_of(first, others)
    project = 1 in counts and 2 in counts and counts[-1] < PROJECTED_THREADS
    has_peak = any(run["peak_mb"] is not None for t in counts for run in by_threads[t])
    header = ["stage"] + ["%d thread%s (ms%s)" % (t, "" if t == 1 else "s",
                                                 "" if t == 1 else ", speedup, efficiency")
                          for t in counts]
    if 1 in counts and 2 in counts:
        header.append("serial fraction (1 -> 2)")
    if project:
        header.append("%d threads, projected (ms, speedup)" % PROJECTED_THREADS)
    lines = ["| %s |" % " | ".join(header), "|%s" % ("---|" * len(header))]
    summary = {}
    for label, value in rows:
        medians = {t: median_of(by_threads[t], value) for t in counts}
        base = medians.get(1)
        cells = [label]
        for t in counts:
            cell = ms(medians[t])
            if t != 1 and base and medians[t]:
                speedup = base / medians[t]
                cell += " (%s, %.0f%%)" % (("%.2fx" if speedup < 10 else "%.1fx") % speedup,
                                           100.0 * speedup / t)
            cells.append(cell)
        f = serial_fraction(base, medians.get(2)) if 2 in counts else None
        if 1 in counts and 2 in counts:
            cells.append("" if f is None else "%.2f" % f)
        projected = None
        if project:
            if f is not None:
                speedup = amdahl_speedup(f, PROJECTED_THREADS)
                projected = base / speedup
                cells.append("%s (%.1fx)" % (ms(projected), speedup))
            else:
                cells.append("")
        lines.append("| %s |" % " | ".join(cells))
        summary[label] = (base, projected, medians[counts[-1]])
    if has_peak:
        peaks = {t: median_of(by_threads[t], lambda run: run["peak_mb"]) for t in counts}
        cells = ["peak memory (MB)"] + ["" if peaks[t] is None else "{:,.0f}".format(peaks[t]) for t in counts]
        cells += [""] * (len(header) - len(cells))
        lines.append("| %s |" % " | ".join(cells))
    return lines, summary, project, counts


def main(run_dir, markdown_path):
    runs = read_runs(run_dir)
    if not runs:
        sys.exit("thread_scaling_table.py: no <mesh>_t<threads>[_r<rep>].json reports in %s" % run_dir)
    reports = [run["report"] for by_threads in runs.values() for reps in by_threads.values()
               for run in reps]
    repeated = any(REPEATED.match(name) for name in os.listdir(run_dir))
    repetitions = max(len(reps) for by_threads in runs.values() for reps in by_threads.values())
    commits = sorted({r["msdeform"]["commit"] for r in reports})
    dates = sorted(r["date"] for r in reports)
    source = ("`bash bench/thread_scaling_table.sh`" if repeated else
              "the device kit's `run.sh` (`bash bench/device_kit.sh`)")
    lines = [
        "# Threads",
        "",
        "Generated by %s and bench/thread_scaling_table.py; do not edit." % source,
        "The claw drag of `data/scenarios/armadillo_claw.json` (30 frames, the default solver)",
        "on the armadillo at 104K (OFF text), 1.66M and 6.66M vertices (binary PLY, made by",
        "`msdeform_make_large --huge`) at each thread count (`--threads`). Times from msdeform's",
        "report (its totals and `timings_ms.stages`, each stage under its total; frame, solve and",
        "skin are medians over the 30 frames), %s. Beside each time:"
        % ("one run each" if repetitions == 1 else "the median of %d runs" % repetitions),
        "the speedup against 1 thread and the parallel efficiency (speedup / threads). *Serial",
        "fraction*: Amdahl's f from the 1 -> 2 thread speedup S, f = 2/S - 1, clipped to [0, 1]",
        "(noise can push S past 2 or below 1). "
        + ("Peak memory: the whole process, from `/usr/bin/time -v`." if repeated else
           "Peak memory: not measured by the kit."),
        "",
        "- commit: %s" % ", ".join(commits),
        "- machine: %s" % machine_line(run_dir),
        "- date: %s" % (dates[0] if dates[0] == dates[-1] else "%s to %s" % (dates[0], dates[-1])),
        "- load before: %s" % optional_line(run_dir, "load_before.txt"),
        "- load after: %s" % optional_line(run_dir, "load_after.txt"),
        "",
    ]
    order = sorted(runs, key=lambda stem: next(iter(runs[stem].values()))[0]["report"]["vertices"])
    summaries = []
    for stem in order:
        report = next(iter(runs[stem].values()))[0]["report"]
        label = vertices_label(report["vertices"])
        table, summary, projected, counts = mesh_table(runs[stem])
        lines += ["## %s vertices (`%s`)" % (label, os.path.basename(report["mesh"])), ""]
        lines += table + [""]
        summaries.append((label, summary, projected, counts))

    first_frame = "**start to first frame** (load + precompute + layout change)"
    frame = "**frame** (median)"
    lines += ["## Start to first frame, and a frame, on many cores", ""]
    for label, summary, projected, counts in summaries:
        base_start, projected_start, last_start = summary[first_frame]
        base_frame, projected_frame, last_frame = summary[frame]
        if projected:
            how = ("projected from the 2-core table" if counts[-1] == 2 else
                   "projected from the 1 -> 2 thread speedups")
            lines.append("- %s: start to first frame %s ms on 1 thread, %s ms on %d threads; frame "
                         "%s ms, %s ms on %d threads (%s)" % (
                             label, ms(base_start), ms(projected_start), PROJECTED_THREADS,
                             ms(base_frame), ms(projected_frame), PROJECTED_THREADS, how))
        else:
            lines.append("- %s: start to first frame %s ms on 1 thread, %s ms on %d threads; frame "
                         "%s ms, %s ms on %d threads (measured)" % (
                             label, ms(base_start), ms(last_start), counts[-1], ms(base_frame),
                             ms(last_frame), counts[-1]))
    lines.append("")
    temporary = markdown_path + ".tmp"
    with open(temporary, "w") as f:
        f.write("\n".join(lines))
    os.replace(temporary, markdown_path)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: thread_scaling_table.py REPORT_DIR OUT.md")
    main(*sys.argv[1:])
