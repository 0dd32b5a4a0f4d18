#pragma once
// Recorded frames, the parts every executor shares: the key a recording is valid for and
// how a frame's recorded work ran. CudaFrameGraph (exec/cuda_exec.cuh) records CUDA graphs;
// HostFrameGraph (exec/host_exec.h) runs the work as it comes.
#include <array>
#include <cstdint>

namespace cdb {

// What, besides device memory contents, decides the kernels and arguments a recorded
// frame launches; the caller says (for example a version counter of its buffers and fronts,
// and the vertex buffers in use).
using FrameGraphKey = std::array<uint64_t, 4>;

enum class FrameGraphRun { plain, captured, replayed };

inline const char* frame_graph_run_name(FrameGraphRun r) {
  return r == FrameGraphRun::captured ? "captured" : r == FrameGraphRun::replayed ? "replayed" : "";
}

}  // namespace cdb
