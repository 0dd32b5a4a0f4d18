#include "scenes/load/npy_header.h"

#include <charconv>
#include <set>
#include <utility>

#include "cdbench/core/error.h"
#include "scenes/load/input_files.h"

namespace cdb {
namespace {

// A cursor over the header dict, failing with the offending text in its message.
class DictParser {
 public:
  DictParser(std::string_view text, const std::string& where) : s_(text), where_(where) {}

  NpyHeader parse() {
    NpyHeader h;
    std::set<std::string> seen;
    expect('{');
    while (true) {
      skip_space();
      if (peek() == '}') break;
      const std::string key = string_literal();
      expect(':');
      if (!seen.insert(key).second) bad("key '" + key + "' appears twice");
      if (key == "descr") h.descr = string_literal();
      else if (key == "fortran_order") h.fortran_order = boolean();
      else if (key == "shape") h.shape = tuple();
      else bad("unknown key '" + key + "' (a .npy header has descr, fortran_order and shape)");
      skip_space();
      if (peek() == ',') ++p_;
      else if (peek() != '}') bad("expected ',' or '}'");
    }
    ++p_;
    skip_space();
    if (p_ != s_.size()) bad("text after the dict");
    for (const char* key : {"descr", "fortran_order", "shape"})
      if (!seen.count(key)) fail(where_ + ": .npy header lacks '" + key + "'");
    return h;
  }

 private:
  // Padding is spaces and a final newline.
  void skip_space() {
    while (p_ < s_.size() && (s_[p_] == ' ' || s_[p_] == '\n' || s_[p_] == '\t')) ++p_;
  }
  char peek() const { return p_ < s_.size() ? s_[p_] : '\0'; }
  [[noreturn]] void bad(const std::string& what) const {
    fail(where_ + ": malformed .npy header at character " + std::to_string(p_) + ": " + what + " in \"" +
         std::string(s_) + "\"");
  }
  void expect(char c) {
    skip_space();
    if (peek() != c) bad(std::string("expected '") + c + "'");
    ++p_;
  }
  std::string string_literal() {
    skip_space();
    const char quote = peek();
    if (quote != '\'' && quote != '"') bad("expected a quoted string");
    const size_t end = s_.find(quote, p_ + 1);
    if (end == std::string_view::npos) bad("unterminated string");
    std::string text(s_.substr(p_ + 1, end - p_ - 1));
    p_ = end + 1;
    return text;
  }
  bool boolean() {
    skip_space();
    for (const auto& [word, value] : {std::pair{"True", true}, std::pair{"False", false}}) {
      const std::string_view w(word);
      if (s_.substr(p_, w.size()) == w) {
        p_ += w.size();
        return value;
      }
    }
    bad("expected True or False");
  }
  std::vector<uint64_t> tuple() {
    std::vector<uint64_t> dims;
    expect('(');
    while (true) {
      skip_space();
      if (peek() == ')') break;
      uint64_t d = 0;
      const auto [end, ec] = std::from_chars(s_.data() + p_, s_.data() + s_.size(), d);
      if (ec != std::errc()) bad("expected a dimension (a non-negative integer)");
      p_ = size_t(end - s_.data());
      // NumPy writes 3L on Python 2.
      if (peek() == 'L') ++p_;
      dims.push_back(d);
      skip_space();
      if (peek() == ',') ++p_;
      else if (peek() != ')') bad("expected ',' or ')'");
    }
    ++p_;
    return dims;
  }

  std::string_view s_;
  const std::string& where_;
  size_t p_ = 0;
};

}  // namespace

NpyHeader parse_npy_header(std::string_view bytes, const std::string& where) {
  static constexpr std::string_view kMagic("\x93NUMPY", 6);
  if (bytes.substr(0, kMagic.size()) != kMagic) fail(where + ": not a .npy file (no \\x93NUMPY magic)");
  if (bytes.size() < 10) fail(where + ": truncated .npy header");
  const int major = uint8_t(bytes[6]), minor = uint8_t(bytes[7]);
  if (major < 1 || major > 3 || minor != 0)
    fail(where + ": .npy format version " + std::to_string(major) + "." + std::to_string(minor) +
         " is not supported (1.0, 2.0, 3.0)");
  // Version 1 stores the header length in 2 bytes, versions 2 and 3 in 4.
  const size_t length_bytes = major == 1 ? 2 : 4, text_at = 8 + length_bytes;
  if (bytes.size() < text_at) fail(where + ": truncated .npy header");
  const size_t text_length = little_endian(bytes.data() + 8, length_bytes);
  if (bytes.size() < text_at + text_length)
    fail(where + ": truncated .npy header (" + std::to_string(text_length) + " header bytes announced, " +
         std::to_string(bytes.size() - text_at) + " in the file)");
  NpyHeader h = DictParser(bytes.substr(text_at, text_length), where).parse();
  h.data_offset = text_at + text_length;
  return h;
}

std::string shape_text(const std::vector<uint64_t>& shape) {
  std::string t = "(";
  for (size_t i = 0; i < shape.size(); ++i) t += (i ? ", " : "") + std::to_string(shape[i]);
  return t + (shape.size() == 1 ? ",)" : ")");
}

}  // namespace cdb
