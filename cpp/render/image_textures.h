#pragma once
// Images that filters sample (colour look-up tables, paper textures): read
// through OpenImageIO on first use, kept as GL textures while the file is
// unchanged (same size and modification time), so an animation reads each
// file once. Lives on the GL thread, owned by the Renderer.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <utility>

#include "gl/objects.h"

namespace pointnpr {

struct Image;  // core/image_io.h

class ImageTextures {
 public:
  // Turns the file's pixels into the RGBA image the filter samples (a LUT
  // re-laid out, a height map...); throws Error on a file it cannot use.
  using Prepare = std::function<Image(Image)>;

  enum class Sampling {
    Tiled,    // repeat wrapping, trilinear over a full mipmap chain (textures)
    Clamped,  // clamp to edge, bilinear, one level (tables such as LUTs)
  };

  // The texture for `path` prepared by `prepare`, registered under `kind`
  // (the same file may be used as two kinds). RGBA32F. Throws Error naming
  // the file when it cannot be read or used.
  const gl::Texture& get(const std::string& path, const std::string& kind, Sampling sampling,
                         const Prepare& prepare);

  size_t loads() const { return loads_; }  // files read so far (tests)

 private:
  struct Entry {
    std::filesystem::file_time_type modified;
    uintmax_t bytes = 0;
    gl::Texture texture;
  };
  std::map<std::pair<std::string, std::string>, Entry> entries_;
  size_t loads_ = 0;
};

// An image's channels expanded to RGBA (grey -> grey, grey, grey; alpha 1).
Image to_rgba(const Image& image);

}  // namespace pointnpr
