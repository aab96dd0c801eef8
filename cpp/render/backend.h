#pragma once
// Which backend draws a mark that has two: GL's passes or the native ones
// on the CPU's threads. One rule for every such mark: its backend parameter
// names the backend or "auto", and auto takes the native passes where GL
// itself runs on the CPU (llvmpipe, where they are faster) and GL on a GPU.
#include <string>

#include "core/params.h"
#include "gl/device.h"

namespace pointnpr {

enum class Backend { Gl, Native };

// The backend `param` asks for: "native", "auto" (by the device), or any
// other value, which names one of the mark's GL methods.
inline Backend chosen_backend(const ParamValues& p, const char* param = "rasterizer") {
  const std::string value = p.get_enum_name(param);
  if (value == "native") return Backend::Native;
  if (value == "auto") return gl::Device::instance().info().software ? Backend::Native : Backend::Gl;
  return Backend::Gl;
}

}  // namespace pointnpr
