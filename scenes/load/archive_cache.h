#pragma once
// Scene data that a package ships inside an archive (libcgal-demo's data.tar.gz) is
// extracted on first use into the scene cache, never into the source tree, and read from
// there afterwards.
#include <filesystem>
#include <string>

namespace cdb {

// $CDBENCH_CACHE, else $XDG_CACHE_HOME/cdbench, else $HOME/.cache/cdbench.
std::filesystem::path scene_cache_dir();

// The path of `member` of the gzip-compressed tar `archive` in the cache, extracted when it
// is not there yet (or the archive changed size or time since). Throws naming the archive
// and member when the member is missing or the archive is damaged.
std::filesystem::path extract_from_archive(const std::filesystem::path& archive, const std::string& member);

}  // namespace cdb
