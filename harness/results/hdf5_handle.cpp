#include "harness/results/hdf5_handle.h"

#include <cctype>
#include <cstdlib>
#include <cstring>

namespace cdb::h5 {

Handle& Handle::operator=(Handle&& o) noexcept {
  if (this != &o) {
    reset();
    id_ = o.id_;
    close_ = o.close_;
    o.id_ = H5I_INVALID_HID;
  }
  return *this;
}

bool Handle::reset() noexcept {
  bool ok = true;
  if (id_ >= 0 && close_) ok = close_(id_) >= 0;
  id_ = H5I_INVALID_HID;
  return ok;
}

void silence_library_errors() {
  // Before any other HDF5 call, or it has no effect; the library ignores repeats.
  H5dont_atexit();
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

namespace {

struct LibraryFailure {
  std::string reason;    // the system's text for the errno when there is one, else HDF5's innermost
  int error_number = 0;  // the errno HDF5 recorded, 0 when none
};

// What HDF5's current error stack says went wrong, and clears it.
LibraryFailure library_failure() {
  LibraryFailure failure;
  // Walking downward ends at the deepest entry, the most specific reason. The POSIX driver
  // puts the errno into its text ("..., errno = 28, error message = '...'").
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned, const H5E_error2_t* e, void* out) -> herr_t {
        auto& f = *static_cast<LibraryFailure*>(out);
        if (!e->desc || !*e->desc) return 0;
        f.reason = e->desc;
        if (const char* at = std::strstr(e->desc, "errno = ")) {
          const int n = std::atoi(at + 8);
          if (n > 0) f.error_number = n;
        }
        return 0;
      },
      &failure);
  H5Eclear2(H5E_DEFAULT);
  if (failure.error_number) {
    failure.reason = std::strerror(failure.error_number);
    if (!failure.reason.empty()) failure.reason[0] = char(std::tolower(static_cast<unsigned char>(failure.reason[0])));
  }
  return failure;
}

// A scalar attribute, replacing one of the same name.
void write_scalar(hid_t loc, const char* name, hid_t file_type, hid_t mem_type, const void* value,
                  const std::string& where) {
  const std::string at = where + " attribute '" + name + "'";
  if (H5Aexists(loc, name) > 0) check(H5Adelete(loc, name), at, "delete");
  Handle space = own(H5Screate(H5S_SCALAR), H5Sclose, at, "create dataspace");
  Handle attr = own(H5Acreate2(loc, name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                    at, "create");
  check(H5Awrite(attr.get(), mem_type, value), at, "write");
}

Handle open_attr(hid_t loc, const char* name, const std::string& at) {
  if (H5Aexists(loc, name) <= 0) fail(at + ": missing");
  return own(H5Aopen(loc, name, H5P_DEFAULT), H5Aclose, at, "open");
}

// A number attribute converted to `mem_type` by HDF5.
template <class T>
T read_number(hid_t loc, const char* name, hid_t mem_type, const std::string& where) {
  const std::string at = where + " attribute '" + name + "'";
  Handle attr = open_attr(loc, name, at);
  T value = 0;
  check(H5Aread(attr.get(), mem_type, &value), at, "read");
  return value;
}

}  // namespace

hid_t check(hid_t result, const std::string& where, const char* what) {
  if (result < 0) {
    const LibraryFailure f = library_failure();
    const std::string message = where + ": " + what + " failed" + (f.reason.empty() ? "" : ": " + f.reason);
    if (f.error_number) throw IoError(message, f.reason, f.error_number);
    throw LibraryError(message, f.reason);
  }
  return result;
}

Handle own(hid_t id, Handle::Closer close, const std::string& where, const char* what) {
  check(id, where, what);
  return Handle(id, close);
}

void write_attr(hid_t loc, const char* name, const std::string& value, const std::string& where) {
  const std::string at = where + " attribute '" + name + "'";
  Handle type = own(H5Tcopy(H5T_C_S1), H5Tclose, at, "copy string type");
  check(H5Tset_size(type.get(), H5T_VARIABLE), at, "set string size");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), at, "set character set");
  const char* text = value.c_str();
  write_scalar(loc, name, type.get(), type.get(), &text, where);
}

void write_attr(hid_t loc, const char* name, double value, const std::string& where) {
  write_scalar(loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value, where);
}

void write_attr(hid_t loc, const char* name, int64_t value, const std::string& where) {
  write_scalar(loc, name, H5T_STD_I64LE, H5T_NATIVE_INT64, &value, where);
}

void write_attr(hid_t loc, const char* name, uint64_t value, const std::string& where) {
  write_scalar(loc, name, H5T_STD_U64LE, H5T_NATIVE_UINT64, &value, where);
}

bool has_attr(hid_t loc, const char* name) { return H5Aexists(loc, name) > 0; }

std::vector<std::string> attr_names(hid_t loc, const std::string& where) {
  std::vector<std::string> names;
  hsize_t index = 0;
  check(H5Aiterate2(
            loc, H5_INDEX_NAME, H5_ITER_INC, &index,
            [](hid_t, const char* name, const H5A_info_t*, void* out) -> herr_t {
              static_cast<std::vector<std::string>*>(out)->push_back(name);
              return 0;
            },
            &names),
        where, "list attributes");
  return names;
}

std::string read_string_attr(hid_t loc, const char* name, const std::string& where) {
  const std::string at = where + " attribute '" + name + "'";
  Handle attr = open_attr(loc, name, at);
  Handle type = own(H5Aget_type(attr.get()), H5Tclose, at, "get type");
  if (H5Tget_class(type.get()) != H5T_STRING) fail(at + ": not a string");
  if (H5Tis_variable_str(type.get()) > 0) {
    Handle mem = own(H5Tcopy(H5T_C_S1), H5Tclose, at, "copy string type");
    check(H5Tset_size(mem.get(), H5T_VARIABLE), at, "set string size");
    check(H5Tset_cset(mem.get(), H5Tget_cset(type.get())), at, "set character set");
    char* text = nullptr;
    check(H5Aread(attr.get(), mem.get(), &text), at, "read");
    std::string value = text ? text : "";
    H5free_memory(text);
    return value;
  }
  const size_t size = H5Tget_size(type.get());
  std::string value(size, '\0');
  check(H5Aread(attr.get(), type.get(), value.data()), at, "read");
  value.resize(value.find('\0') == std::string::npos ? size : value.find('\0'));
  return value;
}

double read_double_attr(hid_t loc, const char* name, const std::string& where) {
  return read_number<double>(loc, name, H5T_NATIVE_DOUBLE, where);
}

int64_t read_int_attr(hid_t loc, const char* name, const std::string& where) {
  return read_number<int64_t>(loc, name, H5T_NATIVE_INT64, where);
}

}  // namespace cdb::h5
