#!/usr/bin/env python3
"""Measures full_arap against CGAL's ARAP run long (issue 38's targets).

For each scenario of experiments/scenarios as a one-frame edit (the handle
moved to its target at once, as a new user would try it): the ARAP energy
(table 2's arap_energy) of full_arap, converged, against CGAL's ARAP after
20 and after 1,000 local/global iterations. Then the default armadillo edit
on the 104K-vertex armadillo: full_arap's time to converge (precompute, set-up
and the frame) against CGAL's with 20 iterations, in the same run.

    PYTHONPATH=build/python /usr/bin/python3 scripts/full_arap_targets.py [--skip_104k] [--only=a,b]

Prints one markdown table per part; the numbers are deterministic but the
times are the machine's (quote the machine).
"""
import argparse
import glob
import os
import sys

import msdeform

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def total_ms(row):
    return row["precompute_ms"] + row["setup_ms"] + row["solve_total_ms"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip_104k", action="store_true", help="only the scenarios")
    parser.add_argument("--cgal_long", type=int, default=1000, help="CGAL's long run")
    parser.add_argument("--only", default="", help="comma-separated scenario names (default: all)")
    args = parser.parse_args()

    print(f"| scenario | full_arap | CGAL {args.cgal_long} | CGAL 20 | full / CGAL {args.cgal_long} "
          f"| CGAL 20 / full |")
    print("|---|---|---|---|---|---|")
    only = [name for name in args.only.split(",") if name]
    for path in sorted(glob.glob(os.path.join(ROOT, "experiments", "scenarios", "*.json"))):
        if only and os.path.basename(path)[:-5] not in only:
            continue
        scenario = msdeform.load_scenario(path, frames=1)
        full, _ = msdeform.run_method(scenario, "full_arap")
        long, _ = msdeform.run_method(scenario, "cgal_arap", cgal_iterations=args.cgal_long,
                                      cgal_tolerance=0.0)
        short, _ = msdeform.run_method(scenario, "cgal_arap")
        name = os.path.basename(path)[:-5]
        e_full, e_long, e_short = full["arap_energy"], long["arap_energy"], short["arap_energy"]
        print(f"| {name} | {e_full:.6g} | {e_long:.6g} | {e_short:.6g} | {e_full / e_long:.5f} "
              f"| {e_short / e_full:.4f} |", flush=True)
    if args.skip_104k:
        return 0

    claw = os.path.join(ROOT, "data", "scenarios", "armadillo_claw.json")
    mesh = os.path.join(ROOT, "data", "meshes", "armadillo_104k.off")
    scenario = msdeform.load_scenario(claw, frames=1, mesh_path=mesh)
    full, _ = msdeform.run_method(scenario, "full_arap", num_threads=1)
    cgal, _ = msdeform.run_method(scenario, "cgal_arap", num_threads=1)
    print()
    print("| 104K claw, one frame, 1 thread | precompute ms | set-up ms | frame ms | total ms "
          "| iterations | ARAP energy |")
    print("|---|---|---|---|---|---|---|")
    for name, row in (("full_arap", full), ("cgal_arap (20)", cgal)):
        print(f"| {name} | {row['precompute_ms']:.0f} | {row['setup_ms']:.0f} "
              f"| {row['solve_total_ms']:.0f} | {total_ms(row):.0f} | {row['iterations_total']} "
              f"| {row['arap_energy']:.6g} |")
    print(f"\nfull_arap total / CGAL-20 total: {total_ms(full) / total_ms(cgal):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
