#pragma once
// The exceptions the standard library and nlohmann-json throw carry text meant for
// programmers ("filesystem error: status: ...", "[json.exception.type_error.316] ...",
// "stoul"). Whatever reaches the user is said in words naming the input and what to do.
#include <exception>
#include <string>
#include <system_error>

namespace cdb {

// `e` as a sentence for the user: cdb::Error's own message, a translation of a library's.
std::string error_text(const std::exception& e);

// A system error on a path in words, with what to do: "its symbolic links form a loop;
// point the link at a real file or directory".
std::string path_error_text(const std::error_code& ec);

}  // namespace cdb
