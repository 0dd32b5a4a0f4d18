#include "harness/pairs/pairs_file.h"

#include <algorithm>
#include <charconv>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <string_view>

#include "cdbench/core/error.h"
#include "cdbench/core/pair_set.h"
#include "scenes/load/input_files.h"

namespace cdb {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// One triangle index of a text line at `p`, blanks before it skipped; false when there
// is no number there. Numbers past uint32 read as UINT32_MAX, out of every range.
bool parse_index(const char*& p, const char* end, uint32_t& index) {
  while (p < end && is_blank(*p)) ++p;
  uint64_t value = 0;
  const auto [next, ec] = std::from_chars(p, end, value);
  if (next == p) return false;
  p = next;
  index = ec == std::errc::result_out_of_range || value > UINT32_MAX ? UINT32_MAX : uint32_t(value);
  return true;
}

// "file:line" for text, "file: pair K (byte B)" for binary.
std::string where(const std::filesystem::path& file, PairsFormat format, uint64_t entry) {
  if (format == PairsFormat::text) return file.string() + ":" + std::to_string(entry);
  return file.string() + ": pair " + std::to_string(entry) + " (byte " + std::to_string(entry * 8) + ")";
}

void check_pair(uint32_t i, uint32_t j, uint32_t num_faces, const std::filesystem::path& file,
                PairsFormat format, uint64_t entry) {
  for (uint32_t t : {i, j})
    if (t >= num_faces)
      fail(where(file, format, entry) + ": triangle " + (t == UINT32_MAX ? std::string(">= 2^32-1") : std::to_string(t)) +
           " out of range (the scene has " + std::to_string(num_faces) + " triangles, 0-based)");
  if (i == j) fail(where(file, format, entry) + ": triangle " + std::to_string(i) + " paired with itself");
}

void parse_text(const std::string& text, uint32_t num_faces, const std::filesystem::path& file,
                std::vector<PrimPair>& out) {
  const char* p = text.data();
  const char* const end = p + text.size();
  for (uint64_t line = 1; p < end; ++line) {
    const char* eol = static_cast<const char*>(std::memchr(p, '\n', size_t(end - p)));
    if (!eol) eol = end;
    const char* q = p;
    while (q < eol && is_blank(*q)) ++q;
    if (q < eol && *q != '#') {
      uint32_t i = 0, j = 0;
      bool two = parse_index(q, eol, i);
      while (q < eol && is_blank(*q)) ++q;
      if (q < eol && *q == ',') ++q;
      two = two && parse_index(q, eol, j);
      while (q < eol && is_blank(*q)) ++q;
      if (!two || q != eol) {
        std::string shown(p, size_t(eol - p));
        if (!shown.empty() && shown.back() == '\r') shown.pop_back();
        if (shown.size() > 60) shown = shown.substr(0, 60) + "...";
        fail(file.string() + ":" + std::to_string(line) + ": expected two triangle indices, got '" + shown + "'");
      }
      check_pair(i, j, num_faces, file, PairsFormat::text, line);
      out.push_back(make_pair_ordered(i, j));
    }
    p = eol + 1;
  }
}

void parse_binary(const std::string& bytes, uint32_t num_faces, const std::filesystem::path& file,
                  std::vector<PrimPair>& out) {
  if (bytes.size() % 8 != 0)
    fail(file.string() + ": " + std::to_string(bytes.size()) +
         " bytes, not a whole number of pairs (8 bytes each: two little-endian uint32)");
  const size_t n = bytes.size() / 8;
  out.reserve(n);
  for (size_t k = 0; k < n; ++k) {
    const uint32_t i = uint32_t(little_endian(bytes.data() + 8 * k, 4));
    const uint32_t j = uint32_t(little_endian(bytes.data() + 8 * k + 4, 4));
    check_pair(i, j, num_faces, file, PairsFormat::binary, k);
    out.push_back(make_pair_ordered(i, j));
  }
}

// frame_N.EXT's N, or nullopt for any other name.
std::optional<uint32_t> frame_number(const std::string& name) {
  constexpr std::string_view prefix = "frame_";
  if (name.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  const char* p = name.data() + prefix.size();
  const char* end = name.data() + name.size();
  uint32_t n = 0;
  const auto [next, ec] = std::from_chars(p, end, n);
  if (next == p || ec != std::errc() || (next != end && *next != '.')) return std::nullopt;
  return n;
}

// .bin is binary, any other name text.
PairsFormat pairs_format_of(const std::filesystem::path& file) {
  return file.extension() == ".bin" ? PairsFormat::binary : PairsFormat::text;
}

}  // namespace

std::string pairs_file_name(uint32_t frame, PairsFormat format) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04u.%s", frame, format == PairsFormat::binary ? "bin" : "txt");
  return name;
}

PairsRead read_pairs_file(const std::filesystem::path& file, uint32_t num_faces, size_t keep) {
  const std::string bytes = read_file(file, " pairs file");
  PairsRead r;
  std::vector<PrimPair> listed;
  if (pairs_format_of(file) == PairsFormat::binary)
    parse_binary(bytes, num_faces, file, listed);
  else
    parse_text(bytes, num_faces, file, listed);
  r.listed = listed.size();
  sort_by_pair_key(listed);
  r.pairs.reserve(listed.size());
  for (const PrimPair p : listed) {
    if (!r.pairs.empty() && pair_key(r.pairs.back()) == pair_key(p)) {
      if (r.first_duplicates.size() < keep &&
          (r.first_duplicates.empty() || pair_key(r.first_duplicates.back()) != pair_key(p)))
        r.first_duplicates.push_back(p);
      ++r.duplicates;
      continue;
    }
    r.pairs.push_back(p);
  }
  return r;
}

void write_pairs_file(const std::filesystem::path& file, const std::vector<PrimPair>& pairs,
                      const std::vector<std::string>& comment) {
  const bool binary = pairs_format_of(file) == PairsFormat::binary;
  std::unique_ptr<FILE, int (*)(FILE*)> out(std::fopen(file.string().c_str(), binary ? "wb" : "w"), std::fclose);
  if (!out) fail(file.string() + ": cannot open for writing: " + std::strerror(errno));
  errno = 0;
  if (binary) {
    for (const PrimPair p : pairs) {
      const uint32_t ij[2] = {p.a, p.b};
      std::fwrite(ij, sizeof ij, 1, out.get());
    }
  } else {
    for (const std::string& line : comment) std::fprintf(out.get(), "# %s\n", line.c_str());
    for (const PrimPair p : pairs) std::fprintf(out.get(), "%u %u\n", p.a, p.b);
  }
  // The last buffer is written at the close: its failure (a full disk) counts too. A cut-off
  // file would read as a frame with fewer pairs, so it is removed.
  const bool failed = std::ferror(out.get()) | (std::fclose(out.release()) != 0);
  if (failed) {
    const int error = errno;
    std::error_code ec;
    std::filesystem::remove(file, ec);
    fail(file.string() + ": write failed" + (error ? std::string(": ") + std::strerror(error) : "") +
         " (the partial file removed)");
  }
}

std::vector<std::filesystem::path> pairs_files_for_frames(const std::filesystem::path& dir, uint32_t first,
                                                          uint32_t last) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) fail(dir.string() + ": not a directory of pairs files");
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name[0] == '.' || !entry.is_regular_file()) continue;
    files.push_back(entry.path());
  }
  if (ec) fail(dir.string() + ": cannot list: " + ec.message());
  const bool numbered = !files.empty() && std::all_of(files.begin(), files.end(), [](const auto& f) {
    return frame_number(f.filename().string()).has_value();
  });
  std::vector<std::filesystem::path> matched;
  if (numbered) {
    std::map<uint32_t, std::filesystem::path> by_frame;
    for (const auto& f : files) {
      const uint32_t n = *frame_number(f.filename().string());
      if (n < first || n >= last) continue;
      const auto [at, fresh] = by_frame.emplace(n, f);
      if (!fresh)
        fail(dir.string() + ": two pairs files for frame " + std::to_string(n) + ": " +
             at->second.filename().string() + " and " + f.filename().string());
    }
    for (uint32_t n = first; n < last; ++n) {
      const auto it = by_frame.find(n);
      if (it == by_frame.end())
        fail(dir.string() + ": no pairs file for frame " + std::to_string(n) + " (e.g. " +
             pairs_file_name(n, PairsFormat::text) + ")");
      matched.push_back(it->second);
    }
    return matched;
  }
  if (files.size() != size_t(last - first))
    fail(dir.string() + ": " + std::to_string(files.size()) + " files for the " + std::to_string(last - first) +
         " frames " + std::to_string(first) + ":" + std::to_string(last) +
         " (matched in natural order; name them frame_N.txt to match frames by number)");
  std::sort(files.begin(), files.end(),
            [](const auto& a, const auto& b) { return natural_less(a.filename().string(), b.filename().string()); });
  return files;
}

}  // namespace cdb
