#!/usr/bin/python3
"""The tables of bench/anchors.sh: per scene, c (mean, median, p95; a single pass's median
and p95), a, b, grid and bvh means, c with --rebuild-degraded off, each base binary's c, the
ratio base / new, the pairs and c's peak memory.

  bench/anchors_report.py DIR [--base NAME ...] > tables.md

DIR is $OUT/anchors: NEW files under DIR/new, a base binary's under DIR/NAME. Times are ms
per frame over the measured frames (the first left out), upload excluded.
"""
import argparse
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts"))
import cdb_results as cr  # noqa: E402

FILE = re.compile(r"^(repeat|single|keep-tree)-(.+)-([a-z-]+?)\.h5$")
PIPELINES = ["c", "a", "b", "grid", "bvh"]


def index(directory):
    """{(mode, scene, pipeline): Run} for every complete file in directory."""
    runs = {}
    if not os.path.isdir(directory):
        return runs
    for name in sorted(os.listdir(directory)):
        m = FILE.match(name)
        if not m:
            continue
        run = cr.Run(os.path.join(directory, name))
        if not run.complete:
            print(f"anchors_report: {run.path}: {run.incomplete_reason()}; left out", file=sys.stderr)
            continue
        runs[(m.group(1), m.group(2), run.pipeline)] = run
    return runs


def stat(run, key):
    return run.stat(f"t_total_ms_{key}") if run is not None else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--base", action="append", default=[])
    args = ap.parse_args()
    new = index(os.path.join(args.dir, "new"))
    bases = {b: index(os.path.join(args.dir, b)) for b in args.base}
    scenes = sorted({s for (_, s, _) in new}, key=lambda s: min(r.triangles for (m, sc, p), r in new.items() if sc == s))
    header = ["scene", "triangles", "pairs", "c mean / median / p95", "c single median / p95 (p95/median)"]
    header += [f"{p} mean" for p in PIPELINES[1:]] + ["c, tree kept", "c peak MiB (KB/tri)"]
    for b in args.base:
        header += [f"{b} c mean / p95 single", f"{b} ÷ new"]
    rows = []
    for s in scenes:
        c, single, kept = new.get(("repeat", s, "c")), new.get(("single", s, "c")), new.get(("keep-tree", s, "c"))
        if c is None:
            continue
        row = [s, f"{c.triangles:,}", f"{c.stat('pairs_mean'):,.0f}",
               f"{stat(c, 'mean'):.3f} / {stat(c, 'median'):.3f} / {stat(c, 'p95'):.3f}"]
        row.append(f"{stat(single, 'median'):.3f} / {stat(single, 'p95'):.3f} ({stat(single, 'p95') / stat(single, 'median'):.2f})"
                   if single else "—")
        for p in PIPELINES[1:]:
            r = new.get(("repeat", s, p))
            row.append(f"{stat(r, 'mean'):.3f}" if r else "—")
        row.append(f"{stat(kept, 'mean'):.3f}" if kept else "—")
        peak = c.peak_bytes()
        row.append(f"{peak / 2**20:.0f} ({peak / c.triangles / 1024:.2f})")
        for b in args.base:
            bc, bs = bases[b].get(("repeat", s, "c")), bases[b].get(("single", s, "c"))
            row.append(f"{stat(bc, 'mean'):.3f} / {stat(bs, 'p95'):.3f}" if bc else "—")
            row.append(f"{stat(bc, 'mean') / stat(c, 'mean'):.2f}x" if bc else "—")
        rows.append(row)
    runs = list(new.values()) + [r for b in bases.values() for r in b.values()]
    print(cr.provenance(runs) + "\n")
    print("\n".join(cr.markdown_table(header, rows)))
    return 0


if __name__ == "__main__":
    sys.exit(cr.run_main(main))
