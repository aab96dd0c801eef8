#include "io/mapped_file.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <fstream>

#include "core/error.h"

#if defined(__unix__) || defined(__APPLE__)
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#define POINTNPR_HAVE_MMAP 1
#endif

namespace pointnpr::io {

namespace {
// Files up to this size are mapped populated (MAP_POPULATE).
constexpr size_t kPopulateLimit = size_t{64} << 20;
}  // namespace

MappedFile::MappedFile(const std::string& path, Access access) : path_(path) {
#ifdef POINTNPR_HAVE_MMAP
  // Non-blocking: opening a FIFO without a writer would wait forever; it is
  // refused below like any file that is not a regular one.
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw ReadError(path, std::string("cannot open file: ") + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    int e = errno;
    ::close(fd);
    throw ReadError(path, std::string("cannot stat file: ") + std::strerror(e));
  }
  if (S_ISDIR(st.st_mode)) {
    ::close(fd);
    throw ReadError(path, "is a directory, not a point cloud file");
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    throw ReadError(path, "is not a regular file (a named pipe, device or socket is not a point cloud file)");
  }
  size_ = static_cast<size_t>(st.st_size);
  if (size_ > 0) {
    // The readers go through the whole file: map small ones populated (one
    // call instead of a page fault per 4 KB). Large ones are faulted in as
    // they are read (the kernel maps 64 KB around each fault) and released
    // block by block (release()), so they never reside whole.
    int flags = MAP_PRIVATE;
#ifdef MAP_POPULATE
    if (access == Access::Sequential && size_ <= kPopulateLimit) flags |= MAP_POPULATE;
#endif
    void* p = ::mmap(nullptr, size_, PROT_READ, flags, fd, 0);
    if (p == MAP_FAILED) {
      int e = errno;
      ::close(fd);
      throw ReadError(path, std::string("cannot map file into memory: ") + std::strerror(e));
    }
    ::madvise(p, size_, access == Access::Sequential ? MADV_SEQUENTIAL : MADV_RANDOM);
    map_ = p;
    data_ = static_cast<const uint8_t*>(p);
  }
  ::close(fd);
#else
  (void)access;
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw ReadError(path, "cannot open file");
  std::streamoff n = in.tellg();
  if (n < 0) throw ReadError(path, "cannot determine file size");
  fallback_.resize(static_cast<size_t>(n));
  in.seekg(0);
  if (n > 0 && !in.read(reinterpret_cast<char*>(fallback_.data()), n))
    throw ReadError(path, "cannot read file");
  data_ = fallback_.data();
  size_ = fallback_.size();
#endif
}

void MappedFile::release(size_t offset, size_t bytes) const {
#ifdef POINTNPR_HAVE_MMAP
  if (!map_ || offset >= size_) return;
  bytes = std::min(bytes, size_ - offset);
  // Every page the range touches (madvise wants page-aligned starts). A
  // page shared with bytes still to be read (a block decoded in parallel
  // next to this one, a neighbouring chunk) is read again from the file
  // when next touched: a private read-only mapping loses nothing.
  const size_t page = size_t(::sysconf(_SC_PAGESIZE));
  const size_t begin = offset / page * page;
  const size_t end = offset + bytes;
  if (end > begin) ::madvise(static_cast<uint8_t*>(map_) + begin, end - begin, MADV_DONTNEED);
#else
  (void)offset;
  (void)bytes;
#endif
}

MappedFile::~MappedFile() {
#ifdef POINTNPR_HAVE_MMAP
  if (map_) ::munmap(map_, size_);
#endif
}

std::string file_extension(const std::string& path) {
  size_t slash = path.find_last_of("/\\");
  size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace pointnpr::io
