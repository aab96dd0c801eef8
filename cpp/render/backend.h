#pragma once
// Which backend draws a mark that has two: GL's passes or the native ones
// on the CPU's threads. One choice for every such mark: its `rasterizer`
// names the backend or "auto", and auto takes the native passes where GL
// itself runs on the CPU (llvmpipe, where they are faster) and GL on a GPU.
#include <string>

#include "core/params.h"
#include "gl/device.h"

namespace pointnpr {

enum class Backend { Gl, Native };

// The backend parameter of every mark that has two: the same values, in the
// same order (gl, native, auto), and the same auto rule; `doc` says what gl
// and native draw on that mark.
inline ParamSpec rasterizer_param(const std::string& doc) {
  return enum_param("rasterizer", {"gl", "native", "auto"}, 2,
                    doc + "; auto: native on a software GL device (llvmpipe), gl on a GPU");
}

// The backend the mark's `rasterizer` asks for: gl, native, or by the device.
inline Backend chosen_backend(const ParamValues& p) {
  const std::string value = p.get_enum_name("rasterizer");
  if (value == "native") return Backend::Native;
  if (value == "auto") return gl::Device::instance().info().software ? Backend::Native : Backend::Gl;
  return Backend::Gl;
}

}  // namespace pointnpr
