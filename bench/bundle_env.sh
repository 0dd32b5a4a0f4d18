# Sourced by the GPU machine's scripts, which run from the repository root: the device
# bundle (BUNDLE, default .devbundle/: bin/ and the libraries its binaries load) on the
# loader's path, the committed scene files for --scene, and out, where the results go
# (OUT, default /tmp/out).
bundle=${BUNDLE:-$PWD/.devbundle}
export LD_LIBRARY_PATH=$bundle/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export CDBENCH_SCENES=$PWD/scenes
out=${OUT:-/tmp/out}
