#include "render/host_scratch.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace pointnpr {

size_t HostScratch::bytes() const {
  size_t n = 0;
  for (const auto& [type, kept] : kept_) n += kept->bytes();
  return n;
}

void return_freed_pages() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

void HostScratch::release() {
  kept_.clear();
  return_freed_pages();
}

}  // namespace pointnpr
