#!/usr/bin/python3
"""Frame k of A against frame k of B: where in a scene two runs differ.

Each side is one results file or several (files, or directories of *.h5) pooled as repeats
of one run: a frame's value on a side is the median of its times over every pass of every
file (/passes; one value per file for files that keep only the passes' mean). One row per
frame both sides ran: A's median, B's, B / A, and each side's front plan step at that frame
where the two sides' plans differ there (a side whose passes ran several steps lists them,
joined by ' | '). Every frame is listed, the warm-up ones too (compare leaves those out).

  scripts/ab_frames.py --a out/ab/a --b out/ab/b [--csv] [--plot ab.png]
"""
import argparse
import csv
import sys

import numpy as np

import cdb_results


def side(paths, name, pipeline):
    """(runs, {frame: [ms, ...]}, {frame: {plan step, ...}}) of one side's complete files."""
    complete, incomplete = cdb_results.load(paths)
    cdb_results.report_incomplete(incomplete, "ab_frames")
    if pipeline is not None:
        complete = [r for r in complete if r.pipeline == pipeline]
    if not complete:
        raise cdb_results.ResultsError(f"{name} ({', '.join(paths)}): no complete results file"
                                       + (f" of pipeline {pipeline}" if pipeline else ""))
    kinds = sorted({(r.scene, r.pipeline, r.device) for r in complete})
    if len(kinds) > 1:
        listed = "; ".join(" ".join(k) for k in kinds)
        raise cdb_results.ResultsError(f"{name}: files of several runs ({listed}): pool repeats of one run only "
                                       "(--pipeline picks one pipeline)")
    times, plans = {}, {}
    for r in complete:
        frames = [int(k) for k in r.frames["frame"]]
        passes = r.passes.get("t_total_ms")
        for row, frame in enumerate(frames):
            values = passes[row] if passes is not None else [r.frames["t_total_ms"][row]]
            times.setdefault(frame, []).extend(float(v) for v in values)
        for steps in r.plans.values():
            for frame, step in steps.items():
                plans.setdefault(frame, set()).add(step)
    return complete, times, plans


def plan_text(steps):
    return " | ".join(sorted(steps)) if steps else ""


def rows_of(times_a, plans_a, times_b, plans_b):
    """[(frame, A median, B median, B / A, A passes, B passes, plan A, plan B)] over the frames
    both sides have, the plans filled only where they differ."""
    rows = []
    for frame in sorted(set(times_a) & set(times_b)):
        a, b = float(np.median(times_a[frame])), float(np.median(times_b[frame]))
        pa, pb = plans_a.get(frame, set()), plans_b.get(frame, set())
        differ = pa != pb or len(pa) > 1 or len(pb) > 1
        rows.append((frame, a, b, b / a if a > 0 else float("nan"), len(times_a[frame]), len(times_b[frame]),
                     plan_text(pa) if differ else "", plan_text(pb) if differ else ""))
    return rows


HEADER = ["frame", "a_median_ms", "b_median_ms", "ratio", "a_n", "b_n", "plan_a", "plan_b"]


def print_csv(rows):
    out = csv.writer(sys.stdout, lineterminator="\n")
    out.writerow(HEADER)
    for frame, a, b, ratio, na, nb, pa, pb in rows:
        # repr: the shortest text that reads back as the same double, as report --csv writes.
        out.writerow([frame, repr(a), repr(b), repr(ratio), na, nb, pa, pb])


def print_markdown(rows, runs_a, runs_b, measured_from):
    def names(runs):
        return ", ".join(f"`{r.path}`" + (f" [{r.run_label}]" if r.run_label else "") for r in runs)

    first = runs_a[0]
    print(f"Per frame, {first.scene} {first.pipeline} on {first.device}: the median over every pass "
          f"(A {rows[0][4] if rows else 0}, B {rows[0][5] if rows else 0} values a frame); B / A below 1 is B faster.")
    print()
    header = ["frame", "A median ms", "B median ms", "B / A", "plan A", "plan B"]
    cells = []
    for frame, a, b, ratio, _, _, pa, pb in rows:
        cells.append([f"{frame}" + (" (warm-up)" if frame < measured_from else ""), cdb_results.fmt(a), cdb_results.fmt(b),
                      f"{ratio:.3f}", pa or "", pb or ""])
    print("\n".join(cdb_results.markdown_table(header, cells)))
    print()
    print(f"- A: {names(runs_a)}")
    print(f"- B: {names(runs_b)}")
    if any(r[6] or r[7] for r in rows):
        print("- plans differ at the frames whose plan cells are filled: their times are of other work")


def plot(rows, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    frames = [r[0] for r in rows]
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(9, 6), gridspec_kw={"height_ratios": [2, 1]})
    top.plot(frames, [r[1] for r in rows], label="A", linewidth=1.2)
    top.plot(frames, [r[2] for r in rows], label="B", linewidth=1.2)
    top.set_ylabel("ms per frame (median over passes)")
    top.set_title(title)
    top.legend()
    bottom.plot(frames, [r[3] for r in rows], color="black", linewidth=1.0)
    bottom.axhline(1.0, color="grey", linewidth=0.8, linestyle="--")
    for r in rows:
        if r[6] or r[7]:
            bottom.axvline(r[0], color="tab:red", alpha=0.3, linewidth=0.8)
    bottom.set_ylabel("B / A")
    bottom.set_xlabel("frame (red: the plans differ)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--a", nargs="+", required=True, metavar="PATH", help="A: results files or directories of *.h5")
    parser.add_argument("--b", nargs="+", required=True, metavar="PATH", help="B: results files or directories")
    parser.add_argument("--pipeline", help="the pipeline to compare, where the files hold several")
    parser.add_argument("--csv", action="store_true", help="CSV instead of Markdown (" + ", ".join(HEADER) + ")")
    parser.add_argument("--plot", metavar="PNG", help="also draw both sides' curves and B / A into this PNG")
    args = parser.parse_args()

    def body():
        runs_a, times_a, plans_a = side(args.a, "A", args.pipeline)
        runs_b, times_b, plans_b = side(args.b, "B", args.pipeline)
        if runs_a[0].scene != runs_b[0].scene:
            raise cdb_results.ResultsError(f"A is scene {runs_a[0].scene}, B {runs_b[0].scene}: frame k of one "
                                           "scene is not frame k of another")
        rows = rows_of(times_a, plans_a, times_b, plans_b)
        if not rows:
            raise cdb_results.ResultsError("A and B have no frame in common")
        if args.csv:
            print_csv(rows)
        else:
            first = runs_a[0]
            print_markdown(rows, runs_a, runs_b, int(first.attrs["frame_first"]) + first.warmup())
        if args.plot:
            plot(rows, args.plot, f"{runs_a[0].scene} {runs_a[0].pipeline}: B against A, frame by frame")
        return 0
    return cdb_results.run_main(body)


if __name__ == "__main__":
    sys.exit(main())
