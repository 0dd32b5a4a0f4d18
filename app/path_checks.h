#pragma once
// Options that name a file or directory: an empty name (`--out ""`, an unset shell
// variable) is a mistake in the call, refused with exit 2 naming the option, rather than
// read as "not given" (run --out "" wrote nothing, verify --pairs "" checked nothing) or
// passed to the file system as it stands.
#include <CLI/CLI.hpp>

namespace cdb {

CLI::Validator non_empty_path();

}  // namespace cdb
