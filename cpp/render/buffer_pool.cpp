#include "render/renderer.h"

namespace pointnpr {

namespace {
template <class T>
std::vector<T> take(std::vector<std::vector<T>>& list, size_t size) {
  for (auto it = list.begin(); it != list.end(); ++it)
    if (it->size() == size) {
      std::vector<T> v = std::move(*it);
      list.erase(it);
      return v;
    }
  return std::vector<T>(size);
}
template <class T>
void keep(std::vector<std::vector<T>>& list, std::vector<T>&& v) {
  constexpr size_t kMaxKept = 6;  // a few frames' worth, in flight at once
  if (!v.empty() && list.size() < kMaxKept) list.push_back(std::move(v));
}
}  // namespace

std::vector<float> BufferPool::take_floats(size_t size) {
  std::lock_guard lock(mutex_);
  return take(floats_, size);
}
std::vector<int32_t> BufferPool::take_ints(size_t size) {
  std::lock_guard lock(mutex_);
  return take(ints_, size);
}
void BufferPool::give(std::vector<float>&& v) {
  std::lock_guard lock(mutex_);
  keep(floats_, std::move(v));
}
void BufferPool::give(std::vector<int32_t>&& v) {
  std::lock_guard lock(mutex_);
  keep(ints_, std::move(v));
}

RenderResult::~RenderResult() {
  if (!pool) return;
  pool->give(std::move(color));
  pool->give(std::move(depth));
  pool->give(std::move(segment_index));
}

}  // namespace pointnpr
