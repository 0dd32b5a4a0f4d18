#pragma once
// `--help` text wrapped to the terminal: CLI11 2.1 prints each option's description on one
// line however long, so long descriptions ran to several hundred characters.
#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>

namespace cdb {

// Columns to wrap help text to: the terminal's width when stdout is one, else $COLUMNS,
// else 100; never below 60 or above 160.
std::size_t help_width();

// `text`, starting at column `start`, broken at spaces into lines of at most `width`
// columns (a longer word keeps its own line); every line after the first starts with
// `indent` spaces. Line breaks already in the text are kept.
std::string wrap_text(const std::string& text, std::size_t width, std::size_t indent, std::size_t start);

// The formatter of every command: option names in the first column, descriptions wrapped
// to the width beside them.
class WrappedHelp : public CLI::Formatter {
 public:
  explicit WrappedHelp(std::size_t width);
  std::string make_option(const CLI::Option* opt, bool is_positional) const override;
  std::string make_description(const CLI::App* app) const override;
  std::string make_footer(const CLI::App* app) const override;

 private:
  std::size_t width_;
};

}  // namespace cdb
