#!/usr/bin/python3
"""Per-frame curves of the front strategies on one scene (the paper's Figures 5 and 8).

Top panel: t_total_ms per frame; bottom panel: q_root (Formula 1 at the root). Frames where
pipeline c decided to restructure or rebuild (/frames/decision) are circled. Only measured
frames are drawn (the first `warmup` rows, which build, would flatten the curves). The
baselines are drawn by default beside the strategies, the yardstick of the curves. Each run
has its own line style and marker (named in the line printed), so curves that coincide, as
b's Q under c's, both stay visible.

  scripts/plot_curves.py results/ --scene funnel --out funnel-curves.png
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)
from matplotlib.ticker import MaxNLocator  # noqa: E402

import numpy as np  # noqa: E402

import cdb_results  # noqa: E402

STRATEGIES = ["unordered", "static", "b", "periodic", "restructure", "c", "reference"]
BASELINES = ["bvh", "sweep", "hash", "grid", "brute"]
MARKED = ("restructure", "rebuild")
# Line styles and markers cycle at different lengths, so the first 28 runs each get their own
# pair; a marker every few frames tells lines apart where they lie on each other.
LINE_STYLES = [("-", "solid"), ("--", "dashed"), ("-.", "dash-dot"), (":", "dotted")]
MARKERS = [("o", "circles"), ("s", "squares"), ("^", "triangles"), ("D", "diamonds"), ("v", "down triangles"),
           ("x", "crosses"), ("P", "pluses")]


def style_of(k):
    """Run k's (linestyle, marker) and their names."""
    (ls, ls_name), (marker, marker_name) = LINE_STYLES[k % len(LINE_STYLES)], MARKERS[k % len(MARKERS)]
    return ls, marker, f"{ls_name}, {marker_name}"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("paths", nargs="+", help="results files or directories of *.h5")
    parser.add_argument("--scene", help="scene to plot (needed when the files hold several)")
    parser.add_argument("--pipelines", default=",".join(STRATEGIES + BASELINES),
                        help="pipelines to draw, in this order, when present (default: %(default)s)")
    parser.add_argument("--out", required=True, help="PNG to write")
    args = parser.parse_args()

    def body():
        complete, incomplete = cdb_results.load(args.paths)
        args.scene = cdb_results.pick_scene(args.paths, complete, args.scene)
        wanted = args.pipelines.split(",")
        runs = [r for r in complete if r.scene == args.scene and r.pipeline in wanted]
        runs.sort(key=lambda r: (wanted.index(r.pipeline), r.label))
        left_out = [r for r in incomplete if r.scene == args.scene and r.pipeline in wanted]
        cdb_results.report_incomplete(left_out, "plot_curves")
        if not runs:
            # A scene run with --set is labelled name[key=value]: name those the user may mean.
            near = sorted({r.scene for r in complete if r.scene.split("[")[0] == args.scene.split("[")[0]}
                          - {args.scene})
            hint = f" (runs of {', '.join(repr(n) for n in near)} are there: pass one to --scene)" if near else ""
            raise cdb_results.ResultsError(f"{', '.join(args.paths)}: no complete run of scene "
                                           f"'{args.scene}' with pipelines {args.pipelines}{hint}")

        fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(9, 6.5))
        marked = 0
        styles = []
        for k, r in enumerate(runs):
            frames = r.column("frame")
            total = r.column("t_total_ms")
            ls, marker, style = style_of(k)
            styles.append(style)
            drawn = {"linestyle": ls, "marker": marker, "markersize": 4, "markevery": max(1, len(frames) // 12),
                     "linewidth": 1.2, "markerfacecolor": "none"}
            (line,) = top.plot(frames, total, label=r.label, **drawn)
            q = r.column("q_root")
            has_q = (q > 0).any()
            if has_q:
                bottom.plot(frames, q, label=r.label, color=line.get_color(), **drawn)
            if "decision" in r.frames:
                decided = np.array([d in MARKED for d in r.column("decision")], dtype=bool)
                if decided.any():
                    marked += int(decided.sum())
                    for ax, ys in ((top, total), (bottom, q if has_q else None)):
                        if ys is None:
                            continue
                        ax.scatter(frames[decided], ys[decided], s=70, facecolors="none",
                                   edgecolors="red", linewidths=1.5, zorder=3)
        if marked:
            top.scatter([], [], s=70, facecolors="none", edgecolors="red", label="restructure/rebuild")
        device = runs[0].device
        top.set_title(f"{args.scene}: per-frame time and Q(root) ({device})", fontsize=10)
        top.set_ylabel("total ms / frame")
        bottom.set_ylabel("Q(root), Formula 1")
        bottom.set_xlabel("frame")
        bottom.xaxis.set_major_locator(MaxNLocator(integer=True))
        top.legend(fontsize=8)
        if bottom.lines:
            bottom.legend(fontsize=8)
        else:
            bottom.text(0.5, 0.5, "no ordered front pipeline reported q_root", ha="center",
                        transform=bottom.transAxes)
        if left_out:
            fig.text(0.01, 0.005, "incomplete, not drawn: " + ", ".join(r.path for r in left_out),
                     fontsize=7, color="darkred")
        for ax in (top, bottom):
            ax.grid(alpha=0.3)
        fig.tight_layout()
        # No Software entry: the PNG stays byte-identical across matplotlib versions.
        fig.savefig(args.out, dpi=110, metadata={"Software": None})
        print(f"wrote {args.out}: {args.scene}, " + ", ".join(f"{r.label} ({s})" for r, s in zip(runs, styles))
              + f"; {marked} restructure/rebuild decisions marked")
        return 0

    return cdb_results.run_main(body)


if __name__ == "__main__":
    sys.exit(main())
