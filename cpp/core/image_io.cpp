#include "core/image_io.h"

#include <OpenImageIO/imageio.h>

#include <cmath>

#include "core/error.h"

namespace pointnpr {

namespace {
float encode_srgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}
}  // namespace

void write_image(const std::string& path, const Image& image, bool linear_to_srgb) {
  if (image.width <= 0 || image.height <= 0 || image.channels <= 0 ||
      image.pixels.size() != size_t(image.width) * size_t(image.height) * size_t(image.channels))
    throw Error("write_image: pixel array does not match width x height x channels");
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw Error("cannot write " + path + ": " + OIIO::geterror());
  OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::FLOAT);
  const bool float_file = out->format_name() == std::string("openexr");
  if (!float_file) spec.set_format(OIIO::TypeDesc::UINT8);
  if (image.channels == 4) spec.alpha_channel = 3;
  const size_t row = size_t(image.width) * size_t(image.channels);
  std::vector<float> flipped(image.pixels.size());
  for (int y = 0; y < image.height; ++y) {
    const float* src = &image.pixels[size_t(image.height - 1 - y) * row];
    float* dst = &flipped[size_t(y) * row];
    for (size_t x = 0; x < row; x += size_t(image.channels)) {
      const bool has_alpha = image.channels == 4;
      const float a = has_alpha ? src[x + 3] : 1.0f;
      for (int c = 0; c < image.channels; ++c) {
        float v = src[x + size_t(c)];
        const bool color = !(has_alpha && c == 3);
        if (color && has_alpha && !float_file) v = a > 0.0f ? v / a : 0.0f;  // PNG stores straight alpha
        if (color && linear_to_srgb) v = encode_srgb(v);
        dst[x + size_t(c)] = v;
      }
    }
  }
  if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, flipped.data()) || !out->close())
    throw Error("cannot write " + path + ": " + out->geterror());
}

Image read_image(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error("cannot read " + path + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  Image image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.nchannels;
  std::vector<float> raw(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, raw.data()))
    throw Error("cannot read " + path + ": " + in->geterror());
  const size_t row = size_t(spec.width) * size_t(spec.nchannels);
  image.pixels.resize(raw.size());
  for (int y = 0; y < spec.height; ++y)
    std::copy_n(&raw[size_t(spec.height - 1 - y) * row], row, &image.pixels[size_t(y) * row]);
  return image;
}

}  // namespace pointnpr
