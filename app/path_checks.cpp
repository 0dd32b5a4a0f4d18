#include "path_checks.h"

#include <string>

namespace cdb {

CLI::Validator non_empty_path() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return text.empty() ? "expected a name, not an empty string" : "";
      },
      "");
}

}  // namespace cdb
