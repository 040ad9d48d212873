#!/usr/bin/env python3
"""Counts the non-time cells that differ between two runs of a result table.

    python3 scripts/compare_tables.py experiments/results/table2.csv new/table2.csv

Rows are matched on their key columns (every column before the first numeric
one that is not a time); time columns (names ending in `_ms`, or
`ms_per_iteration`, `wall_s`, and the traces' `ms`) and `#` header lines are ignored. When the
runs' columns differ (a column added, renamed or removed), the columns both have are compared
and the others are named. Rows only the second run has are counted as new. Prints the cells
that differ and a count; exits 1 if any differ or a row of the first run is missing.
"""
import csv
import sys

TIME_SUFFIXES = ("_ms", "ms_per_iteration", "wall_s")
KEYS = ("scenario", "method", "energy", "variant", "budget", "frame", "iteration", "description")


def is_time(column):
    return column == "ms" or column.endswith(TIME_SUFFIXES)


def read(path):
    with open(path, newline="") as f:
        lines = [line for line in f if not line.startswith("#")]
    rows = list(csv.DictReader(lines))
    columns = list(rows[0].keys()) if rows else []
    return columns, rows


def main(before_path, after_path):
    columns, before = read(before_path)
    after_columns, after = read(after_path)
    if columns != after_columns:
        only_before = [c for c in columns if c not in after_columns]
        only_after = [c for c in after_columns if c not in columns]
        print(f"columns only in {before_path}: {only_before}")
        print(f"columns only in {after_path}: {only_after}")
        columns = [c for c in columns if c in after_columns]
    keys = [c for c in columns if c in KEYS]
    index = {}
    for row in after:
        index.setdefault(tuple(row[k] for k in keys), []).append(row)
    changed = compared = missing = 0
    for row in before:
        key = tuple(row[k] for k in keys)
        if not index.get(key):
            print(f"missing row {key}")
            missing += 1
            continue
        other = index[key].pop(0)
        for column in columns:
            if is_time(column) or column in keys:
                continue
            compared += 1
            if row[column] != other[column]:
                changed += 1
                print(f"{key} {column}: {row[column]} -> {other[column]}")
    new = sum(len(rows) for rows in index.values())
    print(f"{after_path}: {changed} of {compared} non-time cells changed, {missing} rows missing, "
          f"{new} new rows")
    return 1 if changed or missing else 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
