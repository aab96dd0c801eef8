#include "render/image_textures.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/image_io.h"
#include "gl/device.h"
#include "render/filter.h"

namespace pointnpr {

ImageTextures& standalone_image_textures() {
  static ImageTextures* cache = new ImageTextures();  // GL objects: kept to process exit, like the context
  return *cache;
}

Image to_rgba(const Image& image) {
  if (image.channels == 4) return image;
  Image out;
  out.width = image.width;
  out.height = image.height;
  out.channels = 4;
  const size_t n = size_t(image.width) * size_t(image.height);
  out.pixels.resize(n * 4);
  for (size_t i = 0; i < n; ++i) {
    const float* src = &image.pixels[i * size_t(image.channels)];
    float* dst = &out.pixels[i * 4];
    const bool grey = image.channels < 3;
    dst[0] = src[0];
    dst[1] = grey ? src[0] : src[1];
    dst[2] = grey ? src[0] : src[2];
    dst[3] = image.channels == 2 ? src[1] : 1.0f;
  }
  return out;
}

const gl::Texture& ImageTextures::get(const std::string& path, const std::string& kind, Sampling sampling,
                                      const Prepare& prepare) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path file(path);
  const auto modified = fs::last_write_time(file, ec);
  const uintmax_t bytes = ec ? 0 : fs::file_size(file, ec);
  if (ec) throw Error("cannot read image '" + path + "': " + ec.message());
  const auto key = std::make_pair(path, kind);
  auto it = entries_.find(key);
  if (it != entries_.end() && it->second.modified == modified && it->second.bytes == bytes) return it->second.texture;

  Image image = prepare(to_rgba(read_image(path)));
  ++loads_;
  if (image.channels != 4 || image.width <= 0 || image.height <= 0)
    throw Error("image '" + path + "' could not be prepared as a " + kind);
  for (float& v : image.pixels)
    if (!std::isfinite(v)) v = 0.0f;  // a float file's NaN/inf must not reach a filter
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  if (image.width > max_size || image.height > max_size)
    throw Error("image '" + path + "' is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                ", larger than this GPU's textures (" + std::to_string(max_size) + ")");
  const bool tiled = sampling == Sampling::Tiled;
  const int levels = tiled ? 1 + int(std::floor(std::log2(double(std::max(image.width, image.height))))) : 1;
  gl::Texture texture(GL_RGBA32F, {image.width, image.height}, levels);
  glTextureSubImage2D(texture.id(), 0, 0, 0, image.width, image.height, GL_RGBA, GL_FLOAT, image.pixels.data());
  if (tiled) glGenerateTextureMipmap(texture.id());
  glTextureParameteri(texture.id(), GL_TEXTURE_MIN_FILTER, tiled ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
  glTextureParameteri(texture.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_S, tiled ? GL_REPEAT : GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_T, tiled ? GL_REPEAT : GL_CLAMP_TO_EDGE);
  gl::check_gl(("upload of image " + path).c_str());
  Entry& entry = entries_[key];
  entry = Entry{modified, bytes, std::move(texture)};
  return entry.texture;
}

}  // namespace pointnpr
