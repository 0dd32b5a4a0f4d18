#!/usr/bin/python3
"""The tables of bench/bar.sh: per scene the new binary's c (mean, median, p95, and the
median over its passes of each pass's p95 and of its slowest frame over its median, the front
nodes a pair), b, a, grid and hash, each base
binary's c and b with base over new, and the targets: c at a third of the strongest peer's
mean (the bar's scenes), the best of a/b/c against the best of grid and hash, c against b,
c's peak memory (with what the second tree and fronts of builds ahead held of it, /memory)
against the first base's; then per base, c and b beside the new binary's: mean and median,
base over new, each one's pass p95 over median and peak memory.

  bench/bar_report.py DIR [--base NAME ...] > report.md

DIR holds bar.sh's files: the new binary's under DIR/new, a base binary's under DIR/NAME.
Times are ms per frame over the measured frames (the first left out), upload excluded.
"""
import argparse
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts"))
import cdb_results as cr  # noqa: E402

FILE = re.compile(r"^(.+)-([a-z]+)\.h5$")
NEW = ["c", "b", "a", "grid", "hash"]
FRONTS = ["a", "b", "c"]
CELLS = ["grid", "hash"]
# The strongest peer's mean on the bar's scenes (cuBQL refit + query on the same frames, one
# NVIDIA H200, driver 580.159.04, 2026-12-01, measured outside this repository); the target
# is a third of it.
PEER_MS = {"cloth-wave": 0.141, "spheres": 0.417, "cloth-wave-522k": 0.642, "cloth-wave-1m": 1.116,
           "crumple": 0.381, "garment": 0.720, "cloth-wave-10m": 10.80}
# The card PEER_MS was measured on: a run on another card gives the third of the peer with no
# verdict (its times and the peer's are not of one card).
PEER_DEVICE = "NVIDIA H200"


def index(directory):
    """{(scene, pipeline): Run} for every complete file in directory."""
    runs = {}
    if not os.path.isdir(directory):
        return runs
    for name in sorted(os.listdir(directory)):
        m = FILE.match(name)
        if not m:
            continue
        run = cr.Run(os.path.join(directory, name))
        if not run.complete:
            print(f"bar_report: {run.path}: {run.incomplete_reason()}; left out", file=sys.stderr)
            continue
        runs[(m.group(1), run.pipeline)] = run
    return runs


def mean(run):
    return run.stat("t_total_ms_mean") if run is not None else float("nan")


def single_pass_tail(run):
    """The median over the passes of each pass's p95 over its median (nan without /passes)."""
    times = run.pass_times() if run is not None else None
    if times is None or times.size == 0:
        return float("nan")
    return float(np.median(np.percentile(times, 95, axis=0) / np.median(times, axis=0)))


def single_pass_peak(run):
    """The median over the passes of each pass's slowest frame over its median."""
    times = run.pass_times() if run is not None else None
    if times is None or times.size == 0:
        return float("nan")
    return float(np.median(np.max(times, axis=0) / np.median(times, axis=0)))


def front_nodes_per_pair(run):
    """The mean over the measured frames of every front's nodes (self, cross, T_R's) over the pairs."""
    fronts = sum(run.column(k).astype(float) for k in ("front_int", "front_ext", "front_inter", "front_rigid")
                 if k in run.frames)
    return float(np.mean(fronts / np.maximum(run.column("pairs").astype(float), 1.0)))


def ms(x):
    return "—" if np.isnan(x) else f"{x:.4f}"


def two_places(x):
    return "—" if np.isnan(x) else f"{x:.2f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--base", action="append", default=[])
    args = ap.parse_args()
    new = index(os.path.join(args.dir, "new"))
    bases = {b: index(os.path.join(args.dir, b)) for b in args.base}
    scenes = sorted({s for (s, _) in new}, key=lambda s: new[(s, next(p for (t, p) in new if t == s))].triangles)

    header = ["scene", "triangles", "pairs", "c mean / median / p95", "c pass p95/median", "c pass max/median",
              "c front nodes a pair"]
    header += [f"{p} mean" for p in NEW[1:]] + ["c peak MiB", "of it built ahead"]
    for b in args.base:
        header += [f"{b} c", f"{b} b", f"{b} c ÷ new c", f"{b} c peak MiB"]
    rows, targets = [], []
    for s in scenes:
        c = new.get((s, "c"))
        if c is None:
            continue
        row = [s, f"{c.triangles:,}", f"{c.stat('pairs_mean'):,.0f}",
               f"{mean(c):.4f} / {c.stat('t_total_ms_median'):.4f} / {c.stat('t_total_ms_p95'):.4f}",
               f"{single_pass_tail(c):.2f}", f"{single_pass_peak(c):.2f}", f"{front_nodes_per_pair(c):.2f}"]
        row += [ms(mean(new.get((s, p)))) for p in NEW[1:]]
        row.append(f"{c.peak_bytes() / 2**20:.0f}")
        ahead = c.bytes_at_peak("ahead_")
        row.append("—" if ahead is None else f"{ahead / 2**20:.0f}")
        for b in args.base:
            bc, bb = bases[b].get((s, "c")), bases[b].get((s, "b"))
            row += [ms(mean(bc)), ms(mean(bb)), f"{mean(bc) / mean(c):.2f}x" if bc else "—",
                    f"{bc.peak_bytes() / 2**20:.0f}" if bc else "—"]
        rows.append(row)

        fronts = {p: mean(new.get((s, p))) for p in FRONTS}
        cells = {p: mean(new.get((s, p))) for p in CELLS}
        best_front = min(fronts, key=lambda p: np.inf if np.isnan(fronts[p]) else fronts[p])
        best_cell = min(cells, key=lambda p: np.inf if np.isnan(cells[p]) else cells[p])
        peer = PEER_MS.get(s)
        target = [s, f"{mean(c):.4f}"]
        if not peer:
            target.append("—")
        elif c.device != PEER_DEVICE:
            target.append(f"{peer / 3:.4f} (the peer's on the {PEER_DEVICE}; no verdict on the {c.device})")
        else:
            target.append(f"{peer / 3:.4f} ({'met' if mean(c) <= peer / 3 else 'not met'}; "
                          f"{peer / mean(c):.2f}x the peer)")
        ratio = cells[best_cell] / fronts[best_front]
        # A scene where no cell method ran (a run of c alone) has no such comparison.
        target.append("—" if np.isnan(ratio) else
                      f"{best_front} {fronts[best_front]:.4f} / {best_cell} {cells[best_cell]:.4f} = "
                      f"{ratio:.2f}x ({'met' if ratio >= 1.0 else 'not met'})")
        cb = fronts["c"] / fronts["b"]
        target.append("—" if np.isnan(cb) else f"{cb:.3f}")
        tail = single_pass_tail(c)
        target.append(f"{tail:.2f} ({'met' if tail <= 2.0 else 'not met'})")
        # Peak memory against the first base's c: at most as high.
        first = bases[args.base[0]].get((s, "c")) if args.base else None
        if first:
            peak = c.peak_bytes() / first.peak_bytes()
            # The excess too: a peak a few KiB above the base's reads 1.00.
            over = c.peak_bytes() - first.peak_bytes()
            size = (f"{over / 2**20:+.2f} MiB" if over >= 2**20 else
                    f"{over / 2**10:+.1f} KiB" if over >= 2**10 else f"{over:+d} bytes")
            target.append(f"{peak:.2f} ({'met' if peak <= 1.0 else f'not met: {size}'})")
        elif args.base:
            target.append("—")
        targets.append(target)

    # Per base, c and b beside the new binary's: where a base is the new binary with another
    # option (BASE_BIN naming a wrapper), this is that option's A/B.
    side_header = ["scene", "pipeline", "new mean / median", "base mean / median", "base ÷ new mean",
                   "new pass p95/median", "base pass p95/median", "new peak MiB", "base peak MiB"]
    sides = {}
    for b in args.base:
        sides[b] = []
        for s in scenes:
            for p in ("c", "b"):
                n, o = new.get((s, p)), bases[b].get((s, p))
                if n is None or o is None:
                    continue
                sides[b].append([s, p, f"{mean(n):.4f} / {n.stat('t_total_ms_median'):.4f}",
                                 f"{mean(o):.4f} / {o.stat('t_total_ms_median'):.4f}", f"{mean(o) / mean(n):.2f}",
                                 two_places(single_pass_tail(n)), two_places(single_pass_tail(o)),
                                 f"{n.peak_bytes() / 2**20:.0f}", f"{o.peak_bytes() / 2**20:.0f}"])

    runs = list(new.values()) + [r for b in bases.values() for r in b.values()]
    print("Generated by `bench/bar_report.py DIR" + "".join(f" --base {b}" for b in args.base) +
          "` from the files of `bench/bar.sh` (one process a scene and binary, `--repeat 3 --phase-timing off`, "
          "the default warm-up; new and base alternating first). Times: ms a frame over the frames after the "
          "first, upload excluded.\n")
    print(cr.provenance(runs) + "\n")
    print("## Every scene\n")
    print("\n".join(cr.markdown_table(header, rows)))
    print("\n## Targets\n")
    print("c ≤ a third of the strongest peer's mean (the bar's scenes); the best of a/b/c at least as fast as the "
          "best of grid and hash; c over b (1 or less: c never slower); p95 at most twice the median in single "
          "passes (the median over the passes of each pass's p95 over its median)" +
          (f"; c's peak memory over {args.base[0]}'s c (1 or less)" if args.base else "") + ".\n")
    print("\n".join(cr.markdown_table(
        ["scene", "c mean", "a third of the peer", "best front / best cell", "c ÷ b", "pass p95/median"] +
        ([f"c peak ÷ {args.base[0]} c peak"] if args.base else []), targets)))
    for b in args.base:
        print(f"\n## {b} beside new\n")
        print("c and b of each binary; base ÷ new above 1: the base slower. Pass p95/median as above; peak: the "
              "run's executor memory peak.\n")
        print("\n".join(cr.markdown_table(side_header, sides[b])))
    return 0


if __name__ == "__main__":
    sys.exit(cr.run_main(main))
