#pragma once
// Every image read and write goes through OpenImageIO.
#include <string>
#include <vector>

namespace pointnpr {

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float> pixels;  // row 0 = bottom (GL order), interleaved
};

// Writes float pixels; 8/16-bit formats are quantized by OIIO. With
// `linear_to_srgb`, colour channels (not alpha) are encoded to sRGB first;
// premultiplied input is un-premultiplied for formats without associated alpha.
void write_image(const std::string& path, const Image& image, bool linear_to_srgb);
Image read_image(const std::string& path);

}  // namespace pointnpr
