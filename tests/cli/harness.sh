# Shared by the CLI test scripts (sourced, with no arguments of its own, so $1 is the
# script's: the cdbench binary, as tests/CMakeLists.txt passes it): the repository root, a
# python3 (/usr/bin/python3 first, the one the scripts of docs/plots.md use, with h5py,
# numpy and matplotlib), a temporary directory, the failure count and the checks that
# print "ok" or "FAIL" lines.
cdbench=$1
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
python=/usr/bin/python3
[[ -x $python ]] || python=python3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() {  # fail MESSAGE: count a failure
  echo "FAIL $1"
  failures=$((failures + 1))
}
check() {  # check NAME EXPECTED_RC PATTERN -- CMD...: exit code and a line of the output
  local name=$1 want_rc=$2 pattern=$3; shift 4
  "$@" >"$tmp/out" 2>&1; local rc=$?
  if [[ $rc -ne $want_rc ]] || ! grep -qE -- "$pattern" "$tmp/out"; then
    fail "$name: rc=$rc (want $want_rc), pattern '$pattern'"; sed 's/^/    /' "$tmp/out" | tail -20
  else
    echo "ok   $name"
  fi
}
has() {  # has NAME FILE PATTERN: FILE has a line matching PATTERN
  if grep -qE -- "$3" "$2"; then echo "ok   $1"; else fail "$1: no '$3' in $2"; fi
}
finish() {  # finish WHAT: the summary line and the exit status
  if [[ $failures -ne 0 ]]; then echo "$failures $1 test(s) failed"; exit 1; fi
  echo "all $1 tests passed"
}
