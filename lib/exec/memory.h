#pragma once
#include <cstddef>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

namespace cdb {

// One buffer that had to grow after its first reservation: how often, and from which size
// to which (in elements, or in bytes where the name says so).
struct BufferGrowth {
  std::string buffer;
  size_t times = 0;
  size_t first_count = 0, last_count = 0;
};

// Bytes one buffer name held (a name may stand for several buffers of one kind, e.g. both
// queries' of a tree).
struct BufferBytes {
  std::string buffer;
  size_t bytes = 0;
};

// Accounting every executor's allocator shares: bytes in use, peak, and how many times a
// buffer had to grow after the run started, per buffer. Nothing is printed while frames
// run: the CLI sums the growths up at the end of a run.
struct MemoryStats {
  size_t current_bytes = 0;
  size_t peak_bytes = 0;
  size_t allocations = 0;
  size_t growths = 0;
  std::vector<BufferGrowth> grown;  // one entry per buffer name, in the order they first grew
  // What each buffer held when the peak was reached, in the order the buffers were first
  // allocated: where the peak goes (tests, docs/design.md "Memory").
  std::vector<BufferBytes> at_peak;
};

class MemoryResource {
 public:
  virtual ~MemoryResource() = default;
  virtual bool is_device() const = 0;
  // `name` tallies the bytes per buffer. Allocations are few (set_topology, then growth
  // after a read-back), so the tally's linear search and the copy at each new peak cost a
  // frame nothing.
  void* allocate(size_t bytes, const std::string& name = "unnamed") {
    void* p = do_allocate(bytes);
    stats_.current_bytes += bytes;
    held(name) += bytes;
    if (stats_.current_bytes > stats_.peak_bytes) {
      stats_.peak_bytes = stats_.current_bytes;
      stats_.at_peak = live_;
    }
    ++stats_.allocations;
    return p;
  }
  void deallocate(void* p, size_t bytes, const std::string& name = "unnamed") {
    if (!p) return;
    do_deallocate(p, bytes);
    stats_.current_bytes -= bytes;
    held(name) -= bytes;
  }
  void note_growth(const char* what, size_t old_count, size_t new_count) {
    ++stats_.growths;
    for (BufferGrowth& g : stats_.grown)
      if (g.buffer == what) {
        ++g.times;
        g.last_count = new_count;
        return;
      }
    stats_.grown.push_back({what, 1, old_count, new_count});
  }
  const MemoryStats& stats() const { return stats_; }

 private:
  virtual void* do_allocate(size_t bytes) = 0;
  virtual void do_deallocate(void* p, size_t bytes) = 0;
  size_t& held(const std::string& name) {
    for (BufferBytes& b : live_)
      if (b.buffer == name) return b.bytes;
    live_.push_back({name, 0});
    return live_.back().bytes;
  }
  MemoryStats stats_;
  std::vector<BufferBytes> live_;  // bytes each buffer name holds now
};

// A typed buffer in an executor's memory. Contents are not preserved when it grows: every
// user refills what it reserves.
template <class T>
class Array {
 public:
  Array() = default;
  explicit Array(MemoryResource& mr, std::string name = "buffer") : mr_(&mr), name_(std::move(name)) {}
  Array(const Array&) = delete;
  Array& operator=(const Array&) = delete;
  Array(Array&& o) noexcept { swap(o); }
  Array& operator=(Array&& o) noexcept {
    swap(o);
    return *this;
  }
  ~Array() { release(); }

  void bind(MemoryResource& mr, std::string name) {
    release();
    mr_ = &mr;
    name_ = std::move(name);
  }

  // Makes room for n elements. A first reservation is the planned allocation; a later one
  // that needs more is a growth and is counted.
  void reserve(size_t n) {
    if (n <= capacity_) {
      size_ = n;
      return;
    }
    const size_t old = capacity_;
    release();
    ptr_ = static_cast<T*>(mr_->allocate(n * sizeof(T), name_));
    capacity_ = n;
    size_ = n;
    if (old > 0) mr_->note_growth(name_.c_str(), old, n);
  }

  T* data() { return ptr_; }
  const T* data() const { return ptr_; }
  size_t size() const { return size_; }
  size_t capacity() const { return capacity_; }
  size_t bytes() const { return capacity_ * sizeof(T); }

 private:
  void release() {
    if (ptr_) mr_->deallocate(ptr_, capacity_ * sizeof(T), name_);
    ptr_ = nullptr;
    capacity_ = size_ = 0;
  }
  void swap(Array& o) {
    std::swap(mr_, o.mr_);
    std::swap(name_, o.name_);
    std::swap(ptr_, o.ptr_);
    std::swap(size_, o.size_);
    std::swap(capacity_, o.capacity_);
  }
  MemoryResource* mr_ = nullptr;
  std::string name_ = "buffer";  // names the buffer in the growth summary
  T* ptr_ = nullptr;
  size_t size_ = 0;
  size_t capacity_ = 0;
};

// An array of any element type with its name, for bind_arrays.
struct NamedArray {
  template <class T>
  NamedArray(Array<T>* a, const char* n)
      : array(a), name(n), bind([](void* p, MemoryResource& mr, const std::string& full) {
          static_cast<Array<T>*>(p)->bind(mr, full);
        }) {}
  void* array;
  const char* name;
  void (*bind)(void*, MemoryResource&, const std::string&);
};

// Binds each (array, name) of `arrays` to `mr`, named prefix + name: one list a workspace,
// in place of a bind line an array.
inline void bind_arrays(MemoryResource& mr, const std::string& prefix, std::initializer_list<NamedArray> arrays) {
  for (const NamedArray& a : arrays) a.bind(a.array, mr, prefix + a.name);
}

}  // namespace cdb
