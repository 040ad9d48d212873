"""What a sweep writes: per-task row files, the merged table, the Markdown summary, the chart
and the table projections. Every file is written to a temporary beside it, then renamed.
"""

import csv
import io
import json
import math
import os
import posixpath
import statistics
import tempfile

from msdeform._sweep_grid import OPTION_COLUMN_PREFIX
from msdeform._sweep_task import (FAILED, LOST, METRIC_COLUMNS, OK, PROVENANCE_COLUMNS,
                                  STATUS_COLUMNS, TIMING_COLUMNS)

# Columns that differ between two runs of the same tasks: a sweep's table equals a serial
# run's, row for row, in every other column.
NONDETERMINISTIC_COLUMNS = TIMING_COLUMNS + ("worker",)
# The summary's default metrics (the ablation table's quality columns and sizes).
SUMMARY_METRICS = ("nodes_optimized", "variables", "iterations", "handle_rms_rel",
                   "fixed_max_rel", "arap_energy", "arap_energy_joint", "strain", "leakage_rel",
                   "orthogonality", "frame_ms")


def write_atomically(path, write):
    """Calls write(file) on a temporary file in path's folder, then renames it to path, so a
    reader never sees a partial file. `write` gets a text file (or binary when path ends in
    .png)."""
    folder = os.path.dirname(os.path.abspath(path))
    text = {} if path.endswith(".png") else {"encoding": "utf-8", "newline": ""}
    handle, temporary = tempfile.mkstemp(dir=folder, prefix="." + os.path.basename(path) + ".")
    try:
        with os.fdopen(handle, "w" if text else "wb", **text) as file:
            write(file)
            file.flush()
            os.fsync(file.fileno())
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise


def columns_of(sweep):
    """The result columns of a sweep, in order."""
    parameters = ["index", "task_id", "scenario", "scenario_file", "model", "method", "energy",
                  "variant",
                  "seed", "frames"] + [OPTION_COLUMN_PREFIX + name for name in sweep.option_names]
    return parameters + list(STATUS_COLUMNS) + list(METRIC_COLUMNS) + list(TIMING_COLUMNS) + \
        list(PROVENANCE_COLUMNS)


def cell(value):
    """A value as results.csv writes it: None empty, bools as the flags spell them, floats as
    the shortest text that reads back as the same double."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def task_file(out, task_id):
    """DIR/tasks/<id>.json: one finished task's row."""
    return os.path.join(out, "tasks", task_id + ".json")


def write_task_row(out, task, row):
    """Writes one finished task's file (its id, params and row)."""
    text = json.dumps({"id": task["id"], "params": task["params"], "row": row}, sort_keys=True,
                      allow_nan=False) + "\n"
    write_atomically(task_file(out, task["id"]), lambda file: file.write(text))


def read_task_row(out, task):
    """The row of a task from its file, or None when the file is missing or is not this task's
    (a different id or params); raises ValueError naming the file when it cannot be read."""
    path = task_file(out, task["id"])
    if not os.path.exists(path):
        return None
    try:
        with open(path, encoding="utf-8") as file:
            record = json.load(file)
    except (OSError, json.JSONDecodeError) as error:
        raise ValueError(f"{path}: cannot read a task row ({error})") from None
    if record.get("id") != task["id"] or record.get("params") != task["params"]:
        raise ValueError(f"{path}: holds another task's row (its id or parameters differ)")
    return record["row"]


def csv_text(columns, rows):
    """The CSV text of rows (dicts) under the given columns."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for row in rows:
        writer.writerow([cell(row.get(column)) for column in columns])
    return buffer.getvalue()


def write_results(out, columns, rows):
    """DIR/results.csv: one row per task, in task order."""
    text = csv_text(columns, rows)
    write_atomically(os.path.join(out, "results.csv"), lambda file: file.write(text))


def format_number(value, significant=4):
    """A number as the experiment tables print it (%.4g; None empty; ints as ints)."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return "" if math.isnan(value) else "%.*g" % (significant, value)
    return str(value)


def _pipe_cell(text):
    """A Markdown table cell: no pipes or line breaks."""
    return str(text).replace("|", ";").replace("\n", " ")


def pipe_table(columns, rows):
    """A Markdown pipe table of rows (lists of cell text)."""
    lines = ["| " + " | ".join(_pipe_cell(c) for c in columns) + " |",
             "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(_pipe_cell(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def write_tables(out, sweep, rows, header):
    """The sweep's table projections (e.g. table2): DIR/<name>.csv and .md, the chosen columns
    of the ok rows of the chosen methods and energies, in task order, numbers as the C++ tables print them
    (experiments/tables.h, FormatNumber), with the provenance lines as '#' lines."""
    written = []
    for table in sweep.tables:
        chosen = [row for row in rows if row["status"] == OK
                  and (table["methods"] is None or row["method"] in table["methods"])
                  and (table["energies"] is None or row["energy"] in table["energies"])]
        cells = [[format_number(_table_value(row, column)) for column in table["columns"]]
                 for row in chosen]
        csv_lines = [f"# {line}" for line in header]
        csv_lines.append(",".join(table["columns"]))
        csv_lines += [",".join(c.replace(",", ";") for c in row) for row in cells]
        csv_body = "\n".join(csv_lines) + "\n"
        md_body = f"# {table['name']}\n\n" + "".join(f"- {line}\n" for line in header) + "\n" + \
            pipe_table(table["columns"], cells)
        csv_path = os.path.join(out, table["name"] + ".csv")
        md_path = os.path.join(out, table["name"] + ".md")
        write_atomically(csv_path, lambda file, body=csv_body: file.write(body))
        write_atomically(md_path, lambda file, body=md_body: file.write(body))
        written += [csv_path, md_path]
    return written


def check_outputs(sweep, chart_x=None, chart_y=None):
    """Checks what the sweep asks to write (table columns, summary metrics, chart axes) before
    anything runs; raises ValueError naming the sweep file and the field."""
    columns = set(columns_of(sweep))
    for i, table in enumerate(sweep.tables):
        for j, column in enumerate(table["columns"]):
            if column not in columns:
                raise ValueError(f"{sweep.file}: tables[{i}].columns[{j}]: {column!r} is not a "
                                 f"result column")
    for i, metric in enumerate(sweep.summary_metrics or ()):
        if metric not in METRIC_COLUMNS + TIMING_COLUMNS:
            raise ValueError(f"{sweep.file}: summary_metrics[{i}]: {metric!r} is not a metric "
                             f"column")
    try:
        chart_axes(sweep, chart_x, chart_y)
    except ValueError as error:
        raise ValueError(f"{sweep.file}: {error}") from None


def _table_value(row, column):
    """A row's value for a table column; a column missing from the rows is an error."""
    if column not in row:
        raise ValueError(f"table column {column!r} is not a result column")
    return row[column]


def option_name(column):
    """A column's name as the sweep file spells it: opt_w_con -> w_con; others unchanged."""
    return column[len(OPTION_COLUMN_PREFIX):] if column.startswith(OPTION_COLUMN_PREFIX) else column


def _group_key_columns(sweep):
    """The columns that name a variant in the summary and the chart: scenario, method, variant
    and every option with more than one value (seeds are what is summarised over)."""
    swept = [OPTION_COLUMN_PREFIX + name for name, values in sweep.options.items()
             if len(values) > 1]
    return ["scenario", "method", "variant"] + swept


def _numbers(rows, metric):
    """The metric's finite numbers over rows."""
    values = []
    for row in rows:
        value = row.get(metric)
        if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value):
            values.append(float(value))
    return values


def mean_and_spread(values):
    """'mean ± sd' over the values (sample standard deviation), 'mean' for one, '' for none."""
    if not values:
        return ""
    mean = statistics.fmean(values)
    if len(values) == 1:
        return format_number(mean)
    return f"{format_number(mean)} ± {format_number(statistics.stdev(values), 2)}"


def grouped(rows, key_columns):
    """[(key, rows)] grouping rows by key_columns, groups in order of first appearance."""
    groups = {}
    for row in rows:
        groups.setdefault(tuple(row.get(c) for c in key_columns), []).append(row)
    return list(groups.items())


def summary_markdown(sweep, rows, header):
    """The Markdown summary: per scenario x method x variant x swept option, over the seeds,
    'mean ± sd' of each summary metric; then the failed and lost tasks with their messages."""
    metrics = list(sweep.summary_metrics or SUMMARY_METRICS)
    for metric in metrics:
        if metric not in METRIC_COLUMNS + TIMING_COLUMNS:
            raise ValueError(f"summary_metrics: {metric!r} is not a metric column")
    keys = _group_key_columns(sweep)
    table = []
    for key, group in grouped(rows, keys):
        ok = [row for row in group if row["status"] == OK]
        table.append([format_number(v) for v in key] + [f"{len(ok)}/{len(group)}"] +
                     [mean_and_spread(_numbers(ok, metric)) for metric in metrics])
    names = [option_name(k) for k in keys]
    text = f"# Sweep {posixpath.basename(sweep.file)}\n\n"
    text += "".join(f"- {line}\n" for line in header)
    text += ("\nPer variant, over the seeds: mean ± sample standard deviation of the tasks that "
             "ran (ok/all); times in ms, *_rel over the bounding-box diagonal "
             "(experiments/results/README.md).\n\n")
    text += pipe_table(names + ["ok/tasks"] + metrics, table)
    bad = [row for row in rows if row["status"] in (FAILED, LOST)]
    if bad:
        text += "\n## Failed tasks\n\n"
        named = ("index", "task_id", "scenario", "method", "variant", "seed", "status")
        text += pipe_table(list(named) + ["error"],
                           [[format_number(row.get(c)) for c in named] +
                            [f"{row.get('error_type')}: {row.get('error')}"] for row in bad])
    return text


def write_summary(out, sweep, rows, header):
    """DIR/summary.md."""
    text = summary_markdown(sweep, rows, header)
    path = os.path.join(out, "summary.md")
    write_atomically(path, lambda file: file.write(text))
    return path


def chart_axes(sweep, x=None, y=None):
    """(x column, y column) of the chart: the given ones, else the sweep file's, else the first
    option with more than one value (else the seed) against arap_energy."""
    x = x or sweep.chart["x"]
    y = y or sweep.chart["y"] or "arap_energy"
    if x is None:
        swept = [name for name, values in sweep.options.items() if len(values) > 1]
        x = swept[0] if swept else "seed"
    x_column = x if x in ("seed", "frames") else OPTION_COLUMN_PREFIX + x
    if x_column != x and x not in sweep.option_names:
        raise ValueError(f"chart x: {x!r} is not the seed, frames or an option of this sweep")
    if y not in METRIC_COLUMNS + TIMING_COLUMNS:
        raise ValueError(f"chart y: {y!r} is not a metric column")
    return x_column, y


def _sort_key(value):
    """Numbers before text, each in its order."""
    return (0, float(value), "") if isinstance(value, (int, float)) else (1, 0.0, str(value))


def write_chart(out, sweep, rows, x=None, y=None):
    """DIR/chart.png: y against x, one panel per scenario, one line per variant (method,
    variant and the other swept options), the mean over seeds with the standard deviation as
    error bars. Returns the path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x_column, y_column = chart_axes(sweep, x, y)
    keys = [c for c in _group_key_columns(sweep) if c != x_column]
    ok = [row for row in rows if row["status"] == OK and row.get(x_column) is not None]
    scenarios = list(dict.fromkeys(row["scenario"] for row in ok)) or ["(no ok task)"]
    xs_all = sorted({row[x_column] for row in ok}, key=_sort_key)
    numeric = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in xs_all)
    log_x = numeric and xs_all and min(xs_all) > 0 and max(xs_all) / min(xs_all) >= 10
    columns = min(3, len(scenarios))
    lines_of = (len(scenarios) + columns - 1) // columns
    figure, axes = plt.subplots(lines_of, columns, figsize=(5.2 * columns, 3.8 * lines_of),
                                squeeze=False)
    for panel, scenario in zip(axes.flat, scenarios):
        for key, group in grouped([r for r in ok if r["scenario"] == scenario], keys):
            points = []
            for value, at in grouped(group, [x_column]):
                numbers = _numbers(at, y_column)
                if numbers:
                    spread = statistics.stdev(numbers) if len(numbers) > 1 else 0.0
                    points.append((value[0], statistics.fmean(numbers), spread))
            points.sort(key=lambda p: _sort_key(p[0]))
            if not points:
                continue
            where = [p[0] if numeric else xs_all.index(p[0]) for p in points]
            label = " / ".join(format_number(k) for k in key[1:] if k is not None) or key[0]
            panel.errorbar(where, [p[1] for p in points], yerr=[p[2] for p in points],
                           marker="o", capsize=3, label=label)
        panel.set_title(scenario)
        panel.set_xlabel(option_name(x_column))
        panel.set_ylabel(y_column)
        if log_x:
            panel.set_xscale("log")
        if not numeric:
            panel.set_xticks(range(len(xs_all)), [format_number(v) for v in xs_all])
        panel.grid(True, alpha=0.3)
        if panel.get_legend_handles_labels()[0]:
            panel.legend(fontsize=7)
    for panel in list(axes.flat)[len(scenarios):]:
        panel.set_visible(False)
    figure.suptitle(f"{posixpath.basename(sweep.file)}: {y_column} (mean ± sd over seeds)")
    figure.tight_layout()
    path = os.path.join(out, "chart.png")
    write_atomically(path, lambda file: figure.savefig(file, format="png", dpi=100))
    plt.close(figure)
    return path
