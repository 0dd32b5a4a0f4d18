#!/usr/bin/python3
"""Shared reading for the table and plot scripts: cdbench results files through the schema only.

docs/results-format.md is the contract: root attributes, the /frames columns (looked up by
name, new ones tolerated) and the /summary attributes. Nothing here knows how a file was
written. Run directly, it prints the inventory of a set of files (one Markdown row each),
or with --provenance / --scenes-with / --scenes-checked what scripts/make_report.sh needs.

  scripts/cdb_results.py results/ [more.h5 ...]
"""
import argparse
import glob
import json
import math
import os
import sys

import h5py
import numpy as np

# 3: label, input_path, input_hash, noise_warning (optional: older files lack them).
# 4: /plans, repeat_plan, plan_source, /frames/plan_mixed, /summary plan_mixed_frames (optional).
# 5: /passes (every pass's frame and phase times) and the run's conditions (optional).
# Scenes with declared queries: /frames/pairs_self, /frames/pairs_inter, /summary pairs_self_mean,
# pairs_inter_mean (optional: other scenes and older files lack them).
SUPPORTED_SCHEMA = 5
# What `cdbench compare` matches runs on besides the pipeline, the scene, device, frames and
# warm-up: the options that change the pair set or how time is measured (not the run's
# --label, a display name). A file records them as params_json's identity_options
# (app/option_table.cpp, its identity rows) and Run reads that; this list is only for files
# written before they recorded it, and stays as those builds had it.
IDENTITY_OPTIONS = ["skip-adjacent", "box-precision", "box-margin", "boxes", "refit-every", "check",
                    "contact-distance", "contact-substeps", "cold", "phase-timing", "warmup-ms"]
# Root attributes every file has from its creation (schema 1 on); a file without them is not ours.
REQUIRED_ATTRS = ["status", "schema_version", "scene", "pipeline", "device_name", "git_sha",
                  "triangles", "frame_first", "frame_last", "warmup"]


class ResultsError(Exception):
    """A file that is not a readable cdbench results file; the message names the file."""


def text(value):
    if isinstance(value, bytes):
        return value.split(b"\0", 1)[0].decode("utf-8", "replace")
    if isinstance(value, np.generic):
        return text(value.item())
    return str(value)


def plain(value):
    """An attribute as a Python str/int/float."""
    if isinstance(value, (bytes, str)):
        return text(value)
    if isinstance(value, np.generic):
        return value.item()
    return value


def set_value(text):
    """A `--set` value as cdbench reads it: JSON where it parses (numbers, booleans), else the text."""
    try:
        return json.loads(text)
    except ValueError:
        return text


def label_of(scene, overrides):
    """`scene` alone, or `scene[k=v,...]` with the keys sorted: the scene label cdbench writes."""
    if not overrides:
        return scene
    parts = []
    for key in sorted(overrides):
        value = overrides[key]
        parts.append(f"{key}={value if isinstance(value, str) else json.dumps(value)}")
    return f"{scene}[{','.join(parts)}]"


def scene_label(attrs):
    """The run's scene identity: the file's scene_label (schema 2), or for older files the
    label made from the `--set` options recorded in params_json."""
    if "scene_label" in attrs:
        return attrs["scene_label"]
    try:
        options = json.loads(attrs.get("params_json", "{}") or "{}").get("options", {})
    except ValueError:
        options = {}
    given = options.get("set", [])
    overrides = {}
    for kv in given if isinstance(given, list) else [given]:
        key, eq, value = str(kv).partition("=")
        if eq and key:
            overrides[key] = set_value(value)
    return label_of(attrs["scene"], overrides)


PLAN_QUERIES = ("self", "inter", "rigid_self")


def plan_steps(group):
    """/plans as {pass: {frame: step text}}, a step as a plan file's line after its frame
    index writes it: `refit self=preserve probe`."""
    columns = {name: ds[()] for name, ds in group.items()}
    steps = {}
    for i in range(len(columns["pass"])):
        words = [text(columns["trees"][i])]
        words += [f"{q}={text(columns[q][i])}" for q in PLAN_QUERIES if q in columns and text(columns[q][i])]
        if "decision" in columns and text(columns["decision"][i]):
            words.append(f"decision={text(columns['decision'][i])}")
        words += [flag for flag in ("inspect", "probe") if flag in columns and int(columns[flag][i])]
        steps.setdefault(int(columns["pass"][i]), {})[int(columns["frame"][i])] = " ".join(words)
    return steps


class Run:
    """One results file: root attributes, every /frames column, /summary (or None), every
    pass's times (/passes) and plans (/plans)."""

    def __init__(self, path):
        self.path = path
        try:
            f = h5py.File(path, "r")
        except OSError as e:
            raise ResultsError(f"{path}: not a cdbench results file (not HDF5: {e})") from None
        with f:
            attrs = {k: plain(v) for k, v in f.attrs.items()}
            missing = [a for a in REQUIRED_ATTRS if a not in attrs]
            if missing:
                raise ResultsError(f"{path}: not a cdbench results file (no root attribute "
                                   f"{', '.join(missing)})")
            if int(attrs["schema_version"]) > SUPPORTED_SCHEMA:
                print(f"{path}: schema_version {attrs['schema_version']} is newer than "
                      f"{SUPPORTED_SCHEMA}; reading the fields this script knows", file=sys.stderr)
            if "frames" not in f or "frame" not in f["frames"]:
                raise ResultsError(f"{path}: not a cdbench results file (no /frames/frame)")
            self.frames = {}
            for name, ds in f["frames"].items():
                data = ds[()]
                if data.dtype.kind == "S":
                    data = np.array([text(v) for v in data], dtype=object)
                self.frames[name] = data
            self.summary = ({k: plain(v) for k, v in f["summary"].attrs.items()}
                            if "summary" in f else None)
            # Every pass's times per /frames row, {"t_total_ms": array (rows, passes), ...}:
            # empty for files before schema 5, which keep only the mean over the passes.
            self.passes = {name: ds[()] for name, ds in f["passes"].items()} if "passes" in f else {}
            # Every pass's plan per frame (/plans, front pipelines; schema 4): {pass: {frame: step}}
            # with each step as a plan file's line writes it (docs/usage.md "Plans"), empty
            # for pipelines without a frame plan and older files.
            self.plans = plan_steps(f["plans"]) if "plans" in f else {}
            # What each buffer held at the run's memory peak (/memory), {name: bytes} in the
            # executor's order; empty for files written before it was recorded.
            self.memory = ({text(b): int(n) for b, n in zip(f["memory"]["buffer"][()], f["memory"]["bytes_at_peak"][()])}
                           if "memory" in f else {})
        self.attrs = attrs
        # Runs group by the scene with its --set overrides (funnel[res=24]), never by the
        # descriptor's name alone; scene_name is the bare name.
        self.scene_name = attrs["scene"]
        self.scene = scene_label(attrs)
        self.pipeline = attrs["pipeline"]
        self.device = attrs["device_name"]
        self.git_sha = attrs["git_sha"]
        self.triangles = int(attrs["triangles"])
        self.rows = len(self.frames["frame"])
        self.asked = int(attrs["frame_last"]) - int(attrs["frame_first"])
        self.complete = attrs["status"] == "complete" and self.summary is not None
        self.label = self.pipeline
        self.run_label = attrs.get("label", "")  # run --label (schema 3)
        self.input_hash = attrs.get("input_hash", "")
        try:
            params = json.loads(attrs.get("params_json", "{}"))
        except ValueError:
            params = {}
        self.options = params.get("options", {}) if isinstance(params, dict) else {}
        recorded = params.get("identity_options") if isinstance(params, dict) else None
        self.identity_options = (recorded if isinstance(recorded, list) and all(isinstance(o, str) for o in recorded)
                                 else IDENTITY_OPTIONS)

    def identity(self, options=None):
        """[(field, value)] compare matches runs on, the pipeline left out; the input's content
        hash is apart (identity_differences), as older files lack it. `options`: the identity
        options to take (identity_options_of a set of runs, so runs whose files name other
        lists line up field by field); the file's own by default."""
        fields = [("scene", self.scene), ("device", self.attrs.get("backend", "")), ("device_name", self.device),
                  ("frames", f"{self.attrs['frame_first']}:{self.attrs['frame_last']}"),
                  ("warmup", str(self.attrs.get("warmup", "")))]
        for o in self.identity_options if options is None else options:
            v = self.options.get(o)
            fields.append((f"--{o}", "(not recorded)" if v is None else v if isinstance(v, str) else json.dumps(v)))
        return fields

    def incomplete_reason(self):
        """How report shows it: 'incomplete (K/N frames): error'."""
        why = self.attrs.get("error", "no error recorded (the process died?)")
        if self.attrs["status"] == "complete" and self.summary is None:
            why = "status complete but no /summary"
        return f"incomplete ({self.rows}/{self.asked} frames): {why}"

    def column(self, name):
        """A /frames column over the measured frames (the first `warmup` rows left out)."""
        if name not in self.frames:
            raise ResultsError(f"{self.path}: no /frames/{name} column")
        return self.frames[name][self.warmup():]

    def pass_times(self, name="t_total_ms"):
        """A /passes dataset over the measured frames: array (frames, passes); None when the
        file keeps no passes (schema 4 and older)."""
        if name not in self.passes:
            return None
        return self.passes[name][self.warmup():]

    def pass_metric(self, stat=np.mean, name="t_total_ms"):
        """Each pass's statistic over its measured frames (np.mean, np.median, ...), pass 0
        first; None without /passes."""
        times = self.pass_times(name)
        return None if times is None else [float(stat(times[:, p])) for p in range(times.shape[1])]

    def warmup(self):
        if self.summary is not None and "warmup" in self.summary:
            return int(self.summary["warmup"])
        return int(self.attrs["warmup"])

    def stat(self, key):
        """A /summary statistic, e.g. stat('t_total_ms_mean')."""
        if self.summary is None or key not in self.summary:
            raise ResultsError(f"{self.path}: no /summary attribute {key}")
        return float(self.summary[key])

    def pairs_by_query(self):
        """Per frame, the pairs within one object and between two ({'self': [...], 'inter': [...]}),
        for a scene with declared queries; None for other scenes and older files."""
        if "pairs_self" not in self.frames:
            return None
        return {"self": self.frames["pairs_self"], "inter": self.frames["pairs_inter"]}

    def bytes_at_peak(self, prefix=""):
        """The bytes the buffers whose names start with `prefix` held at the memory peak
        (/memory); None for files without it."""
        if not self.memory:
            return None
        return sum(n for b, n in self.memory.items() if b.startswith(prefix))

    def peak_bytes(self):
        if self.summary is not None and "peak_bytes" in self.summary:
            return int(self.summary["peak_bytes"])
        return int(self.frames["device_peak_bytes"].max()) if self.rows else 0


def identity_options_of(runs):
    """Every identity option any of the runs' files names, each once, in the order met."""
    names = []
    for r in runs:
        names += [o for o in r.identity_options if o not in names]
    return names


def identity_differences(a, b):
    """The identity fields of runs a and b that differ, as 'field: A vs B' (no pipeline)."""
    options = identity_options_of([a, b])
    diffs = [f"{fa}: {va} vs {vb}" for (fa, va), (_, vb) in zip(a.identity(options), b.identity(options))
             if va != vb]
    if a.input_hash and b.input_hash and a.input_hash != b.input_hash:
        diffs.append(f"input_hash: {a.input_hash} vs {b.input_hash}")
    return diffs


def expand(paths):
    """Files as given, directories as their *.h5 files (not recursive), sorted."""
    files = []
    for p in paths:
        if os.path.isdir(p):
            found = sorted(glob.glob(os.path.join(p, "*.h5")))
            if not found:
                raise ResultsError(f"{p}: no *.h5 files in this directory")
            files.extend(found)
        elif os.path.exists(p):
            files.append(p)
        else:
            raise ResultsError(f"{p}: no such file or directory")
    return files


def load(paths):
    """(complete runs, incomplete runs), each sorted by scene, pipeline, path.

    Runs of one scene, device and pipeline that occur more than once (e.g. other options)
    get the file's stem (or path, when stems repeat) added to their label so that rows
    stay apart.
    """
    runs = [Run(p) for p in expand(paths)]
    runs.sort(key=lambda r: (r.scene, r.pipeline, r.path))
    complete = [r for r in runs if r.complete]
    seen = {}
    for r in complete:
        seen.setdefault((r.scene, r.device, r.pipeline), []).append(r)
    for same in seen.values():
        if len(same) > 1:
            stems = [os.path.splitext(os.path.basename(r.path))[0] for r in same]
            unique = len(set(stems)) == len(stems)
            for r, stem in zip(same, stems):
                r.label = f"{r.pipeline} ({stem if unique else r.path})"
    return complete, [r for r in runs if not r.complete]


def steady_frames(run):
    """Mask of a run's measured frames that only refit and preserve, launched plain or
    replaying the frame's CUDA graph (--cuda-graph on: the frame that records the graph
    carries the host-side capture between its events, and is left out)."""
    op, graph = run.column("op"), run.column("graph")
    return np.array([text(o) == "refit+preserve" and text(g) != "captured" for o, g in zip(op, graph)], dtype=bool)


def pick_scene(paths, runs, scene):
    """The scene to draw: `scene` when given, else the only scene among `runs`."""
    if scene is not None:
        return scene
    scenes = sorted({r.scene for r in runs})
    if len(scenes) != 1:
        raise ResultsError(f"{', '.join(paths)}: --scene needed, the files "
                           f"hold scenes {', '.join(scenes) or 'none'}")
    return scenes[0]


def by_scene(runs):
    """{(scene, device): [runs]} in sorted order; the device only matters when files mix them."""
    groups = {}
    for r in runs:
        groups.setdefault((r.scene, r.device), []).append(r)
    return dict(sorted(groups.items()))


def scene_heading(scene, device, runs_all):
    devices = {r.device for r in runs_all}
    return f"{scene} ({device})" if len(devices) > 1 else scene


def incomplete_lines(incomplete):
    """Markdown list of the files left out because they are not complete."""
    if not incomplete:
        return []
    lines = ["", "Incomplete files (not used):", ""]
    for r in incomplete:
        lines.append(f"- `{r.path}`: {r.scene} / {r.pipeline}: {r.incomplete_reason()}")
    return lines


def print_report(lines, incomplete):
    """Prints a report's Markdown lines, then the list of the incomplete files it left out;
    returns the exit status, 0."""
    print("\n".join(lines + incomplete_lines(incomplete)))
    return 0


def report_incomplete(incomplete, tool):
    for r in incomplete:
        print(f"{tool}: {r.path}: {r.incomplete_reason()}; left out", file=sys.stderr)


def fmt(x):
    """Milliseconds and ratios: four significant digits, no exponent; '—' when missing."""
    if x is None or math.isnan(x):
        return "—"
    return f"{x:.0f}" if abs(x) >= 1e4 else f"{x:.4g}"


def markdown_table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(row) + " |" for row in rows]
    return out


def run_main(body):
    """Common entry: a ResultsError prints its message (naming the file) and exits 1."""
    tool = os.path.basename(sys.argv[0])
    try:
        return body()
    except ResultsError as e:
        print(f"{tool}: {e}", file=sys.stderr)
        return 1


def provenance(runs):
    """The distinct git shas and devices of a set of runs, as one line."""
    shas = sorted({r.git_sha for r in runs})
    devices = sorted({r.device for r in runs})
    return f"git sha {', '.join(shas) or '—'}; device {'; '.join(devices) or '—'}"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("paths", nargs="+", help="results files or directories of *.h5")
    parser.add_argument("--provenance", action="store_true",
                        help="print only the git shas and devices of the files, on one line")
    parser.add_argument("--scenes-with", metavar="PIPELINES",
                        help="print only the scenes with a complete run of one of these pipelines (comma-separated)")
    parser.add_argument("--scenes-checked", action="store_true",
                        help="print only the scenes with a complete run checked against the oracle (run --check)")
    args = parser.parse_args()

    def body():
        complete, incomplete = load(args.paths)
        if args.provenance:
            print(provenance(complete + incomplete))
            return 0
        if args.scenes_with is not None:
            wanted = set(args.scenes_with.split(","))
            for scene in sorted({r.scene for r in complete if r.pipeline in wanted}):
                print(scene)
            return 0
        if args.scenes_checked:
            checked = {r.scene for r in complete if "checked" in r.frames and r.frames["checked"].any()}
            for scene in sorted(checked):
                print(scene)
            return 0
        rows = []
        for r in sorted(complete + incomplete, key=lambda r: r.path):
            status = "complete" if r.complete else r.incomplete_reason()
            rows.append([f"`{r.path}`", r.scene, r.pipeline, f"{r.triangles:,}", r.device,
                         r.git_sha, f"{r.rows}", status])
        print("\n".join(markdown_table(["file", "scene", "pipeline", "triangles", "device",
                                        "git sha", "frames", "status"], rows)))
        return 0
    return run_main(body)


if __name__ == "__main__":
    sys.exit(main())
