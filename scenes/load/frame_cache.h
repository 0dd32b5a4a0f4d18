#pragma once
// Frames of procedural scenes kept on disk after their first simulation, so the many
// processes of a sweep (one per cell) simulate a scene once instead of once per cell. A
// frame is one file, written to a temporary name and renamed, so concurrent cells and
// interrupted runs never leave a half-written frame behind. Each file carries a checksum of
// its positions: a file that does not read back whole, finite and matching it is simulated
// again, with a line on stderr naming the file.
#include <filesystem>
#include <memory>
#include <string>

#include "cdbench/geometry/frame_source.h"

namespace cdb {

// Where frames are cached: the scene cache (scene_cache_dir(): $CDBENCH_CACHE, else
// $XDG_CACHE_HOME/cdbench, else $HOME/.cache/cdbench); empty when frame caching is off
// ($CDBENCH_FRAME_CACHE=off) or there is no such directory.
std::filesystem::path frame_cache_dir();

// Wraps a generator's source: frame k comes from DIR/<key>/frame_<k>.f64 when present,
// else from the generator, and is then stored there. `identity` names the generator and its
// parameters; the key also covers this binary (git sha, size, modification time), so frames
// of a changed generator are never reused. Scenes larger than max_bytes in all are not
// cached (a 10M-triangle soup is cheaper to regenerate than to store).
std::unique_ptr<FrameSource> cache_frames(std::unique_ptr<FrameSource> source, const std::string& identity,
                                          const std::filesystem::path& dir,
                                          uint64_t max_bytes = uint64_t(1) << 30);

}  // namespace cdb
