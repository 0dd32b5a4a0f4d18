#!/usr/bin/env bash
# The installed package (docs/library.md): `cmake --install` into a fresh prefix, moved
# elsewhere (the package must be relocatable), then examples/ configured and built out of
# tree against it with find_package(cdbench) alone and run on the CPU: its frames must equal
# the oracle's, and the overhead benchmark's (api_frames) must too, allocating nothing. Also a wrong pipeline name must fail in the library's words. Where the build
# has the Python module: the installed one runs examples/cloth.py, and python/ built on its
# own against the moved prefix passes tests/python.
set -u
build=$1
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL $1"; failures=$((failures + 1)); }

if ! out=$(cmake --install "$build" --prefix "$work/staged" 2>&1); then
  fail "cmake --install:"; tail -5 <<<"$out" | sed 's/^/    /'; exit 1
fi
mv "$work/staged" "$work/prefix"
prefix=$work/prefix
for f in include/cdbench/cdbench.h include/cdbench/pipeline/pipeline.h include/cdbench/core/error.h \
         lib/cmake/cdbench/cdbenchConfig.cmake lib/cmake/cdbench/cdbenchConfigVersion.cmake; do
  [[ -f $prefix/$f ]] && echo "ok   installed $f" || fail "not installed: $f"
done
if grep -rlF -e "$root" -e "$(cd "$build" && pwd)" "$prefix/lib/cmake"; then
  fail "the package names the source or build tree (not relocatable)"
else
  echo "ok   the package names neither the source nor the build tree"
fi

generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if ! out=$(cmake -S "$root/examples" -B "$work/example" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
             -DCMAKE_PREFIX_PATH="$prefix" 2>&1 && cmake --build "$work/example" 2>&1); then
  fail "the example does not configure and build against the package:"; tail -15 <<<"$out" | sed 's/^/    /'
else
  echo "ok   examples/ built against the installed package"
  for pipeline in c bvh sweep; do
    out=$(OMP_NUM_THREADS=2 "$work/example/cloth_loop" "$pipeline" cpu 12 2>&1)
    rc=$?
    if [[ $rc -eq 0 ]] && grep -q "every frame equals the oracle" <<<"$out" && ! grep -q MISMATCH <<<"$out"; then
      echo "ok   cloth_loop $pipeline: every frame equals the oracle"
    else
      fail "cloth_loop $pipeline exited $rc:"; tail -5 <<<"$out" | sed 's/^/    /'
    fi
  done
  # The overhead benchmark on the CPU, few frames: its checked frames equal the oracle, and
  # frames whose buffers did not grow allocate nothing.
  out=$(OMP_NUM_THREADS=2 "$work/example/api_frames" c cpu 8 2 2>&1)
  rc=$?
  if [[ $rc -eq 0 ]] && grep -q "^api_frames c on cpu: PASS" <<<"$out" && grep -q "^  overhead  mean" <<<"$out" &&
     [[ $(grep -c "= oracle" <<<"$out") -ge 3 ]]; then
    echo "ok   api_frames c cpu: $(grep '^  overhead' <<<"$out" | tr -s ' ')"
  else
    fail "api_frames c cpu exited $rc:"; tail -12 <<<"$out" | sed 's/^/    /'
  fi
  out=$("$work/example/api_frames" c cuda 4 1 2>&1)
  rc=$?
  if grep -q "^set(cdbench_CUDA OFF)" "$prefix/lib/cmake/cdbench/cdbenchConfig.cmake"; then
    if [[ $rc -eq 2 ]] && grep -q "api_frames: " <<<"$out"; then
      echo "ok   api_frames on cuda without CUDA: exit 2, $(tail -1 <<<"$out")"
    else
      fail "api_frames c cuda on a package without CUDA: expected exit 2 and a message, got $rc: $out"
    fi
  fi
  out=$("$work/example/cloth_loop" no-such-pipeline cpu 2 2>&1)
  rc=$?
  if [[ $rc -eq 2 ]] && grep -q "unknown pipeline 'no-such-pipeline' (known: bvh," <<<"$out"; then
    echo "ok   an unknown pipeline is an error naming the known ones"
  else
    fail "cloth_loop no-such-pipeline: expected exit 2 and the known names, got $rc: $out"
  fi
fi
# The Python module, where the build has it: installed under the prefix, imported from there.
if [[ -f $build/CMakeCache.txt ]] && grep -q '^CDB_PYTHON:INTERNAL=' "$build/CMakeCache.txt"; then
  python=$(sed -n 's/^CDB_PYTHON:INTERNAL=//p' "$build/CMakeCache.txt")
  modules=$(find "$prefix" -name 'cdbench*.so' -printf '%h\n')
  if [[ $modules != "$prefix/lib/python3/dist-packages" ]]; then
    fail "the Python module is not installed in $prefix/lib/python3/dist-packages (found: ${modules:-none})"
  else
    out=$(cd "$work" && PYTHONPATH=$modules OMP_NUM_THREADS=2 "$python" "$root/examples/cloth.py" sweep 2>&1)
    rc=$?
    if [[ $rc -eq 0 ]] && grep -q "sweep: every frame equals the oracle" <<<"$out"; then
      echo "ok   examples/cloth.py on the installed module: every frame equals the oracle"
    else
      fail "examples/cloth.py exited $rc:"; tail -5 <<<"$out" | sed 's/^/    /'
    fi
  fi
  # python/ on its own against the package, as on a machine with another Python: configured
  # with find_package(cdbench) and Debian's pybind11, then tests/python run on what it built.
  if ! out=$(cmake -S "$root/python" -B "$work/python" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
               -DCMAKE_PREFIX_PATH="$prefix" -DPython_EXECUTABLE="$python" 2>&1 &&
             cmake --build "$work/python" 2>&1); then
    fail "python/ does not configure and build on its own against the package:"; tail -15 <<<"$out" | sed 's/^/    /'
  elif ! grep -qxF "cdbench_DIR:PATH=$prefix/lib/cmake/cdbench" "$work/python/CMakeCache.txt"; then
    fail "python/ on its own did not take cdbench from the package: $(grep '^cdbench_DIR' "$work/python/CMakeCache.txt")"
  else
    echo "ok   python/ built on its own against the installed package"
    out=$(cd "$root/tests/python" && PYTHONPATH=$work/python OMP_NUM_THREADS=2 "$python" -m unittest test_cdbench 2>&1)
    rc=$?
    if [[ $rc -eq 0 ]] && grep -q "^OK" <<<"$out"; then
      echo "ok   tests/python on the module built on its own: $(tail -1 <<<"$out")"
    else
      fail "tests/python on the module built on its own exited $rc:"; tail -15 <<<"$out" | sed 's/^/    /'
    fi
  fi
else
  echo "ok   no Python module in this build (pybind11 not found): its install not checked"
fi
# bench/api_check.sh, the GPU machine's check, on the host executor against the same moved
# prefix (with the CLI beside it, and the Python module built on its own): every step passes.
# Then on "cuda", which this package or machine lacks: steps fail, and the script says so.
if [[ -n ${python:-} && -x $build/app/cdbench ]]; then
  check=(env PREFIX="$prefix" OUT="$work/api_check" PYTHON="$python" JOBS=2 LONG_FRAMES=12 OMP_NUM_THREADS=2
         CDBENCH="$build/app/cdbench" bash "$root/bench/api_check.sh")
  out=$(cd "$root" && EXECUTOR=cpu "${check[@]}" 2>&1)
  rc=$?
  steps=$(grep -c "^PASS " <<<"$out")
  if [[ $rc -eq 0 ]] && grep -q "^api_check: $steps passed, 0 failed" <<<"$out" && ((steps >= 13)) &&
     grep -q "^PASS cli-api-same-pairs" <<<"$out" && grep -q "^PASS python-check-cpu" <<<"$out" &&
     [[ -s $work/api_check/api_check.log ]]; then
    echo "ok   bench/api_check.sh on cpu: $steps steps passed, the CLI's pairs equal the API's"
  else
    fail "bench/api_check.sh on cpu exited $rc:"; grep -E "^(FAIL|api_check)" <<<"$out" | sed 's/^/    /'
  fi
  if ! cdb_cuda_available=$(PYTHONPATH=$work/python "$python" -c 'import cdbench; print(cdbench.cuda_available()[0])'); then
    fail "cdbench.cuda_available() did not run"
  elif [[ $cdb_cuda_available == False ]]; then
    out=$(cd "$root" && EXECUTOR=cuda "${check[@]}" 2>&1)
    rc=$?
    if [[ $rc -eq 1 ]] && grep -q "^FAIL cloth_loop-c" <<<"$out" && grep -q "^FAIL python-check-cuda" <<<"$out" &&
       grep -Eq "^api_check: [0-9]+ passed, [1-9][0-9]* failed" <<<"$out"; then
      echo "ok   bench/api_check.sh on cuda without a GPU: exit 1, $(grep -E '^api_check: [0-9]+ passed' <<<"$out")"
    else
      fail "bench/api_check.sh on cuda without a GPU: expected exit 1 and FAIL lines, got $rc:"
      tail -8 <<<"$out" | sed 's/^/    /'
    fi
  fi
fi
if ((failures)); then echo "$failures install test(s) failed"; exit 1; fi
echo "all install tests passed"
