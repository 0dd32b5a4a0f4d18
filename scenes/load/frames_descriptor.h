#pragma once
// The descriptor `scenes generate` writes beside a scene's OBJ frames when the scene declares
// queries: OBJ frames keep the triangles but not the objects and queries, which
// `--scene DIR/scene.json` restores ({"frames": ".", "objects", "queries"}, as a descriptor
// over frames takes them: docs/usage.md "Descriptors with sequence parts").
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "cdbench/geometry/mesh.h"

namespace cdb {

inline constexpr const char* kFramesDescriptorName = "scene.json";

// The declared queries by object name, as a descriptor's "queries" takes them ({"self":
// [names], "inter": [[name, name]]}); null where none are declared (every pair).
nlohmann::ordered_json queries_json(const Topology& topology);

// Writes `dir`/scene.json for frames of `topology` when its queries are declared, written
// whole or not at all (a failed write is removed and fails naming the file); returns whether
// it wrote one.
bool write_frames_descriptor(const Topology& topology, const std::string& description, const std::filesystem::path& dir);

}  // namespace cdb
