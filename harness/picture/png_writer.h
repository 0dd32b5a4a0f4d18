#pragma once
// PNG files of RGB pictures: 8-bit truecolour, no interlace, every row filtered with filter
// 0 (none) and the whole compressed by zlib. The pictures are flat-shaded, so filters
// would gain little; the file stays readable by any PNG decoder.
#include <filesystem>

#include "harness/picture/rgb_image.h"

namespace cdb {

// Throws cdb::Error naming the file when it cannot be written (its directory missing or
// read-only, a full disk); a file cut off by a failed write is removed.
void write_png(const std::filesystem::path& file, const RgbImage& image);

}  // namespace cdb
