#!/usr/bin/python3
"""docs/results-format.md against a results file: every root attribute, /frames, /plans,
/passes and /memory dataset and /summary attribute the file has is documented in its section, and every name
documented there is in the file (`error` only in incomplete files, /plans only in a front
pipeline's, pairs by query only for scenes that declare queries). A group's attributes other than its description are documented as `@name`. Prints each difference and exits 1.

  results_format_check.py docs/results-format.md RUN.h5
"""
import re
import sys

import h5py

SECTIONS = {"## Root attributes": "/", "## `/frames/`": "frames", "## `/summary`": "summary", "## `/plans/`": "plans",
            "## `/passes/`": "passes", "## `/memory/`": "memory"}
ABSENT_WHEN_COMPLETE = {"error"}
# Only in files of scenes that declare queries.
ONLY_WITH_QUERIES = {"pairs_self", "pairs_inter", "pairs_self_mean", "pairs_inter_mean"}


def documented(doc):
    """{section: [regex]} from the first cell of each table row of the three sections."""
    names, section = {}, None
    for line in doc.splitlines():
        if line.startswith("## "):
            section = next((key for title, key in SECTIONS.items() if line.startswith(title)), None)
            continue
        if section is None or not line.startswith("| `"):
            continue
        for name in re.findall(r"`([^`]+)`", line.split("|")[1]):
            pattern = re.escape(name).replace(re.escape("<phase>"), "[a-z_]+")
            pattern = re.sub(r"\\\{([^}]*)\\\}", lambda m: "(" + m.group(1).replace(",", "|") + ")", pattern)
            names.setdefault(section, []).append(pattern)
    return names


def main():
    doc_path, h5_path = sys.argv[1], sys.argv[2]
    with open(doc_path, encoding="utf-8") as f:
        doc = documented(f.read())
    problems = []
    with h5py.File(h5_path, "r") as f:
        present = {"/": list(f.attrs), "frames": list(f["frames"]), "summary": list(f["summary"].attrs)}
        queries = "pairs_self" in f["frames"]
        for group in ("plans", "passes", "memory"):
            if group in f:
                present[group] = list(f[group]) + [f"@{a}" for a in f[group].attrs if a != "description"]
        for section, names in present.items():
            patterns = doc.get(section, [])
            for name in names:
                if not any(re.fullmatch(p, name) for p in patterns):
                    problems.append(f"{section}: {name} is in the file but not documented")
            for p in patterns:
                optional = ABSENT_WHEN_COMPLETE | (set() if queries else ONLY_WITH_QUERIES)
                if not any(re.fullmatch(p, n) for n in names) and p not in optional:
                    problems.append(f"{section}: {p} is documented but not in the file")
        groups = sorted(f.keys())
    if not {"frames", "summary", "passes", "memory"} <= set(groups) <= {"frames", "pairs", "plans", "passes", "summary",
                                                                        "memory"}:
        problems.append(f"groups {groups}, documented: frames, summary, passes, memory, pairs (with --save-pairs), "
                        "plans (front pipelines)")
    for p in problems:
        print(p)
    print(f"{len(problems)} differences between {doc_path} and {h5_path}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
