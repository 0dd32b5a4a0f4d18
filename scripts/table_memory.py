#!/usr/bin/python3
"""Peak device memory per triangle and per front node, per scene and pipeline.

Peak bytes is the /summary attribute peak_bytes (executor memory peak of the run; the
largest /frames/device_peak_bytes when a file has no summary value). Bytes per triangle is
peak / the root attribute `triangles`. For front pipelines (any frame with front_int +
front_ext > 0), bytes per front node is peak / the largest front of the run (all frames,
since the peak covers them too). Markdown on stdout.

  scripts/table_memory.py results/
"""
import argparse
import sys

import numpy as np

import cdb_results


def mib(n):
    return f"{n / 2**20:.2f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("paths", nargs="+", help="results files or directories of *.h5")
    args = parser.parse_args()

    def body():
        complete, incomplete = cdb_results.load(args.paths)
        lines = []
        for (scene, device), runs in cdb_results.by_scene(complete).items():
            lines += [f"### {cdb_results.scene_heading(scene, device, complete)} "
                      f"({runs[0].triangles:,} triangles)", ""]
            rows = []
            for r in runs:
                peak = r.peak_bytes()
                per_triangle = f"{peak / r.triangles:.1f}" if r.triangles else "—"
                front = (r.frames["front_int"].astype(np.int64) + r.frames["front_ext"].astype(np.int64))
                max_front = int(front.max()) if len(front) else 0
                per_node = f"{peak / max_front:.1f}" if max_front else "—"
                rows.append([r.label, mib(peak), per_triangle, f"{max_front:,}" if max_front else "—", per_node])
            lines += cdb_results.markdown_table(
                ["pipeline", "peak MiB", "bytes / triangle", "max front nodes", "bytes / front node"], rows)
            lines.append("")
        if not lines:
            lines = ["No complete run."]
        return cdb_results.print_report(lines, incomplete)

    return cdb_results.run_main(body)


if __name__ == "__main__":
    sys.exit(main())
