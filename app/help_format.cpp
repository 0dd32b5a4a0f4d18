#include "help_format.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>

namespace cdb {

namespace {

constexpr std::size_t kNameColumn = 32;

// The first column of a line ("  name   description"): continuation lines of a footer or
// list entry line up under its description.
std::size_t hanging_indent(const std::string& line) {
  const std::size_t name = line.find_first_not_of(' ');
  if (name == std::string::npos) return 0;
  const std::size_t gap = line.find("  ", name);
  if (gap == std::string::npos) return name;
  const std::size_t text = line.find_first_not_of(' ', gap);
  return text == std::string::npos || text > 40 ? name : text;
}

}  // namespace

std::size_t help_width() {
  std::size_t width = 100;
  winsize ws{};
  if (isatty(STDOUT_FILENO) && ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0) {
    width = ws.ws_col;
  } else if (const char* columns = std::getenv("COLUMNS")) {
    const long c = std::strtol(columns, nullptr, 10);
    if (c > 0) width = std::size_t(c);
  }
  return std::clamp<std::size_t>(width, 60, 160);
}

std::string wrap_text(const std::string& text, std::size_t width, std::size_t indent, std::size_t start) {
  std::string out;
  std::size_t column = start;
  bool line_start = true;
  std::istringstream lines(text);
  bool first_line = true;
  for (std::string line; std::getline(lines, line);) {
    if (!first_line) {
      out += '\n' + std::string(indent, ' ');
      column = indent;
      line_start = true;
    }
    first_line = false;
    std::istringstream words(line);
    for (std::string word; words >> word;) {
      if (!line_start && column + 1 + word.size() > width) {
        out += '\n' + std::string(indent, ' ');
        column = indent;
        line_start = true;
      }
      if (!line_start) {
        out += ' ';
        ++column;
      }
      out += word;
      column += word.size();
      line_start = false;
    }
  }
  return out;
}

WrappedHelp::WrappedHelp(std::size_t width) : width_(width) { column_width(kNameColumn); }

std::string WrappedHelp::make_option(const CLI::Option* opt, bool is_positional) const {
  const std::string name = "  " + make_option_name(opt, is_positional) + make_option_opts(opt);
  const std::string desc = make_option_desc(opt);
  std::string out = name;
  if (desc.empty()) return out + "\n";
  // A name that fills its column puts the description on the next line, as CLI11 does.
  if (name.size() >= kNameColumn) out += "\n" + std::string(kNameColumn, ' ');
  else out += std::string(kNameColumn - name.size(), ' ');
  const std::size_t room = width_ > kNameColumn + 20 ? width_ - kNameColumn : 20;
  const std::string wrapped = wrap_text(desc, room, 0, 0);
  std::istringstream lines(wrapped);
  bool first = true;
  for (std::string line; std::getline(lines, line); first = false)
    out += (first ? "" : "\n" + std::string(kNameColumn, ' ')) + line;
  return out + "\n";
}

std::string WrappedHelp::make_description(const CLI::App* app) const {
  const std::string desc = CLI::Formatter::make_description(app);
  return desc.empty() ? desc : wrap_text(desc, width_, 0, 0) + "\n";
}

std::string WrappedHelp::make_footer(const CLI::App* app) const {
  const std::string footer = app->get_footer();
  if (footer.empty()) return footer;
  std::string out;
  std::istringstream lines(footer);
  for (std::string line; std::getline(lines, line);) {
    const std::size_t lead = line.find_first_not_of(' ');
    const std::string body = lead == std::string::npos ? "" : line.substr(lead);
    const std::size_t at = lead == std::string::npos ? 0 : lead;
    out += std::string(at, ' ') + wrap_text(body, width_, hanging_indent(line), at) + "\n";
  }
  return out;
}

}  // namespace cdb
