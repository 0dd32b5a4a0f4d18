"""The Python module against the exact oracle on the host (docs/library.md "Python").

Run by ctest (python_module) as /usr/bin/python3 -m unittest, with PYTHONPATH the built
module's directory.
"""
import ctypes
import ctypes.util
import unittest

import numpy as np

import cdbench


def cloth(n):
    """An n x n grid of quads, two triangles each."""
    faces = []
    for i in range(n):
        for j in range(n):
            v = i * (n + 1) + j
            faces += [(v, v + 1, v + n + 1), (v + 1, v + n + 2, v + n + 1)]
    return np.array(faces, dtype=np.int64)


def waving(n, frame, dtype=np.float32):
    """The cloth's vertices at a frame: a wave steep enough to fold it onto itself."""
    x, y = np.meshgrid(np.linspace(0.0, 1.0, n + 1), np.linspace(0.0, 1.0, n + 1))
    t = 0.3 * frame
    px = x + 0.08 * np.sin(6.0 * y + t)
    pz = 0.1 * np.sin(9.0 * x - 2.0 * t)
    return np.stack([px.ravel(), y.ravel(), pz.ravel()], axis=1).astype(dtype)


class AgainstTheOracle(unittest.TestCase):
    n = 10
    frames = 6

    def check(self, topology, frames, skip_adjacent=False, **options):
        for pipeline in cdbench.pipelines():
            with self.subTest(pipeline=pipeline, skip_adjacent=skip_adjacent):
                bp = cdbench.BroadPhase(topology, pipeline=pipeline, skip_adjacent=skip_adjacent, **options)
                for f, positions in enumerate(frames):
                    stats = bp.run(positions)
                    pairs = bp.pairs()
                    expected = cdbench.oracle_pairs(topology, positions, skip_adjacent)
                    self.assertEqual(pairs.dtype, np.uint32)
                    self.assertEqual(pairs.shape[1], 2)
                    np.testing.assert_array_equal(pairs, expected, err_msg=f"frame {f}")
                    self.assertEqual(stats["pairs"], len(expected))
                    self.assertEqual(stats, bp.stats)

    def test_every_pipeline_on_a_moving_cloth(self):
        topology = cdbench.Topology(cloth(self.n))
        frames = [waving(self.n, f) for f in range(self.frames)]
        self.assertTrue(all(len(cdbench.oracle_pairs(topology, p, True)) > 0 for p in frames))
        for skip in (False, True):
            self.check(topology, frames, skip_adjacent=skip)

    def test_pairs_change_from_frame_to_frame(self):
        topology = cdbench.Topology(cloth(self.n))
        counts = {len(cdbench.oracle_pairs(topology, waving(self.n, f), True)) for f in range(self.frames)}
        self.assertGreater(len(counts), 1, "the wave must change the pairs, or the frames test little")

    def test_doubles_and_fp64(self):
        topology = cdbench.Topology(cloth(self.n))
        # Far from the origin, where float32 alone blurs the cloth: fp64 rebases the doubles.
        frames = [waving(self.n, f, np.float64) + 1e5 for f in range(3)]
        for positions in frames:
            bp = cdbench.BroadPhase(topology, pipeline="c", box_precision="fp64", skip_adjacent=True)
            bp.run(positions)
            missed = set(map(tuple, cdbench.oracle_pairs(topology, positions, True))) - set(map(tuple, bp.pairs()))
            self.assertEqual(missed, set(), "fp64 boxes are conservative against the double geometry")

    def test_boxes(self):
        rng = np.random.default_rng(7)
        count = 300
        topology = cdbench.Topology.boxes(count)
        frames = []
        for f in range(4):
            lo = rng.random((count, 3), dtype=np.float32)
            hi = lo + 0.08 * rng.random((count, 3), dtype=np.float32)
            frames.append(np.stack([lo, hi], axis=1).reshape(2 * count, 3))
        self.check(topology, frames)
        # A box pairs with another exactly when they overlap on every axis.
        lo, hi = frames[-1][0::2], frames[-1][1::2]
        overlap = np.all((lo[:, None, :] <= hi[None, :, :]) & (lo[None, :, :] <= hi[:, None, :]), axis=2)
        i, j = np.nonzero(np.triu(overlap, 1))
        np.testing.assert_array_equal(cdbench.oracle_pairs(topology, frames[-1]), np.stack([i, j], axis=1))

    def test_declared_queries(self):
        faces = cloth(self.n)
        half = len(faces) // 2
        topology = cdbench.Topology(faces, objects=[("top", 0, half), ("bottom", half, len(faces) - half)],
                                    inter_queries=[(0, 1)])
        frames = [waving(self.n, f) for f in range(3)]
        for positions in frames:
            for a, b in cdbench.oracle_pairs(topology, positions):
                self.assertTrue(a < half <= b, "only pairs between the two objects")
        self.check(topology, frames)

    def test_margin_only_adds_pairs(self):
        topology = cdbench.Topology(cloth(self.n))
        positions = waving(self.n, 2)
        exact = set(map(tuple, cdbench.oracle_pairs(topology, positions)))
        bp = cdbench.BroadPhase(topology, pipeline="bvh", margin=0.05)
        bp.run(positions)
        fat = set(map(tuple, bp.pairs()))
        self.assertTrue(exact < fat)


class Errors(unittest.TestCase):
    def setUp(self):
        self.topology = cdbench.Topology(cloth(3))

    def test_unknown_names(self):
        with self.assertRaisesRegex(cdbench.Error, r"unknown pipeline 'nope' \(known: bvh, "):
            cdbench.BroadPhase(self.topology, pipeline="nope")
        with self.assertRaisesRegex(cdbench.Error, "unknown device 'gpu'"):
            cdbench.BroadPhase(self.topology, executor="gpu")
        with self.assertRaisesRegex(cdbench.Error, "fp32"):
            cdbench.BroadPhase(self.topology, box_precision="fp16")
        self.assertTrue(issubclass(cdbench.Error, RuntimeError))

    def test_bad_topology(self):
        with self.assertRaisesRegex(cdbench.Error, r"triangle 0 has vertex 5, but the topology has 4 vertices"):
            cdbench.BroadPhase(cdbench.Topology(np.array([[0, 1, 5]]), num_vertices=4))
        with self.assertRaisesRegex(cdbench.Error, r"shape \(triangles, 3\), got \(2, 2\)"):
            cdbench.Topology(np.zeros((2, 2), dtype=np.int32))
        with self.assertRaisesRegex(cdbench.Error, "must hold integers"):
            cdbench.Topology(np.zeros((2, 3), dtype=np.float32))
        with self.assertRaisesRegex(cdbench.Error, "vertex index -1"):
            cdbench.Topology(np.array([[0, 1, -1]]))

    def test_bad_frames(self):
        bp = cdbench.BroadPhase(self.topology, pipeline="sweep")
        with self.assertRaisesRegex(cdbench.Error, "frame has 3 vertices, topology has 16"):
            bp.run(np.zeros((3, 3), dtype=np.float32))
        with self.assertRaisesRegex(cdbench.Error, r"shape \(vertices, 3\), got \(16, 2\)"):
            bp.run(np.zeros((16, 2), dtype=np.float32))
        with self.assertRaisesRegex(cdbench.Error, "device_pairs: the executor is cpu"):
            bp.device_pairs()

    def test_device_memory_needs_cuda(self):
        class OnDevice:
            __cuda_array_interface__ = {"shape": (16, 3), "typestr": "<f4", "data": (0, True), "version": 2}

        bp = cdbench.BroadPhase(self.topology)
        with self.assertRaisesRegex(cdbench.Error, "need executor 'cuda'; this one is 'cpu'"):
            bp.run(OnDevice())

    def test_cuda_without_a_gpu(self):
        available, reason = cdbench.cuda_available()
        if available:
            self.skipTest("a GPU is present: executor 'cuda' runs")
        with self.assertRaisesRegex(cdbench.Error, "--device cuda: "):
            cdbench.BroadPhase(self.topology, executor="cuda")


class DeviceArray:
    """float32 device memory through the CUDA runtime (ctypes), exposing __cuda_array_interface__
    as CuPy or PyTorch do, so the test needs neither."""

    def __init__(self, cudart, host, stream):
        self.cudart, self.ptr, self.shape = cudart, ctypes.c_void_p(), host.shape
        assert cudart.cudaMalloc(ctypes.byref(self.ptr), ctypes.c_size_t(host.nbytes)) == 0
        self.stream = stream
        self.write(host)

    def write(self, host):
        # Asynchronous on the stream: the frame must wait for it on the device.
        assert self.cudart.cudaMemcpyAsync(self.ptr, host.ctypes.data_as(ctypes.c_void_p),
                                           ctypes.c_size_t(host.nbytes), 1, self.stream) == 0

    @property
    def __cuda_array_interface__(self):
        return {"shape": self.shape, "typestr": "<f4", "data": (self.ptr.value, False), "version": 3,
                "strides": None, "stream": self.stream.value or 1}


class OnCuda(unittest.TestCase):
    def setUp(self):
        available, reason = cdbench.cuda_available()
        if not available:
            self.skipTest(reason)
        self.cudart = ctypes.CDLL(ctypes.util.find_library("cudart") or "/usr/local/cuda/lib64/libcudart.so")
        self.stream = ctypes.c_void_p()
        assert self.cudart.cudaStreamCreate(ctypes.byref(self.stream)) == 0

    def test_device_frames_read_in_place(self):
        n = 12
        topology = cdbench.Topology(cloth(n))
        for pipeline in ("c", "bvh", "sweep"):
            bp = cdbench.BroadPhase(topology, pipeline=pipeline, executor="cuda", skip_adjacent=True)
            device = DeviceArray(self.cudart, waving(n, 0), self.stream)
            for f in range(5):
                positions = waving(n, f)
                device.write(positions)
                stats = bp.run(device)
                expected = cdbench.oracle_pairs(topology, positions, True)
                np.testing.assert_array_equal(bp.pairs(), expected, err_msg=f"{pipeline} frame {f}")
                self.assertEqual(stats["pairs"], len(expected))
                pairs = bp.device_pairs()
                cai = pairs.__cuda_array_interface__
                self.assertEqual(cai["shape"], (len(expected), 2))
                host = np.empty((len(expected), 2), dtype=np.uint32)
                assert self.cudart.cudaMemcpy(host.ctypes.data_as(ctypes.c_void_p), ctypes.c_void_p(cai["data"][0]),
                                              ctypes.c_size_t(host.nbytes), 2) == 0
                np.testing.assert_array_equal(host[np.lexsort((host[:, 1], host[:, 0]))], expected)
            # Host arrays still work on executor cuda (uploaded).
            bp.run(waving(n, 1))
            np.testing.assert_array_equal(bp.pairs(), cdbench.oracle_pairs(topology, waving(n, 1), True))


if __name__ == "__main__":
    unittest.main()
