"""The Python module on executor "cuda" with device arrays, against the exact oracle.

    PYTHONPATH=<the module's directory> python3 tests/python/check_cuda.py [--executor cpu]

Run on the GPU machine by bench/api_check.sh, not by ctest. Each device array library that
imports and sees a GPU, in this order: CuPy, PyTorch, Numba, and always a raw object exposing
__cuda_array_interface__ over memory allocated through libcudart (ctypes). For each, a cloth's
frames are written into one device array, in place, and the array itself is passed to
BroadPhase.run; the pairs (bp.pairs() and bp.device_pairs()) must equal cdbench.oracle_pairs
on every frame. That the module reads the array where it lies, without a copy: the array's
pointer never changes while the pairs follow what was written into that memory just before each
call (they change from frame to frame), and the raw object offers nothing but its device
address to read. Every library that imports must work (the raw object always runs); one that
imports but cannot use the GPU is a failure.

--executor cpu runs the same checks with NumPy arrays read in place on the host executor, so
that the script itself is tested on a machine without a GPU. Prints PASS/FAIL lines; exits 1
on any failure.
"""
import argparse
import ctypes
import ctypes.util
import sys

import numpy as np

import cdbench
from test_cdbench import cloth, waving

N = 24  # quads per side: 1,152 triangles, enough for the pairs to change as the cloth folds
PIPELINES = ("c", "bvh", "grid")


class Cudart:
    """The CUDA runtime through ctypes: the raw array's memory, and copies of device pairs."""

    def __init__(self):
        candidates = [ctypes.util.find_library("cudart"), "libcudart.so", "/usr/local/cuda/lib64/libcudart.so"]
        candidates += [f"/usr/local/cuda/lib64/libcudart.so.{v}" for v in (13, 12)]
        errors = []
        for name in filter(None, candidates):
            try:
                self.lib = ctypes.CDLL(name)
                self.name = name
                return
            except OSError as e:
                errors.append(f"{name}: {e}")
        raise RuntimeError("libcudart not found (" + "; ".join(errors) + ")")

    def check(self, status, what):
        if status != 0:
            raise RuntimeError(f"{what}: CUDA error {status}")

    def malloc(self, nbytes):
        ptr = ctypes.c_void_p()
        self.check(self.lib.cudaMalloc(ctypes.byref(ptr), ctypes.c_size_t(nbytes)), "cudaMalloc")
        return ptr.value

    def to_device(self, ptr, host):
        self.check(self.lib.cudaMemcpy(ctypes.c_void_p(ptr), host.ctypes.data_as(ctypes.c_void_p),
                                       ctypes.c_size_t(host.nbytes), 1), "cudaMemcpy to the device")

    def to_host(self, host, ptr):
        self.check(self.lib.cudaMemcpy(host.ctypes.data_as(ctypes.c_void_p), ctypes.c_void_p(ptr),
                                       ctypes.c_size_t(host.nbytes), 2), "cudaMemcpy to the host")

    def device_pairs(self, device_pairs):
        cai = device_pairs.__cuda_array_interface__
        host = np.empty(cai["shape"], dtype=np.uint32)
        if host.size:
            self.to_host(host, cai["data"][0])
        return host


class RawArray:
    """float32 (V, 3) device memory of its own, exposing __cuda_array_interface__ and nothing else."""

    def __init__(self, cudart, shape):
        self.shape = shape
        self.ptr = cudart.malloc(int(np.prod(shape)) * 4)

    @property
    def __cuda_array_interface__(self):
        return {"shape": self.shape, "typestr": "<f4", "data": (self.ptr, False), "version": 3,
                "strides": None, "stream": None}


# Each library: how to make a device array of a host one, overwrite it in place, read its
# pointer, and read device pairs back. write() copies into the array's own memory.
class CuPy:
    name = "CuPy"

    def __init__(self, cudart):
        import cupy
        cupy.cuda.runtime.getDeviceCount()
        self.cupy = cupy

    def make(self, host):
        return self.cupy.asarray(host)

    def write(self, array, host):
        array.set(host)

    def pointer(self, array):
        return array.data.ptr

    def pairs(self, device_pairs):
        return self.cupy.asnumpy(self.cupy.asarray(device_pairs))


class Torch:
    name = "PyTorch"

    def __init__(self, cudart):
        import torch
        if not torch.cuda.is_available():
            raise RuntimeError("torch.cuda.is_available() is False")
        self.torch, self.cudart = torch, cudart

    def make(self, host):
        return self.torch.from_numpy(host).to("cuda")

    def write(self, array, host):
        array.copy_(self.torch.from_numpy(host))

    def pointer(self, array):
        return array.data_ptr()

    def pairs(self, device_pairs):
        # PyTorch's uint32 support is partial: read the memory through the runtime if it loaded.
        if self.cudart:
            return self.cudart.device_pairs(device_pairs)
        return self.torch.as_tensor(device_pairs, device="cuda").cpu().numpy()


class Numba:
    name = "Numba"

    def __init__(self, cudart):
        from numba import cuda
        if not cuda.is_available():
            raise RuntimeError("numba.cuda.is_available() is False")
        self.cuda = cuda

    def make(self, host):
        return self.cuda.to_device(host)

    def write(self, array, host):
        array.copy_to_device(host)

    def pointer(self, array):
        return array.__cuda_array_interface__["data"][0]

    def pairs(self, device_pairs):
        return self.cuda.as_cuda_array(device_pairs).copy_to_host()


class Raw:
    name = "raw __cuda_array_interface__ (ctypes + libcudart)"

    def __init__(self, cudart):
        self.cudart = cudart

    def make(self, host):
        array = RawArray(self.cudart, host.shape)
        self.write(array, host)
        return array

    def write(self, array, host):
        self.cudart.to_device(array.ptr, np.ascontiguousarray(host))

    def pointer(self, array):
        return array.ptr

    def pairs(self, device_pairs):
        return self.cudart.device_pairs(device_pairs)


class NumPyInPlace:
    """--executor cpu: a NumPy array read in place by the host executor."""
    name = "NumPy (host executor)"

    def make(self, host):
        return host.copy()

    def write(self, array, host):
        array[...] = host

    def pointer(self, array):
        return array.ctypes.data

    def pairs(self, device_pairs):
        raise AssertionError("no device pairs on the host executor")


def sorted_pairs(pairs):
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))] if len(pairs) else pairs.reshape(0, 2)


class Report:
    def __init__(self):
        self.failures = 0

    def line(self, ok, what):
        print(("PASS " if ok else "FAIL ") + what, flush=True)
        if not ok:
            self.failures += 1
        return ok


def check_library(report, library, executor, frames):
    topology = cdbench.Topology(cloth(N))
    on_device = executor == "cuda"
    for pipeline in PIPELINES:
        what = f"{library.name}, pipeline {pipeline} on {executor}"
        try:
            bp = cdbench.BroadPhase(topology, pipeline=pipeline, executor=executor, skip_adjacent=True)
            array = library.make(waving(N, 0))
            pointer = library.pointer(array)
            counts, uploads, problems = [], [], []
            for f in range(frames):
                positions = waving(N, f)
                library.write(array, positions)
                if library.pointer(array) != pointer:
                    problems.append(f"frame {f}: the array moved")
                stats = bp.run(array)
                expected = cdbench.oracle_pairs(topology, positions, skip_adjacent=True)
                counts.append(len(expected))
                if not np.array_equal(bp.pairs(), expected):
                    problems.append(f"frame {f}: pairs() differ from the oracle ({stats['pairs']} against {len(expected)})")
                uploads.append(stats["upload_ms"])
                if on_device:
                    device = sorted_pairs(library.pairs(bp.device_pairs()))
                    if not np.array_equal(device, expected):
                        problems.append(f"frame {f}: device_pairs() differ from the oracle")
            if len(set(counts)) < 2:
                problems.append(f"the pairs did not change over the frames ({counts[0]} each): in place not shown")
            if on_device:
                # The same BroadPhase still takes host frames (uploaded).
                positions = waving(N, 1)
                bp.run(positions)
                if not np.array_equal(bp.pairs(), cdbench.oracle_pairs(topology, positions, skip_adjacent=True)):
                    problems.append("a NumPy frame on cuda: pairs differ from the oracle")
            report.line(not problems, f"{what}: {frames} frames in place at 0x{pointer:x}, pairs {min(counts)}..{max(counts)}, "
                        f"upload_ms mean {np.mean(uploads):.4f}" + ("" if not problems else ": " + "; ".join(problems)))
        except Exception as e:  # a library that imports but cannot run is a failure, said in its words
            report.line(False, f"{what}: {type(e).__name__}: {e}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--executor", choices=("cuda", "cpu"), default="cuda")
    parser.add_argument("--frames", type=int, default=8)
    args = parser.parse_args()
    report = Report()
    available, reason = cdbench.cuda_available()
    print(f"cdbench module {cdbench.__file__}; cuda_available: {available} {reason}".rstrip())
    if args.executor == "cpu":
        check_library(report, NumPyInPlace(), "cpu", args.frames)
    elif report.line(available, f"executor cuda can run{'' if available else ': ' + reason}"):
        cudart = None
        try:
            cudart = Cudart()
            print(f"libcudart: {cudart.name}")
        except RuntimeError as e:
            report.line(False, f"raw CUDA arrays: {e}")
        used = []
        for kind in (CuPy, Torch, Numba, Raw):
            try:
                library = kind(cudart)
            except ImportError as e:
                print(f"skip {kind.name}: {e}")
                continue
            except Exception as e:
                report.line(False, f"{kind.name} imports but cannot use the GPU: {type(e).__name__}: {e}")
                continue
            used.append(kind.name)
            check_library(report, library, "cuda", args.frames)
        print(f"device arrays checked: {', '.join(used) if used else 'none'}")
    print(f"check_cuda: {'PASS' if report.failures == 0 else f'FAIL ({report.failures} failed)'}")
    return 1 if report.failures else 0


if __name__ == "__main__":
    sys.exit(main())
