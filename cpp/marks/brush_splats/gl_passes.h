#pragma once
// The brush_splats mark's GL passes that its files share: brush_splats.cpp
// (the depth pass, blending by weighted average and blur, capture) and
// a_buffer.cpp (blending by the A-buffer).
#include <initializer_list>
#include <optional>

#include "core/params.h"
#include "gl/objects.h"
#include "render/exact_raster.h"
#include "render/mark.h"

namespace pointnpr::brush_gl {

// The splat shaders of one pass (PASS_DEPTH, PASS_BLEND, PASS_COUNT, ...).
const gl::Program& splat_program(const MarkContext& ctx, const ParamValues& p, const char* pass);
void set_splat_uniforms(const gl::Program& g, const MarkContext& ctx, const ParamValues& p);
// The exact path's raster (none: the frame's viewport).
void set_raster_viewport(const gl::Program& g, const std::optional<ExactRaster>& raster);
// The passes' framebuffer: colour attachments and the GL depth.
gl::Framebuffer make_fbo(std::initializer_list<const gl::Texture*> colors, const MarkTargets& targets);
// Every visible chunk's splats (queue counts applied), instanced quads.
void draw_all(const MarkContext& ctx, const gl::Program& g, const ParamValues& p);
// The depth test of the splats near the depth pass's surface.
void near_surface_tests(const MarkContext& ctx, const gl::Program& g, const ParamValues& p);

// The rims of brushes over the surface behind (brush_rims.glsl), after
// either blend.
void draw_rims(const MarkContext& ctx, const ParamValues& p);
// Blending by the A-buffer: false (with a warning) where the frame's
// fragments would not fit its budget; nothing is then allocated for them.
bool draw_a_buffer(const MarkContext& ctx, const ParamValues& p, const std::optional<ExactRaster>& raster);

}  // namespace pointnpr::brush_gl
