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

void HostScratch::release() {
  kept_.clear();
#if defined(__GLIBC__)
  // Images below glibc's (adaptive) mmap threshold were taken from the heap:
  // without a trim the process would keep their pages.
  malloc_trim(0);
#endif
}

}  // namespace pointnpr
