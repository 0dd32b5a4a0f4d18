#!/usr/bin/env bash
# docs/usage.md against the program: every command's options (from `cdbench CMD --help`,
# every subcommand `cdbench --help` lists, nested ones too) named in it; every --option it
# names is one of cdbench's, and one of the command it attributes it to; its exit-code
# tables against app/exit_codes.h and the exit codes the help texts mention; the order of
# the help's headings; README's plot paragraph against its sample output. Reads only:
# the binary is asked for --help and nothing runs.
set -u
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

"$python" - "$cdbench" "$root/docs/usage.md" "$root/app/exit_codes.h" >"$tmp/docs.out" 2>&1 <<'PY'
import re, subprocess, sys

binary, usage_path, codes_path = sys.argv[1:4]
usage = open(usage_path, encoding="utf-8").read()
usage_lines = usage.splitlines()

# Words starting with -- in docs/usage.md that are not cdbench options: each is an option of
# another program the page shows, and must still be on the page and not become cdbench's.
NOT_CDBENCH = {
    "--a": "bench/interleave.sh: the baseline binary",
    "--b": "bench/interleave.sh: the new binary (also scripts/ab_frames.py's B side)",
    "--b-args": "bench/interleave.sh: run options for the B side only",
    "--rounds": "bench/interleave.sh: processes a side",
    "--no-replay": "bench/interleave.sh: lets each process plan its own fronts",
    "--compare-args": "bench/interleave.sh: options passed on to compare",
    "--plot": "scripts/ab_frames.py: the frame-by-frame plot",
    "--summary": "scripts/read_results.py: the summary of a results file",
    "--params": "scripts/read_results.py: the parameters of a results file",
    "--python": "scripts/install-deps.sh: h5py, numpy and matplotlib",
    "--scenes": "scripts/install-deps.sh: assimp's test models",
    "--scenes-extra": "scripts/install-deps.sh: glmark2-data and libcgal-demo",
}
# Commands whose help headings are known to be out of the documented order; each entry
# must still be out of order (remove it once the help is fixed).
KNOWN_HEADING_ORDER = {}
# Each exit code's word in docs/usage.md's table, per constant of app/exit_codes.h; the word
# must also be in the constant's name or its comment there, so neither side drifts alone.
MEANING = {"Ok": "success", "Failure": "failed", "Usage": "usage", "signal": "signal"}

failures = 0
def ok(name): print("ok   " + name)
def fail(name, detail=""):
    global failures
    failures += 1
    print("FAIL " + name + (": " + detail if detail else ""))

OPT = re.compile(r"(?<![\w-])--[a-zA-Z][a-zA-Z0-9-]*")
def opts_in(text): return [m.group(0).rstrip("-") for m in OPT.finditer(text)]

# --- the help of every command -------------------------------------------------------
def help_of(path):
    r = subprocess.run([binary, *path, "--help"], capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"cdbench {' '.join(path)} --help exits 0", f"rc={r.returncode}")
    return r.stdout + r.stderr

HEADING = re.compile(r"^(\S[^:]*):\s*$")
OPTION_LINE = re.compile(r"^  (?:-[a-zA-Z],)?(--[a-zA-Z][a-zA-Z0-9-]*(?:,--[a-zA-Z][a-zA-Z0-9-]*)*)")
commands = {}  # "scenes info" -> {"options": {...}, "headings": [...], "subs": [...], "text": ...}
def read_command(path):
    text = help_of(path)
    options, headings, subs, heading = {}, [], [], None
    for line in text.splitlines():
        h = HEADING.match(line)
        if h:
            heading = h.group(1); continue
        m = OPTION_LINE.match(line)
        if m:
            for name in m.group(1).split(","):
                options[name] = heading
            if heading not in ("Options", None) and heading not in headings:
                headings.append(heading)
        elif heading == "Subcommands" and re.match(r"^  [a-z]", line):
            subs.append(line.split()[0])
    key = " ".join(path)
    commands[key] = {"options": options, "headings": headings, "subs": subs, "text": text}
    for s in subs:
        read_command(path + [s])
read_command([])
names = sorted(k for k in commands if k)
print("commands: " + ", ".join(names))
if len(names) < 6:
    fail("cdbench --help lists its commands", "found " + ", ".join(names))
every_option = set().union(*(c["options"] for c in commands.values()))

# --- every command and every option of its help in docs/usage.md ---------------------
doc_opts = set(opts_in(usage))
for key in names:
    if f"`{key}" not in usage and f"cdbench {key}" not in usage:
        fail(f"docs/usage.md names the command `{key}`")
for key in [""] + names:
    missing = sorted(o for o in commands[key]["options"] if o not in doc_opts)
    what = f"cdbench {key} --help".replace("  ", " ")
    if missing: fail(f"every option of `{what}` in docs/usage.md", "missing " + ", ".join(missing))
    else: ok(f"every option of `{what}` in docs/usage.md ({len(commands[key]['options'])})")

# --- every --option of docs/usage.md is one of cdbench's -----------------------------
unknown = []
for n, line in enumerate(usage_lines, 1):
    for o in opts_in(line):
        if o not in every_option and o not in NOT_CDBENCH:
            unknown.append(f"{o} (line {n})")
if unknown: fail("every --option in docs/usage.md is a cdbench option or listed as another program's", ", ".join(unknown))
else: ok("every --option in docs/usage.md is a cdbench option or listed as another program's")
stale = [o for o in NOT_CDBENCH if o not in doc_opts or o in every_option]
if stale: fail("the list of other programs' options is current", "remove " + ", ".join(stale))
else: ok("the list of other programs' options is current")

# --- options docs/usage.md attributes to a command -----------------------------------
# A code span or a command line of a code block that starts with a command (`run --out`,
# `./scripts/cdbench verify --pairs DIR`, `scenes --scenes-dir DIR info ...`): every
# --option in it belongs to the command it follows, subcommands descended as the program
# parses them, up to a shell separator (; && > # or a bare --).
def attribute(tokens, where, out):
    path, depth = [], 0
    for t in tokens:
        if t in ("&&", ">", ">>", "--") or t.startswith("#"):
            break
        last = ";" in t
        t = t.split(";")[0]
        if t == "|" and depth == 0:
            break
        depth += t.count("[") - t.count("]")
        word = t.strip("[]")
        key = " ".join(path)
        o = re.match(r"--[a-zA-Z][a-zA-Z0-9-]*", word)
        if o:
            out.append((key, o.group(0).rstrip("-"), where))
        elif word in commands[key]["subs"]:
            path.append(word)
        if last:
            break
spans, in_fence, prose = [], False, []  # prose: the lines outside code blocks, blank inside
for n, line in enumerate(usage_lines, 1):
    if line.startswith("```"):
        in_fence = not in_fence; prose.append(""); continue
    prose.append("" if in_fence else line)
    if in_fence:
        tokens = line.split()
        if tokens and tokens[0] == "$": tokens = tokens[1:]
        if tokens and tokens[0].endswith("cdbench"):
            spans.append((tokens[1:], f"line {n}"))
prose_text = "\n".join(prose)
for m in re.finditer(r"`([^`]+)`", prose_text):  # a span may go on to the next line
    tokens = m.group(1).split()
    if tokens and tokens[0].endswith("cdbench"): tokens = tokens[1:]
    elif not tokens or tokens[0] not in commands[""]["subs"]: continue
    spans.append((tokens, f"line {prose_text.count(chr(10), 0, m.start()) + 1}"))
attributed = []
for tokens, where in spans:
    attribute(tokens, where, attributed)
# The per-command exit table: a row's options belong to its command or its subcommands.
for n, line in enumerate(usage_lines, 1):
    m = re.match(r"^\| `([a-z]+)` \|(.*)$", line)
    if m and m.group(1) in commands:
        for o in opts_in(m.group(2)):
            attributed.append((m.group(1) + " *", o, f"line {n}"))
wrong = []
for key, o, where in attributed:
    if key.endswith(" *"):
        base = key[:-2]
        known = set().union(*(c["options"] for k, c in commands.items() if k == base or k.startswith(base + " ")))
        key = base
    else:
        known = commands[key]["options"]
    if o not in known:
        wrong.append(f"{o} is not an option of `cdbench {key}` ({where})".replace("  ", " "))
if wrong: fail(f"options attributed to a command are its own ({len(attributed)} checked)", "; ".join(wrong))
else: ok(f"options attributed to a command are its own ({len(attributed)} checked)")

# --- the exit codes ------------------------------------------------------------------
header = open(codes_path, encoding="utf-8").read()
codes = {}  # code text -> (constant, its comment)
comment = []
for line in header.splitlines():
    s = line.strip()
    if s.startswith("//"):
        comment.append(s[2:].strip()); continue
    m = re.match(r"inline constexpr int kExit(\w+) = (\d+);", s)
    if m:
        codes[m.group(2)] = (m.group(1), " ".join(comment))
    m = re.match(r"inline constexpr int exit_for_signal\(int (\w+)\) \{ return (\d+) \+ \1; \}", s)
    if m:
        codes[m.group(2) + " + N"] = ("signal", " ".join(comment))
    comment = [] if not s.startswith("//") else comment
if len(codes) < 4:
    fail("app/exit_codes.h read", f"found {sorted(codes)}")
section = usage.split("\n## Exit codes\n", 1)[1].split("\n## ", 1)[0] if "\n## Exit codes\n" in usage else ""
rows = {}
for line in section.splitlines():
    m = re.match(r"^\| ([0-9][0-9 +N]*?) \| (.*) \|$", line)
    if m: rows[m.group(1)] = m.group(2)
if set(rows) != set(codes):
    fail("docs/usage.md's exit-code table has the codes of app/exit_codes.h",
         f"table {sorted(rows)}, header {sorted(codes)}")
else:
    ok("docs/usage.md's exit-code table has the codes of app/exit_codes.h: " + ", ".join(sorted(codes)))
for code, (name, text) in sorted(codes.items()):
    word = MEANING.get(name)
    if word is None:
        fail(f"exit code {code} (kExit{name}) has a meaning word", "add it to MEANING in this script"); continue
    if word not in (name + " " + text).lower():
        fail(f"exit code {code}: '{word}' is the word of app/exit_codes.h", f"not in kExit{name} or '{text}'")
    row = rows.get(code, "")
    first = re.split(r"[:(;]", row, 1)[0].lower()
    if word in first: ok(f"exit code {code} is '{word}' in docs/usage.md")
    else: fail(f"exit code {code} is '{word}' in docs/usage.md", f"its row says '{first.strip()}'")
    for o in opts_in(text):
        if o in opts_in(row): ok(f"exit code {code}: {o}, named in app/exit_codes.h, in its row")
        else: fail(f"exit code {code}: {o}, named in app/exit_codes.h, in its row")
    for value, sig in re.findall(r"(\d+) for (SIG[A-Z0-9]+)", text):
        if value in row and sig in row: ok(f"exit code {value} for {sig} in docs/usage.md")
        else: fail(f"exit code {value} for {sig} in docs/usage.md")
# The table per command: the same codes as columns, one row for every command.
per = [l for l in section.splitlines() if l.startswith("| command |")]
columns = [c.strip() for c in per[0].strip("|").split("|")][1:] if per else []
if columns != sorted(codes, key=lambda c: (len(c), c)):
    fail("the exit codes per command are the codes of app/exit_codes.h", f"columns {columns}")
else:
    ok("the exit codes per command are the codes of app/exit_codes.h")
cells = {}
for line in section.splitlines():
    m = re.match(r"^\| `([a-z ]+)` \|(.*)\|$", line)
    if m: cells[m.group(1)] = [c.strip() for c in m.group(2).split("|")]
top = commands[""]["subs"]
if sorted(cells) != sorted(top):
    fail("the exit codes per command have a row for every command", f"rows {sorted(cells)}, commands {sorted(top)}")
else:
    ok("the exit codes per command have a row for every command: " + ", ".join(top))
# The exit codes the help texts mention: a code of app/exit_codes.h whose rows (the table
# and the command's cell) name the option that says it.
mentioned = 0
for key in names:
    cur = None
    for line in commands[key]["text"].splitlines():
        m = OPTION_LINE.match(line)
        if m: cur = m.group(1).split(",")[-1]
        elif HEADING.match(line): cur = None
        for code in re.findall(r"\bexits? (?:with )?(\d+)\b", line):
            mentioned += 1
            what = f"`{key} --help`: exit {code}" + (f" ({cur})" if cur else "")
            if code not in codes:
                fail(what + " is a code of app/exit_codes.h"); continue
            top_key = key.split()[0]
            col = columns.index(code) if code in columns else -1
            cell = cells.get(top_key, [])[col] if 0 <= col < len(cells.get(top_key, [])) else ""
            if cur is None or (cur in rows.get(code, "") and cur in cell): ok(what + " agrees with docs/usage.md")
            else: fail(what + " agrees with docs/usage.md", f"{cur} not in the row of {code} and `{top_key}`'s cell")
print(f"exit codes mentioned in help texts: {mentioned}")

# --- the help's headings in the documented order -------------------------------------
m = re.search(r"under headings, in this order: (.*?)(?:;|\.\s)", usage.replace("\n", " "))
documented = [h.strip() for h in re.split(r", | and ", m.group(1))] if m else []
if not documented:
    fail("docs/usage.md gives the help's headings in order ('under headings, in this order: ...')")
else:
    if commands["run"]["headings"] == documented: ok("`run --help`'s headings as docs/usage.md lists them: " + ", ".join(documented))
    else: fail("`run --help`'s headings as docs/usage.md lists them", f"help {commands['run']['headings']}, docs {documented}")
    for key in names:
        hs = [h for h in commands[key]["headings"] if h in documented]
        in_order = hs == sorted(hs, key=documented.index)
        if key in KNOWN_HEADING_ORDER:
            if in_order: fail(f"`{key} --help`'s headings still out of order, as KNOWN_HEADING_ORDER says", "remove the entry")
            else: print(f"known `{key} --help`: {KNOWN_HEADING_ORDER[key]} ({', '.join(hs)})")
        elif in_order: ok(f"`{key} --help`'s headings in the documented order")
        else: fail(f"`{key} --help`'s headings in the documented order", ", ".join(hs))
sys.exit(min(failures, 100))
PY
rc=$?
cat "$tmp/docs.out"
failures=$(grep -c '^FAIL' "$tmp/docs.out")
[[ $rc -ne 0 && $failures -eq 0 ]] && fail "the docs checks stopped (rc=$rc)"
# README's sample output and its CPU plot come from one machine and commit (issue 56: a
# sample of 4.8 ms a frame next to a plot of 30-50 ms from another machine): the plot's
# paragraph names the commit the sample's first line prints, and the machine.
readme=$root/README.md
sample_commit=$(sed -n '/^## Sample output/,/^## /p' "$readme" | grep -oE '^cdbench [0-9.]+ +commit [0-9a-f]{7}' | grep -oE '[0-9a-f]{7}$')
plot_text=$(sed -n '/^## A plot/,/^!\[/p' "$readme" | tr '\n' ' ')
if [[ -n $sample_commit && $plot_text == *"$sample_commit"* && $plot_text =~ (Intel|AMD|Xeon|EPYC|Ryzen|Core|ARM|Neoverse) ]]; then
  echo "ok   README's plot names the machine and the commit of its sample output ($sample_commit)"
else
  fail "README's plot paragraph does not name the machine and the sample output's commit '${sample_commit:-none}'"
fi
finish docs
