#!/usr/bin/python3
"""Front maintenance report: per scene and pipeline, the mean, median and p95 frame time
(frames after the first), their ratios to the median, the front updates a run made and the
frames they cost, for every binary of a run of bench/maintenance.sh.

  bench/maintenance_report.py DIR [DIR ...]   (each DIR: one binary's HDF5 files)

The binary is named by its directory; rows of the same scene and pipeline come together so
before and after read side by side. Frame times are the files' own (`t_total_ms`).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts"))
import cdb_results  # noqa: E402


def maintenance_frames(ops):
    """Frames whose fronts were produced without a build: updates, generates, restructures."""
    return [i for i, op in enumerate(ops) if op.startswith("refit+") and not op.endswith("+preserve")]


def row(tag, run):
    t = np.asarray(run.column("t_total_ms"), dtype=float)[1:]
    ops = list(run.column("op"))[1:] if "op" in run.frames else []
    if len(t) == 0:
        return None
    med = float(np.median(t))
    mean = float(np.mean(t))
    p95 = float(np.percentile(t, 95))
    upd = maintenance_frames(ops)
    upd_ms = float(np.mean(t[upd])) if upd else float("nan")
    return [run.scene, run.pipeline, tag,
            f"{run.triangles:,}", str(len(t)), f"{mean:.4f}", f"{med:.4f}", f"{p95:.4f}",
            f"{mean / med:.2f}", f"{p95 / med:.2f}", str(len(upd)),
            "-" if not upd else f"{upd_ms:.4f}", run.git_sha[:12]]


def main():
    dirs = sys.argv[1:]
    if not dirs:
        print(__doc__, file=sys.stderr)
        return 2
    rows = []
    devices = set()
    for d in dirs:
        tag = os.path.basename(os.path.normpath(d))
        for path in sorted(cdb_results.expand([d])):
            run = cdb_results.Run(path)
            devices.add(run.device)
            r = row(tag, run)
            if r:
                rows.append((os.path.basename(path), r))
    rows.sort(key=lambda x: (x[0], x[1][2]))
    header = ["scene", "pipeline", "binary", "triangles", "frames", "mean ms", "median ms", "p95 ms",
              "mean/median", "p95/median", "maintenance frames", "their mean ms", "commit"]
    print(f"Device: {', '.join(sorted(devices))}. Frames after the first; times without upload.\n")
    print("\n".join(cdb_results.markdown_table(header, [r for _, r in rows])))
    return 0


if __name__ == "__main__":
    sys.exit(main())
