// The Python module `cdbench`: the public API (cdbench/cdbench.h) with NumPy arrays in and
// out on the host, and on executor "cuda" any object with __cuda_array_interface__ read in
// place (docs/library.md "Python"). Failures raise cdbench.Error (a RuntimeError) with the
// library's message.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "cdbench/cdbench.h"

namespace py = pybind11;
using cdb::fail;

namespace {

std::string shape_text(const py::array& a) {
  std::string s;
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return "(" + s + ")";
}

// The faces array (F, 3) of integers, checked to fit uint32.
std::vector<cdbench::Triangle> triangles_of(const py::array& faces) {
  if (faces.ndim() != 2 || faces.shape(1) != 3)
    fail("faces must be an array of shape (triangles, 3), got " + shape_text(faces));
  if (faces.dtype().kind() != 'i' && faces.dtype().kind() != 'u')
    fail("faces must hold integers (vertex indices), got dtype " + std::string(py::str(faces.dtype())));
  const auto f = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(faces);
  const auto a = f.unchecked<2>();
  std::vector<cdbench::Triangle> out(size_t(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    int64_t v[3] = {a(i, 0), a(i, 1), a(i, 2)};
    for (int64_t x : v)
      if (x < 0 || x > int64_t(UINT32_MAX))
        fail("triangle " + std::to_string(i) + " has vertex index " + std::to_string(x) + ", outside 0..2^32-1");
    out[size_t(i)] = {uint32_t(v[0]), uint32_t(v[1]), uint32_t(v[2])};
  }
  return out;
}

cdbench::Topology make_topology(const py::array& faces, py::object num_vertices, py::object objects,
                                std::vector<uint32_t> self_queries,
                                std::vector<std::pair<uint32_t, uint32_t>> inter_queries) {
  std::vector<cdbench::Triangle> tris = triangles_of(faces);
  uint32_t n = 0;
  if (num_vertices.is_none()) {
    for (const auto& t : tris) n = std::max({n, t.v0 + 1, t.v1 + 1, t.v2 + 1});
  } else {
    n = num_vertices.cast<uint32_t>();
  }
  cdbench::Topology t = cdbench::Topology::mesh(std::move(tris), n);
  if (!objects.is_none())
    for (py::handle o : objects) {
      const auto fields = o.cast<py::tuple>();
      if (fields.size() != 3 && fields.size() != 4)
        fail("an object is (name, first_triangle, num_triangles[, rigid])");
      t.objects.push_back({fields[0].cast<std::string>(), fields[1].cast<uint32_t>(), fields[2].cast<uint32_t>(),
                           fields.size() == 4 && fields[3].cast<bool>()});
    }
  t.self_queries = std::move(self_queries);
  t.inter_queries = std::move(inter_queries);
  return t;
}

// (V, 3) or (3V,) positions: the vertex count.
size_t vertex_count(const std::vector<py::ssize_t>& shape) {
  if (shape.size() == 2 && shape[1] == 3) return size_t(shape[0]);
  if (shape.size() == 1 && shape[0] % 3 == 0) return size_t(shape[0] / 3);
  std::string s;
  for (auto d : shape) s += (s.empty() ? "" : ", ") + std::to_string(d);
  fail("positions must have shape (vertices, 3), got (" + s + ")");
}

// A host frame: float64 arrays run as doubles (box precision fp64 rebases them), anything
// else as float32; a C-contiguous float32 array is read in place on executor "cpu".
const cdbench::FrameStats& run_host(cdbench::BroadPhase& bp, const py::array& positions) {
  const std::vector<py::ssize_t> shape(positions.shape(), positions.shape() + positions.ndim());
  const size_t n = vertex_count(shape);
  if (positions.dtype().is(py::dtype::of<double>())) {
    const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(positions);
    return bp.run(d.data(), n);
  }
  const auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(positions);
  if (!f) fail("positions must be numbers, got dtype " + std::string(py::str(positions.dtype())));
  return bp.run(f.data(), n);
}

// A frame in device memory: __cuda_array_interface__ (version 2 or 3) of C-contiguous
// float32 (V, 3) or (3V,), read in place after the work on its stream (3: "stream", an
// integer cudaStream_t, 1 the legacy and 2 the per-thread default stream; absent or None:
// nothing to wait for, so the default stream, which costs nothing more).
const cdbench::FrameStats& run_device(cdbench::BroadPhase& bp, const py::object& positions) {
  const py::dict cai = positions.attr("__cuda_array_interface__").cast<py::dict>();
  if (cai["typestr"].cast<std::string>() != "<f4")
    fail("device positions must be float32 ('<f4'), got '" + cai["typestr"].cast<std::string>() + "'");
  const auto shape = cai["shape"].cast<std::vector<py::ssize_t>>();
  const size_t n = vertex_count(shape);
  if (cai.contains("strides") && !cai["strides"].is_none()) {
    const auto strides = cai["strides"].cast<std::vector<py::ssize_t>>();
    const bool packed = shape.size() == 1 ? strides[0] == 4 : (strides[0] == 12 && strides[1] == 4);
    if (!packed) fail("device positions must be C-contiguous (x, y, z of each vertex together)");
  }
  if (cai.contains("mask") && !cai["mask"].is_none()) fail("device positions must not be masked");
  const auto data = cai["data"].cast<py::tuple>();
  const auto* xyz = reinterpret_cast<const float*>(data[0].cast<uintptr_t>());
  void* stream = nullptr;
  if (cai.contains("stream") && !cai["stream"].is_none())
    stream = reinterpret_cast<void*>(cai["stream"].cast<uintptr_t>());
  return bp.run_device(xyz, n, stream);
}

py::dict stats_dict(const cdbench::FrameStats& s) {
  py::dict phases;
  for (size_t p = 0; p < s.phase_ms.size(); ++p)
    if (s.phase_ms[p] != 0.0) phases[cdbench::phase_names()[p]] = s.phase_ms[p];
  py::dict d;
  d["pairs"] = s.pairs;
  d["time_ms"] = s.time_ms;
  d["upload_ms"] = s.upload_ms;
  d["phases_ms"] = phases;
  d["op"] = s.op;
  d["front_internal"] = s.front_internal;
  d["front_external"] = s.front_external;
  d["q_root"] = s.q_root;
  d["query_reruns"] = s.query_reruns;
  d["host_syncs"] = s.host_syncs;
  d["buffer_allocations"] = s.buffer_allocations;
  return d;
}

py::array_t<uint32_t> pairs_array(const std::vector<cdbench::Pair>& pairs) {
  py::array_t<uint32_t> out({py::ssize_t(pairs.size()), py::ssize_t(2)});
  if (!pairs.empty()) std::memcpy(out.mutable_data(), pairs.data(), pairs.size() * sizeof(cdbench::Pair));
  return out;
}

// The last frame's pairs on the device, as __cuda_array_interface__ (uint32, (P, 2)); keeps
// its BroadPhase alive. Valid until that BroadPhase's next frame.
struct DevicePairs {
  cdbench::DevicePairs pairs;
  py::object owner;
  py::dict interface() const {
    py::dict d;
    d["shape"] = py::make_tuple(pairs.count, 2);
    d["typestr"] = "<u4";
    d["data"] = py::make_tuple(reinterpret_cast<uintptr_t>(pairs.data), true);
    d["strides"] = py::none();
    d["version"] = 2;
    return d;
  }
};

}  // namespace

PYBIND11_MODULE(cdbench, m) {
  m.doc() = "cdbench's broad phase: every pair of triangles (or boxes) whose boxes overlap, frame by frame";
  py::register_exception<cdb::Error>(m, "Error", PyExc_RuntimeError);

  py::class_<cdbench::Topology>(m, "Topology", "What stays fixed from frame to frame: triangles, or boxes")
      .def(py::init(&make_topology), py::arg("faces"), py::arg("num_vertices") = py::none(),
           py::arg("objects") = py::none(), py::arg("self_queries") = std::vector<uint32_t>{},
           py::arg("inter_queries") = std::vector<std::pair<uint32_t, uint32_t>>{},
           "faces: (F, 3) vertex indices; num_vertices: default the largest index + 1; objects: "
           "[(name, first_triangle, num_triangles[, rigid])]; self_queries / inter_queries: object "
           "indices / index pairs whose pairs alone are reported (none: every pair)")
      .def_static("boxes", &cdbench::Topology::boxes, py::arg("count"),
                  "count boxes; a frame is (2 * count, 3): each box's min corner, then its max corner")
      .def_property_readonly("num_triangles", [](const cdbench::Topology& t) { return t.triangles.size(); })
      .def_readonly("num_vertices", &cdbench::Topology::num_vertices);

  py::class_<DevicePairs>(m, "DevicePairs", "A frame's pairs in device memory (uint32, (P, 2))")
      .def_property_readonly("__cuda_array_interface__", &DevicePairs::interface)
      .def("__len__", [](const DevicePairs& p) { return p.pairs.count; });

  py::class_<cdbench::BroadPhase>(m, "BroadPhase", "One pipeline on one executor, given one frame at a time")
      .def(py::init([](const cdbench::Topology& topology, const std::string& pipeline, const std::string& executor,
                       bool skip_adjacent, float margin, bool swept, const std::string& box_precision) {
             return cdbench::BroadPhase(
                 {pipeline, executor, skip_adjacent, margin, swept, box_precision}, topology);
           }),
           py::arg("topology"), py::arg("pipeline") = "c", py::arg("executor") = "cpu",
           py::arg("skip_adjacent") = false, py::arg("margin") = 0.0f, py::arg("swept") = false,
           py::arg("box_precision") = "fp32")
      .def(
          "run",
          [](cdbench::BroadPhase& bp, const py::object& positions) {
            if (py::hasattr(positions, "__cuda_array_interface__")) {
              if (bp.options().executor != "cuda")
                fail("positions in device memory (__cuda_array_interface__) need executor 'cuda'; this one is '" +
                     bp.options().executor + "'");
              return stats_dict(run_device(bp, positions));
            }
            return stats_dict(run_host(bp, py::array::ensure(positions)));
          },
          py::arg("positions"),
          "one frame: a NumPy (V, 3) array, or on executor 'cuda' any object with "
          "__cuda_array_interface__ (float32, read in place); returns the frame's statistics")
      .def("pairs", [](const cdbench::BroadPhase& bp) { return pairs_array(bp.pairs()); },
           "the last frame's pairs, (P, 2) uint32, sorted")
      .def(
          "device_pairs",
          [](py::object self) { return DevicePairs{self.cast<const cdbench::BroadPhase&>().device_pairs(), self}; },
          "executor 'cuda': the last frame's pairs in device memory, unsorted")
      .def_property_readonly("stats", [](const cdbench::BroadPhase& bp) { return stats_dict(bp.stats()); })
      .def_property_readonly("num_vertices", &cdbench::BroadPhase::num_vertices)
      .def_property_readonly("num_triangles", &cdbench::BroadPhase::num_triangles);

  m.def("pipelines", &cdbench::pipelines, "the pipelines' names");
  m.def("cuda_available", [] {
    std::string reason;
    const bool ok = cdbench::cuda_available(&reason);
    return py::make_tuple(ok, reason);
  }, "(whether executor 'cuda' can run, why not)");
  m.def(
      "oracle_pairs",
      [](const cdbench::Topology& topology, const py::array& positions, bool skip_adjacent) {
        const std::vector<py::ssize_t> shape(positions.shape(), positions.shape() + positions.ndim());
        const size_t n = vertex_count(shape);
        if (positions.dtype().is(py::dtype::of<double>())) {
          const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(positions);
          return pairs_array(cdbench::oracle_pairs(topology, d.data(), n, skip_adjacent));
        }
        const auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(positions);
        return pairs_array(cdbench::oracle_pairs(topology, f.data(), n, skip_adjacent));
      },
      py::arg("topology"), py::arg("positions"), py::arg("skip_adjacent") = false,
      "the exact serial reference: (P, 2) uint32, sorted");
}
