#!/usr/bin/python3
"""Mean ms/frame against triangles, log-log, one line per pipeline, with fitted exponents.

x is the root attribute `triangles`, y the /summary t_total_ms_mean of each complete run.
The exponent k of ms ~ c * triangles^k is the least-squares slope on log-log axes; it needs
two sizes at least. Writes the PNG and prints the exponents as a Markdown table.

  scripts/plot_scaling.py results/scaling/ --out scaling.png [--scene 'soup.*']
"""
import argparse
import math
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)
import numpy as np  # noqa: E402

import cdb_results  # noqa: E402


def fit_exponent(x, y):
    if len(set(x)) < 2 or min(x) <= 0 or min(y) <= 0:
        return None
    slope, _ = np.polyfit(np.log(x), np.log(y), 1)
    return float(slope)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("paths", nargs="+", help="results files or directories of *.h5")
    parser.add_argument("--scene", default=".*", help="only scenes whose name (without its --set overrides) matches this regex (default: all)")
    parser.add_argument("--out", required=True, help="PNG to write")
    args = parser.parse_args()

    def body():
        complete, incomplete = cdb_results.load(args.paths)
        pattern = re.compile(args.scene)
        runs = [r for r in complete if pattern.fullmatch(r.scene_name)]
        series = {}
        for r in runs:
            if not math.isfinite(r.stat("t_total_ms_mean")):
                continue  # no measured frame: nothing to place on the plot
            series.setdefault(r.pipeline, []).append((r.triangles, r.stat("t_total_ms_mean"), r.scene))
        fig, ax = plt.subplots(figsize=(7, 5))
        rows = []
        for pipeline, points in sorted(series.items()):
            points.sort()
            x = [p[0] for p in points]
            y = [p[1] for p in points]
            k = fit_exponent(x, y)
            label = pipeline if k is None else f"{pipeline} (k = {k:.2f})"
            ax.plot(x, y, marker="o", label=label)
            rows.append([pipeline, str(len(set(x))), f"{min(x):,} ~ {max(x):,}",
                         f"{cdb_results.fmt(min(y))} ~ {cdb_results.fmt(max(y))}",
                         "—" if k is None else f"{k:.2f}"])
        if runs:
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_title(f"ms/frame vs triangles ({runs[0].device})", fontsize=10)
            ax.legend(fontsize=8)
        else:
            ax.text(0.5, 0.5, "no complete run", ha="center", transform=ax.transAxes)
        ax.set_xlabel("triangles")
        ax.set_ylabel("mean total ms / frame")
        ax.grid(alpha=0.3, which="both")
        fig.tight_layout()
        # No Software entry: the PNG stays byte-identical across matplotlib versions.
        fig.savefig(args.out, dpi=110, metadata={"Software": None})
        lines = ["Fitted exponent k of ms/frame ~ c * triangles^k (least squares on log-log)", ""]
        lines += cdb_results.markdown_table(
            ["pipeline", "sizes", "triangles", "mean ms/frame", "exponent k"], rows)
        return cdb_results.print_report(lines, incomplete)

    return cdb_results.run_main(body)


if __name__ == "__main__":
    sys.exit(main())
