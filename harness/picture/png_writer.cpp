#include "harness/picture/png_writer.h"

#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>
#include <vector>

#include "cdbench/core/error.h"

namespace cdb {
namespace {

void put_u32(std::vector<uint8_t>& out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(uint8_t(v >> shift));
}

// One chunk: length, type, data, and the CRC of type and data (PNG spec 5.3).
void put_chunk(std::vector<uint8_t>& out, const char type[4], const std::vector<uint8_t>& data) {
  put_u32(out, uint32_t(data.size()));
  const size_t type_at = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  const uLong crc = crc32(crc32(0L, Z_NULL, 0), out.data() + type_at, uInt(out.size() - type_at));
  put_u32(out, uint32_t(crc));
}

// The rows as IDAT holds them: each row its filter byte (0) and its pixels, zlib-compressed.
std::vector<uint8_t> compressed_rows(const RgbImage& image) {
  const size_t row_bytes = 1 + size_t(image.width) * 3;
  std::vector<uint8_t> raw(row_bytes * image.height);
  for (uint32_t y = 0; y < image.height; ++y) {
    uint8_t* row = raw.data() + y * row_bytes;
    row[0] = 0;
    std::memcpy(row + 1, &image.at(0, y), size_t(image.width) * 3);
  }
  uLongf size = compressBound(uLong(raw.size()));
  std::vector<uint8_t> packed(size);
  // Level 6, zlib's default: the pictures are mostly flat colour and compress well at it.
  if (compress2(packed.data(), &size, raw.data(), uLong(raw.size()), 6) != Z_OK)
    fail("PNG: zlib could not compress the picture");
  packed.resize(size);
  return packed;
}

}  // namespace

void write_png(const std::filesystem::path& file, const RgbImage& image) {
  static_assert(sizeof(Rgb) == 3, "a row of Rgb is the PNG row's bytes");
  if (image.width == 0 || image.height == 0) fail("PNG " + file.string() + ": a picture of no pixels");
  std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<uint8_t> header;
  put_u32(header, image.width);
  put_u32(header, image.height);
  // Bit depth 8, colour type 2 (truecolour), deflate, filter method 0, no interlace.
  header.insert(header.end(), {8, 2, 0, 0, 0});
  put_chunk(png, "IHDR", header);
  put_chunk(png, "IDAT", compressed_rows(image));
  put_chunk(png, "IEND", {});

  std::FILE* out = std::fopen(file.string().c_str(), "wb");
  if (!out) fail("cannot write " + file.string() + ": " + std::strerror(errno));
  errno = 0;
  const bool written = std::fwrite(png.data(), 1, png.size(), out) == png.size();
  const int write_error = errno;
  const bool closed = std::fclose(out) == 0;
  if (written && closed) return;
  const int error = write_error ? write_error : errno;
  std::error_code ignored;
  std::filesystem::remove(file, ignored);
  fail("writing " + file.string() + " failed" + (error ? std::string(": ") + std::strerror(error) : "") +
       " (the file was removed)");
}

}  // namespace cdb
