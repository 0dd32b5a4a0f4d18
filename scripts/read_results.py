#!/usr/bin/python3
"""Print cdbench results files: the run's attributes, the per-frame table and /summary.

Reads only the schema (docs/results-format.md): every /frames dataset is a column,
whatever columns a file has. Needs h5py and numpy (Debian: python3-h5py, python3-numpy).

  scripts/read_results.py results/run.h5 [more.h5 ...] [--summary] [--params]
  scripts/read_results.py --csv results/run.h5 [more.h5 ...]

--csv prints CSV alone (for csv.DictReader and the like): a header, then one row per frame
of every file, the file's path in the first column `file`, then every /frames column of
the files in the first file's order (a column some file lacks is empty there), numbers as
the shortest text that reads back as the same value.
"""
import argparse
import csv
import json
import math
import sys

import h5py
import numpy as np

# In step with kResultsSchemaVersion (harness/results/results_file.h); 3 added label, input_path,
# input_hash and noise_warning, which older files lack (they are printed when present); 4
# added each pass's front plan (/plans) and the columns and attributes of --repeat-plan; 5
# every pass's times (/passes) and the run's conditions. Scenes with declared queries add
# /frames/pairs_self, /frames/pairs_inter and /summary pairs_self_mean, pairs_inter_mean.
SUPPORTED_SCHEMA = 5
HEADER_ATTRS = ["scene", "pipeline", "backend", "device_name", "frame_first", "frame_last",
                "warmup", "triangles", "label", "input_path", "input_hash", "noise_warning", "git_sha",
                "cdbench_version", "created_utc", "closed_utc"]


def text(value):
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    if isinstance(value, np.generic):
        return text(value.item())
    if isinstance(value, float):
        return "nan" if math.isnan(value) else f"{value:.6g}"
    return str(value)


def frame_columns(f):
    """The /frames datasets in the writer's order (the group tracks creation order)."""
    return list(f["frames"].keys())


def exact(value):
    """A cell of --csv: floats as the shortest text that reads back as the same double."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float):
        return repr(value)
    return text(value)


def print_csv(paths):
    """Every file's /frames as one CSV table; 1 when a file cannot be read (named on stderr)."""
    tables, names, rc = [], [], 0
    for path in paths:
        try:
            with h5py.File(path, "r") as f:
                if int(f.attrs.get("schema_version", 0)) == 0:
                    raise ValueError("not a cdbench results file (no schema_version attribute)")
                columns = {n: f["frames"][n][()] for n in frame_columns(f)}
        except (OSError, KeyError, ValueError) as e:
            print(f"read_results: {path}: {e}", file=sys.stderr)
            rc = 1
            continue
        names += [n for n in columns if n not in names]
        tables.append((path, columns))
    out = csv.writer(sys.stdout, lineterminator="\n")
    out.writerow(["file"] + names)
    for path, columns in tables:
        rows = len(columns["frame"])
        for i in range(rows):
            out.writerow([path] + [exact(columns[n][i]) if n in columns else "" for n in names])
    return rc


def print_frames(f):
    names = frame_columns(f)
    columns = [f["frames"][n][()] for n in names]
    rows = len(columns[0]) if columns else 0
    cells = [[text(c[i]) for c in columns] for i in range(rows)]
    widths = [max([len(n)] + [len(r[k]) for r in cells]) for k, n in enumerate(names)]
    print("  ".join(n.rjust(w) for n, w in zip(names, widths)))
    for r in cells:
        print("  ".join(c.rjust(w) for c, w in zip(r, widths)))


def print_summary(f):
    if "summary" not in f:
        print("summary: none (the run stopped before writing it)")
        return
    attrs = f["summary"].attrs
    print(f"summary: {text(attrs['frames'])} frames, {text(attrs['warmup'])} warm-up, "
          f"first frame {text(attrs['first_frame_ms'])} ms ({text(attrs['first_frame_op'])})")
    phases = [k[len("t_"):-len("_ms_mean")] for k in attrs if k.startswith("t_") and k.endswith("_ms_mean")]
    for p in phases:
        key = f"t_{p}_ms"
        if int(attrs.get(key + "_frames", 1)) == 0:
            continue
        stats = "  ".join(f"{s} {text(attrs[key + '_' + s])}" for s in ("mean", "median", "p95", "min"))
        print(f"  {p:<12} {stats} ms  ({text(attrs.get(key + '_frames', '?'))} frames)")
    by_query = (f", self {text(attrs['pairs_self_mean'])}, inter {text(attrs['pairs_inter_mean'])}"
                if "pairs_self_mean" in attrs else "")
    print(f"  pairs        mean {text(attrs['pairs_mean'])} per frame{by_query}")
    if int(attrs.get("checked_frames", 0)):
        print(f"  check        {text(attrs['checked_frames'])} frames: recall min {text(attrs['recall_min'])}, "
              f"precision min {text(attrs['precision_min'])}")
        if "contact_precision" in attrs:  # files written before the narrow phase lack it
            print(f"  contacts     {text(attrs['contacts'])} of {text(attrs['checked_pairs'])} checked pairs: "
                  f"contact precision {text(attrs['contact_precision'])}, min {text(attrs['contact_precision_min'])}")
        if "discrete_missed_contacts" in attrs:  # files written before the interval contacts lack it
            print(f"  interval     {text(attrs['discrete_missed_contacts'])} contacts missed by discrete boxes")
    print(f"  memory       peak {text(attrs['peak_bytes'])} bytes, {text(attrs['growths'])} growths, "
          f"{text(attrs['query_reruns'])} query re-runs")


def show(path, args):
    with h5py.File(path, "r") as f:
        version = int(f.attrs.get("schema_version", 0))
        if version == 0:
            raise ValueError(f"{path}: not a cdbench results file (no schema_version attribute)")
        if version > SUPPORTED_SCHEMA:
            print(f"{path}: schema_version {version} is newer than this script's {SUPPORTED_SCHEMA}; "
                  "reading what it knows", file=sys.stderr)
        status = text(f.attrs["status"])
        rows = len(f["frames/frame"])
        print(f"== {path}")
        print(f"status: {status} ({rows} frames written)")
        if "error" in f.attrs:
            print(f"error: {text(f.attrs['error'])}")
        for name in HEADER_ATTRS:
            if name in f.attrs:
                print(f"{name}: {text(f.attrs[name])}")
        if args.params:
            print("params: " + json.dumps(json.loads(text(f.attrs["params_json"])), indent=2, sort_keys=True))
        if not args.summary:
            print_frames(f)
        print_summary(f)
        if "pairs" in f:
            print(f"pairs saved for {len(f['pairs'])} frames")
        return status


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("files", nargs="+", help="results files written by cdbench run --out")
    parser.add_argument("--summary", action="store_true", help="no per-frame table")
    parser.add_argument("--csv", action="store_true",
                        help="the per-frame tables of all files as one CSV table, nothing else")
    parser.add_argument("--params", action="store_true", help="print every parameter of the run")
    args = parser.parse_args()
    if args.csv:
        return print_csv(args.files)
    rc = 0
    for path in args.files:
        try:
            show(path, args)
        except (OSError, KeyError, ValueError) as e:
            print(f"read_results: {path}: {e}", file=sys.stderr)
            rc = 1
    return rc


if __name__ == "__main__":
    sys.exit(main())
