#!/usr/bin/python3
"""Histogram sort vs radix sort of the BVTT front, per scene (the paper's Figure 6).

Histogram sort is what the ordered front pipeline (`static` = `b`) runs in its front_order
phase; radix sort is the `radix-order` baseline's front_order phase on the same scene. Per
scene: the front length range (front_int + front_ext, at the shortest and the longest
front), each sort's time range over the measured frames where it ran (t_front_order_ms > 0),
and the ratio of the mean radix time to the mean histogram time. Markdown on stdout.

  scripts/table_sort.py results/ [--histogram static,b] [--radix radix-order]
"""
import argparse
import sys

import numpy as np

import cdb_results


def sort_times(run):
    t = run.column("t_front_order_ms")
    return t[t > 0]


def front_range(run):
    inner = run.column("front_int").astype(np.int64)
    outer = run.column("front_ext").astype(np.int64)
    total = inner + outer
    if not len(total):
        return "—"
    lo, hi = int(np.argmin(total)), int(np.argmax(total))
    return f"({inner[lo]:,} + {outer[lo]:,}) ~ ({inner[hi]:,} + {outer[hi]:,})"


def time_range(t):
    return f"{cdb_results.fmt(float(t.min()))} ~ {cdb_results.fmt(float(t.max()))}" if len(t) else "—"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("paths", nargs="+", help="results files or directories of *.h5")
    parser.add_argument("--histogram", default="static,b",
                        help="pipelines whose front_order is the histogram sort, first found wins "
                             "(default: %(default)s)")
    parser.add_argument("--radix", default="radix-order", help="the radix-sort pipeline (default: %(default)s)")
    args = parser.parse_args()

    def body():
        complete, incomplete = cdb_results.load(args.paths)
        histogram_names = args.histogram.split(",")
        rows, without_radix = [], []
        for (scene, device), runs in cdb_results.by_scene(complete).items():
            hist = next((r for name in histogram_names for r in runs if r.pipeline == name), None)
            radix = next((r for r in runs if r.pipeline == args.radix), None)
            if hist is None and radix is None:
                continue
            ht = sort_times(hist) if hist else np.array([])
            rt = sort_times(radix) if radix else np.array([])
            if radix is None:
                without_radix.append(cdb_results.scene_heading(scene, device, complete))
            ratio = float(rt.mean() / ht.mean()) if len(ht) and len(rt) else None
            front = front_range(hist or radix)
            rows.append([cdb_results.scene_heading(scene, device, complete), front,
                         time_range(ht), time_range(rt),
                         "—" if ratio is None else f"{cdb_results.fmt(ratio)}x",
                         f"{len(ht)} / {len(rt)}"])
        print(f"Front sort per frame, ms (histogram: {args.histogram}; radix: {args.radix}; "
              "frames where the sort ran)")
        print()
        lines = cdb_results.markdown_table(
            ["scene", "front length (internal + external), min ~ max", "histogram sort (ms)",
             "radix sort (ms)", "radix / histogram (mean)", "frames (hist / radix)"], rows)
        if not rows:
            lines = ["No complete run of a histogram or radix front pipeline."]
        elif len(without_radix) == len(rows):
            # Every radix column would be a dash: say what is missing instead.
            lines = [f"No complete `{args.radix}` run: the table sets the radix sort against the histogram "
                     f"sort, so each scene needs a run of both (`cdbench run --pipeline {args.radix} ...`); "
                     f"histogram runs found for: {', '.join(without_radix)}."]
        elif without_radix:
            lines += ["", f"No `{args.radix}` run of: {', '.join(without_radix)} (its radix columns are `—`)."]
        return cdb_results.print_report(lines, incomplete)

    return cdb_results.run_main(body)


if __name__ == "__main__":
    sys.exit(main())
