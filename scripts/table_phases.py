#!/usr/bin/python3
"""Per-operation timings across sizes: the kernel micro-benchmarks, measured inside cdbench.

Each front-pipeline operation (build, order, refit, generate, preserve, update, balance,
front_order, restructure, inspect) is a timed phase of every frame, so a sweep of one scene
family over sizes (sweeps/gpu-ops.json, --warmup 0 so the building first frame counts too)
measures every operation at every size with the run's own method: CUDA events, --repeat
passes, noise. For each pipeline, a table: rows are phases, columns are sizes; a cell is the
mean ms over the frames where the phase ran, and its cost per triangle in ns. The histogram
sort (front_order of b/c) and the radix sort (front_order of radix-order) of the same fronts
sit side by side as the two pipelines' front_order rows.

  scripts/table_phases.py results/ops/ [--pipelines b,c,radix-order]
"""
import argparse
import math

import cdb_results

PHASES = ["build", "order", "refit", "generate", "preserve", "update", "balance", "front_order",
          "restructure", "inspect", "query", "boxes"]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("paths", nargs="+", help="results files or directories of *.h5")
    parser.add_argument("--pipelines", default="", help="comma-separated pipelines (default: all)")
    args = parser.parse_args()

    def body():
        complete, incomplete = cdb_results.load(args.paths)
        wanted = [p for p in args.pipelines.split(",") if p]
        by_pipeline = {}
        for r in complete:
            if wanted and r.pipeline not in wanted:
                continue
            by_pipeline.setdefault(r.pipeline, []).append(r)
        lines = []
        for pipeline in (wanted or sorted(by_pipeline)):
            runs = sorted(by_pipeline.get(pipeline, []), key=lambda r: r.triangles)
            if not runs:
                lines += [f"No complete `{pipeline}` run.", ""]
                continue
            header = ["phase"] + [f"{r.triangles:,} tris" for r in runs]
            rows = []
            for phase in PHASES:
                key = f"t_{phase}_ms_mean"
                cells, ran = [], False
                for r in runs:
                    mean = float(r.summary[key]) if r.summary and key in r.summary else math.nan
                    if math.isfinite(mean) and mean > 0:
                        ran = True
                        cells.append(f"{cdb_results.fmt(mean)} ms ({1e6 * mean / r.triangles:.3g} ns/tri)")
                    else:
                        cells.append("—")
                if ran:
                    rows.append([phase] + cells)
            lines += [f"### {pipeline}", ""]
            lines += cdb_results.markdown_table(header, rows)
            lines.append("")
        return cdb_results.print_report(lines, incomplete)

    return cdb_results.run_main(body)


if __name__ == "__main__":
    raise SystemExit(main())
