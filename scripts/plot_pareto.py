#!/usr/bin/python3
"""Speed against accuracy of the speed/accuracy knobs on one scene (issue 8; docs/design.md
"Speed/accuracy knobs").

One point per complete run checked against the oracle (`run --check`): the pipeline and its
knobs (box_margin, boxes, box_precision, refit_every from params_json's pipeline_config; older
files count as 0 / discrete / fp32 / 1). x: mean ms per frame (/summary t_total_ms_mean); left panel: worst
recall over the checked frames (recall_min), right panel: mean precision over them. The
Pareto front of each panel (no other run is as fast and at least as accurate, one of them
strictly) is joined and ringed. With --table, also a Markdown table of the points, fastest
first, on stdout. Runs without checked frames are left out (named on stderr).

With swept boxes the oracle is still the discrete box-overlap set, so their "false
positives" include the pairs only the swept boxes find: their precision is a share of
discrete pairs, not an error rate.

  scripts/plot_pareto.py results/pareto --scene cloth-ball --out pareto.png --table
"""
import argparse
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)

import numpy as np  # noqa: E402

import cdb_results  # noqa: E402


class Point:
    def __init__(self, run):
        self.run = run
        config = json.loads(run.attrs.get("params_json", "{}") or "{}").get("pipeline_config", {})
        self.margin = float(config.get("box_margin", 0.0))
        self.boxes = str(config.get("boxes", "discrete"))
        self.precision = str(config.get("box_precision", "fp32"))
        self.refit_every = int(config.get("refit_every", 1))
        self.conservative = bool(config.get("conservative", True))
        checked = run.frames["checked"].astype(bool) if "checked" in run.frames else np.zeros(run.rows, bool)
        self.checked = int(checked.sum())
        self.ms = run.stat("t_total_ms_mean")
        self.recall_min = min(run.frames["recall"][checked]) if self.checked else math.nan
        self.precision_min = min(run.frames["precision"][checked]) if self.checked else math.nan
        self.precision_mean = float(np.mean(run.frames["precision"][checked])) if self.checked else math.nan
        self.contact_precision = (run.stat("contact_precision")
                                  if run.summary and "contact_precision" in run.summary else math.nan)
        self.front = []

    def knobs(self):
        return f"margin {self.margin:g}, {self.boxes}, {self.precision}, refit every {self.refit_every}"

    def label(self):
        return f"{self.run.pipeline} ({self.knobs()})"


def pareto(points, key):
    """Points no other point dominates: as fast or faster and as accurate or more, one strictly."""
    front = []
    for p in points:
        dominated = any(q is not p and q.ms <= p.ms and key(q) >= key(p) and (q.ms < p.ms or key(q) > key(p))
                        for q in points)
        if not dominated:
            front.append(p)
    return sorted(front, key=lambda p: p.ms)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("paths", nargs="+", help="results files or directories of *.h5")
    parser.add_argument("--scene", help="scene to plot (needed when the files hold several)")
    parser.add_argument("--out", required=True, help="PNG to write")
    parser.add_argument("--table", action="store_true", help="also print a Markdown table of the points")
    args = parser.parse_args()

    def body():
        complete, incomplete = cdb_results.load(args.paths)
        args.scene = cdb_results.pick_scene(args.paths, complete, args.scene)
        cdb_results.report_incomplete([r for r in incomplete if r.scene == args.scene], "plot_pareto")
        points = [Point(r) for r in complete if r.scene == args.scene]
        for p in points:
            if not p.checked:
                print(f"plot_pareto: {p.run.path}: no frame checked against the oracle (run --check); left out",
                      file=sys.stderr)
        points = [p for p in points if p.checked]
        if not points:
            raise cdb_results.ResultsError(f"{', '.join(args.paths)}: no complete checked run of scene "
                                           f"'{args.scene}'")
        points.sort(key=lambda p: (p.ms, p.run.pipeline, p.knobs()))
        panels = (("worst recall (recall_min)", lambda p: p.recall_min, "recall"),
                  ("mean precision", lambda p: p.precision_mean, "precision"))
        fig, axes = plt.subplots(1, 2, figsize=(12, 5.2), sharex=True)
        pipelines = sorted({p.run.pipeline for p in points})
        colors = {name: plt.cm.tab10(k % 10) for k, name in enumerate(pipelines)}
        edge_of = {"q16": "black", "fp64": "magenta"}  # fp32: no edge
        markers = {("discrete", True): "o", ("swept", True): "s", ("discrete", False): "v", ("swept", False): "D"}
        for ax, (ylabel, key, name) in zip(axes, panels):
            for p in points:
                ax.scatter(p.ms, key(p), color=colors[p.run.pipeline], s=22 + 60 * min(p.margin, 1.0) ** 0.5,
                           marker=markers[(p.boxes, p.refit_every == 1)], alpha=0.8, zorder=2,
                           edgecolors=edge_of.get(p.precision, "none"), linewidths=1.5)
            front = pareto(points, key)
            for p in front:
                p.front.append(name)
            ax.plot([p.ms for p in front], [key(p) for p in front], color="black", linewidth=1, zorder=1,
                    drawstyle="steps-post")
            ax.scatter([p.ms for p in front], [key(p) for p in front], s=140, facecolors="none",
                       edgecolors="black", linewidths=1.2, zorder=3)
            # A front point says its margin: the knob a reader picks the point by.
            for p in front:
                ax.annotate(f"margin {p.margin:g}", (p.ms, key(p)), textcoords="offset points", xytext=(6, 6),
                            fontsize=7, zorder=4)
            ax.set_xscale("log")
            ax.set_xlabel("mean ms / frame")
            ax.set_ylabel(ylabel)
            ax.grid(alpha=0.3)
        for name in pipelines:
            axes[0].scatter([], [], color=colors[name], label=name)
        # The legend lists only the marker kinds and edges some point of the plot has.
        kinds = {(p.boxes, p.refit_every == 1) for p in points}
        shape_labels = ((("discrete", True), "discrete, refit every frame"),
                        (("swept", True), "swept, refit every frame"),
                        (("discrete", False), "lazy refit (not conservative)"),
                        (("swept", False), "swept, lazy refit (not conservative)"))
        for kind, label in shape_labels:
            if kind in kinds:
                axes[0].scatter([], [], marker=markers[kind], color="gray", label=label)
        precisions = {p.precision for p in points}
        for precision, label in (("q16", "q16 boxes"), ("fp64", "fp64 (rebased) boxes")):
            if precision in precisions:
                axes[0].scatter([], [], marker="o", color="gray", edgecolors=edge_of[precision], linewidths=1.5,
                                label=label)
        axes[0].scatter([], [], s=140, facecolors="none", edgecolors="black", label="Pareto front")
        axes[0].legend(fontsize=7)
        fig.suptitle(f"{args.scene}: speed/accuracy knobs ({points[0].run.device}); "
                     "marker size grows with the box margin", fontsize=10)
        fig.tight_layout()
        # No Software entry: the PNG stays byte-identical across matplotlib versions.
        fig.savefig(args.out, dpi=110, metadata={"Software": None})
        if args.table:
            header = ["pipeline", "box margin", "boxes", "box precision", "refit every", "conservative", "mean ms", "recall min",
                      "precision min", "precision mean", "contact precision", "Pareto"]
            rows = [[p.run.pipeline, f"{p.margin:g}", p.boxes, p.precision, str(p.refit_every),
                     "yes" if p.conservative else "**no**", cdb_results.fmt(p.ms), f"{p.recall_min:.6f}",
                     f"{p.precision_min:.6f}", f"{p.precision_mean:.6f}",
                     "—" if math.isnan(p.contact_precision) else f"{p.contact_precision:.6f}",
                     ", ".join(p.front) or "—"] for p in points]
            print("\n".join(cdb_results.markdown_table(header, rows)))
        def front_text(name):
            on = [p for p in points if name in p.front]
            return f"{name} {len(on)} (margins {', '.join(f'{p.margin:g}' for p in on)})"

        print(f"wrote {args.out}: {args.scene}, {len(points)} runs; Pareto front, its points labelled with their "
              "margin: " + "; ".join(front_text(name) for _, _, name in panels),
              file=sys.stderr if args.table else sys.stdout)
        return 0

    return cdb_results.run_main(body)


if __name__ == "__main__":
    sys.exit(main())
