#pragma once
// Host (CPU) memory the native mark backends keep from frame to frame: the
// images they draw into and their threads' scratch, so that a frame does
// not page-fault tens of megabytes in anew. The Renderer owns it (one per
// renderer, reached through MarkContext::host): it is counted in the frame's
// statistics, released when the renderer goes, and released after a frame
// that leaves more kept than the frame's memory budget.
#include <cstddef>
#include <memory>
#include <typeindex>
#include <unordered_map>
#include <vector>

namespace pointnpr {

// Bytes a vector holds (its capacity).
template <class T>
size_t held_bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

// Hands pages freed on the heap back to the system: blocks below glibc's
// (adaptive) mmap threshold come from the heap, and without a trim the
// process keeps their pages after they are freed.
void return_freed_pages();

class HostScratch {
 public:
  // The kept object of type T, made on first use; T tells its size by
  // `size_t bytes() const`. Objects are told apart by type: each backend
  // keeps a type of its own, declared in its anonymous namespace (two
  // same-named types with external linkage would share one slot).
  template <class T>
  T& get() {
    std::unique_ptr<Kept>& slot = kept_[std::type_index(typeid(T))];
    if (!slot) slot = std::make_unique<Holder<T>>();
    return static_cast<Holder<T>*>(slot.get())->value;
  }
  HostScratch() = default;
  HostScratch(const HostScratch&) = delete;
  HostScratch& operator=(const HostScratch&) = delete;
  ~HostScratch() { release(); }
  size_t bytes() const;
  // Frees everything kept, and hands the freed pages back to the system.
  void release();

 private:
  struct Kept {
    virtual ~Kept() = default;
    virtual size_t bytes() const = 0;
  };
  template <class T>
  struct Holder final : Kept {
    T value;
    size_t bytes() const override { return value.bytes(); }
  };
  std::unordered_map<std::type_index, std::unique_ptr<Kept>> kept_;
};

}  // namespace pointnpr
