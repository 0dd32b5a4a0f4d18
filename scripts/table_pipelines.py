#!/usr/bin/python3
"""Every pipeline and baseline per scene: ms/frame and speed-up (the paper's Figure 9).

Mean, median and p95 come from /summary over the measured frames (all but the first `warmup`,
the count in "frames measured"; `report` gives both, `frames_run` and `frames_measured`);
"noise %" is the run's measurement noise: with `run --repeat K`, the median over the frames of
the relative standard deviation of a frame's time over the K passes ("—" for one pass). The
spread columns, the standard deviation of /frames/t_total_ms over the measured frames and
p95 - median, show how much frames differ from each other (the scene's work, not noise). Speed-up is the baseline's mean over the row's mean (> 1: faster than the
baseline). A row's baseline is the baseline pipeline's run of the same identity (the fields
`cdbench compare` matches on: scene, device, frames, warm-up and the options that change the
pair set or the timing, e.g. --skip-adjacent); the table names the file used, and a row with
no such run gets no speed-up. The fastest mean of each scene is in bold. Markdown, or LaTeX
with --latex.

  scripts/table_pipelines.py results/ [--baseline bvh] [--latex]
"""
import argparse
import math
import sys

import numpy as np

import cdb_results

HEADER = ["pipeline", "frames measured", "mean ms", "noise %", "median ms", "p95 ms", "std ms", "p95 - median",
          "speed-up vs {baseline}"]


def identity_suffix(run, runs):
    """The identity options that set this run apart within its table, e.g. ' [--skip-adjacent true]';
    '' when every run of the table shares them."""
    options = cdb_results.identity_options_of(runs)
    parts = []
    for k, (field, value) in enumerate(run.identity(options)):
        if len({r.identity(options)[k][1] for r in runs}) > 1:
            parts.append(f"{field} {value}")
    return f" [{', '.join(parts)}]" if parts else ""


def baseline_of(run, runs, baseline):
    """The baseline pipeline's run of the same identity as `run`, or None."""
    same = [b for b in runs if b.pipeline == baseline and not cdb_results.identity_differences(run, b)]
    return same[0] if same else None


def rows_of(runs, baseline):
    """The rows, and notes naming the baseline file of each identity (or its absence)."""
    means = [r.stat("t_total_ms_mean") for r in runs]
    # A run with no measured frame has a NaN mean; it is never the fastest.
    fastest = min((m for m in means if math.isfinite(m)), default=None)
    rows, notes = [], []
    for r, mean in zip(runs, means):
        base = baseline_of(r, runs, baseline)
        suffix = identity_suffix(r, runs)
        note = (f"Speed-up{suffix or ''} against `{base.path}`." if base is not None
                else f"No `{baseline}` run of the same identity as `{r.path}`{suffix}: no speed-up.")
        if note not in notes:
            notes.append(note)
        base_mean = base.stat("t_total_ms_mean") if base is not None else None
        median, p95 = r.stat("t_total_ms_median"), r.stat("t_total_ms_p95")
        t = r.column("t_total_ms")
        std = float(np.std(t, ddof=1)) if len(t) > 1 else float("nan")
        speedup = base_mean / mean if base_mean is not None and mean > 0 else None
        repeats = int(r.summary.get("repeats", 1)) if r.summary else 1
        noise = 100.0 * float(r.summary["noise_median"]) if repeats > 1 else None
        rows.append({"label": r.label + suffix, "frames_measured": str(len(t)), "mean": mean, "noise": noise,
                     "median": median, "p95": p95, "std": std, "spread": p95 - median, "speedup": speedup,
                     "bold": mean == fastest})
    return rows, notes


def cells(row):
    f = cdb_results.fmt
    noise = "—" if row["noise"] is None else f"{row['noise']:.1f}"
    return [row["label"], row["frames_measured"], f(row["mean"]), noise, f(row["median"]), f(row["p95"]), f(row["std"]),
            f(row["spread"]), "—" if row["speedup"] is None else f"{f(row['speedup'])}x"]


def markdown(groups, baseline, complete, incomplete):
    lines = []
    for (scene, device), runs in groups.items():
        rows, notes = rows_of(runs, baseline)
        triangles = runs[0].triangles
        lines += [f"### {cdb_results.scene_heading(scene, device, complete)} ({triangles:,} triangles)", ""]
        body = []
        for row in rows:
            c = cells(row)
            if row["bold"]:
                c[0], c[2] = f"**{c[0]}**", f"**{c[2]}**"
            body.append(c)
        lines += cdb_results.markdown_table([h.format(baseline=baseline) for h in HEADER], body)
        lines += [""] + notes
        lines.append("")
    lines += cdb_results.incomplete_lines(incomplete)
    return lines


def latex_escape(s):
    for a, b in (("\\", "\\textbackslash{}"), ("_", "\\_"), ("%", "\\%"), ("&", "\\&"), ("#", "\\#")):
        s = s.replace(a, b)
    return s


def latex(groups, baseline, complete, incomplete):
    header = [latex_escape(h.format(baseline=baseline)) for h in HEADER]
    lines = ["\\begin{tabular}{l" + "r" * (len(HEADER) - 1) + "}",
             "\\toprule", " & ".join(header) + " \\\\"]
    for (scene, device), runs in groups.items():
        rows, notes = rows_of(runs, baseline)
        lines += ["\\midrule",
                  f"\\multicolumn{{{len(HEADER)}}}{{l}}{{\\emph{{"
                  f"{latex_escape(cdb_results.scene_heading(scene, device, complete))}}}}} \\\\"]
        for row in rows:
            c = [latex_escape(x).replace("—", "--") for x in cells(row)]
            if row["bold"]:
                c[0], c[2] = f"\\textbf{{{c[0]}}}", f"\\textbf{{{c[2]}}}"
            lines.append(" & ".join(c) + " \\\\")
        lines += [f"% {n}" for n in notes]
    lines += ["\\bottomrule", "\\end{tabular}"]
    for r in incomplete:
        lines.append(f"% incomplete, not used: {r.path}: {r.incomplete_reason()}")
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("paths", nargs="+", help="results files or directories of *.h5")
    parser.add_argument("--baseline", default="bvh", help="pipeline the speed-up is relative to (default: %(default)s)")
    parser.add_argument("--latex", action="store_true", help="a LaTeX tabular (booktabs) instead of Markdown")
    args = parser.parse_args()

    def body():
        complete, incomplete = cdb_results.load(args.paths)
        groups = cdb_results.by_scene(complete)
        if not groups and not args.latex:
            print("No complete run.")
        make = latex if args.latex else markdown
        print("\n".join(make(groups, args.baseline, complete, incomplete)))
        return 0

    return cdb_results.run_main(body)


if __name__ == "__main__":
    sys.exit(main())
