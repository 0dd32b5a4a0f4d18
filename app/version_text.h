#pragma once
// What `cdbench --version` prints: the version, the commit, the CUDA toolkit the binary was
// compiled with (or that it has no CUDA backend) and the build type.
#include <string>

namespace cdb {

std::string version_text();

}  // namespace cdb
