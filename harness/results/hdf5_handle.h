#pragma once
// Thin RAII over HDF5 C API identifiers, plus the checks and attribute reads/writes the
// results writer and reader share. Every failure throws cdb::Error naming the file and
// the object, with HDF5's own reason appended.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cdbench/core/error.h"

namespace cdb::h5 {

// An HDF5 call that failed on the operating system's side (an errno on HDF5's error stack:
// a full disk, a file size limit, an I/O error). `reason` is the system's text for the
// errno ("no space left on device"), not HDF5's, and `error_number` the errno itself, so
// a reader can tell a file another process holds locked (EWOULDBLOCK) from a failed disk.
// What was written since the last flush may be lost, and the library's cache cannot be
// flushed again.
struct IoError : Error {
  IoError(const std::string& message, std::string why, int error)
      : Error(message), reason(std::move(why)), error_number(error) {}
  std::string reason;
  int error_number;
};

// An HDF5 call that failed inside the library, with no errno: in a reader, a file that is
// truncated or damaged (a bad address, a signature or conversion HDF5 cannot make sense of).
// `reason` is HDF5's innermost message.
struct LibraryError : Error {
  LibraryError(const std::string& message, std::string why) : Error(message), reason(std::move(why)) {}
  std::string reason;
};

class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer close) : id_(id), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept;
  ~Handle() { reset(); }
  hid_t get() const { return id_; }
  explicit operator bool() const { return id_ >= 0; }
  // Closes now; returns false when HDF5 reports a failure (the id is gone either way).
  bool reset() noexcept;
  // Forgets the id without closing it (after an IoError, when closing would flush again).
  void abandon() noexcept { id_ = H5I_INVALID_HID; }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer close_ = nullptr;
};

// HDF5 prints its error stack to stderr by default; we throw with context instead. Also
// keeps HDF5 from closing files itself at exit: a file whose writes failed is left for the
// system to close, since flushing HDF5's cache again after a failed write crashes.
void silence_library_errors();

// Throws "WHERE: WHAT failed: <reason>" when an HDF5 call returned a negative value: an
// IoError when the failure carries an errno, LibraryError otherwise.
hid_t check(hid_t result, const std::string& where, const char* what);

// Wraps a fresh id, throwing as check() does when it is invalid.
Handle own(hid_t id, Handle::Closer close, const std::string& where, const char* what);

// Attributes on a file, group or dataset. A string attribute is variable-length UTF-8 and
// replaces one of the same name; numbers are stored in the type given.
void write_attr(hid_t loc, const char* name, const std::string& value, const std::string& where);
void write_attr(hid_t loc, const char* name, double value, const std::string& where);
void write_attr(hid_t loc, const char* name, int64_t value, const std::string& where);
void write_attr(hid_t loc, const char* name, uint64_t value, const std::string& where);

bool has_attr(hid_t loc, const char* name);
std::vector<std::string> attr_names(hid_t loc, const std::string& where);
std::string read_string_attr(hid_t loc, const char* name, const std::string& where);
double read_double_attr(hid_t loc, const char* name, const std::string& where);
int64_t read_int_attr(hid_t loc, const char* name, const std::string& where);

}  // namespace cdb::h5
