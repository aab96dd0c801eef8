#pragma once
// Ink of marks drawn as GL primitives (strokes, sprites), blended
// order-independently and deterministically into three scratch images over
// the mark's clip: colour weighted by alpha (a sum), transmittance (a
// product) and the nearest depth (a minimum). Sums and products in a fixed
// primitive order give the same bytes in every run, whatever the order the
// marks were generated in. A fragment shader writes (rgb * a, a), (a) and
// (linear depth) to locations 0, 1, 2. resolve() lays the ink over paper
// into the segment's colour and depth (shaders/ink_resolve.comp).
#include <vector>

#include <glm/vec4.hpp>

#include "render/exact_raster.h"
#include "render/mark.h"

namespace pointnpr {

class InkLayer {
 public:
  // Clears the ink over ctx.clip and builds its framebuffer (with the
  // frame's GL depth buffer, for depth tests against a depth pass).
  InkLayer(const MarkContext& ctx, const char* what);

  // GL state for drawing ink: its framebuffer, the exact viewport (the
  // marks draw tiles, render/exact_raster.h), scissor to the clip,
  // reversed-Z GEQUAL depth test when asked, no depth writes, the three
  // blend modes.
  void begin(bool depth_test, const ExactRaster& raster) const;
  void end() const;  // back to GL defaults
  // The three blend modes alone (for marks with their own raster state).
  static void blend_modes();

  // Ink over `paper` (display sRGB, alpha = its opacity over the surface)
  // into ctx.targets.color and .depth. With `surface`, ctx.targets.depth
  // holds a depth pass: the paper covers it and its depth wins; elsewhere
  // the ink's nearest depth.
  void resolve(glm::vec4 paper, bool surface) const;

  const gl::Texture& accum;   // RGBA32F
  const gl::Texture& reveal;  // R32F transmittance
  const gl::Texture& depth;   // R32F nearest linear depth

 private:
  const MarkContext& ctx_;
  gl::Framebuffer fbo_;
};

// Marks whose select pass writes records compacted per workgroup of 128
// with one indirect draw each (shaders/compact_records.glsl): batches of
// consecutive chunks whose record slots fit a buffer.
struct DrawCommand {
  uint32_t count, instance_count, first, base_instance;
};
struct RecordBatch {
  size_t begin = 0, end = 0;      // chunks [begin, end)
  std::vector<uint32_t> offsets;  // each chunk's first record slot
  uint32_t used = 0;              // slots, 128 per workgroup
  GLsizei draws() const { return GLsizei(used / 128u); }
};
// Batches of chunks [0, chunks) whose slots (slots_of(i), multiples of 128)
// fit `capacity` (a batch holds at least one chunk).
template <class SlotsOf>
std::vector<RecordBatch> record_batches(size_t chunks, uint32_t capacity, SlotsOf&& slots_of) {
  std::vector<RecordBatch> out;
  for (size_t c = 0; c < chunks;) {
    RecordBatch b;
    b.begin = c;
    while (c < chunks && (c == b.begin || b.used + slots_of(c) <= capacity)) {
      b.offsets.push_back(b.used);
      b.used += slots_of(c++);
    }
    b.end = c;
    out.push_back(std::move(b));
  }
  return out;
}
// The batch's triangles: one indirect draw a workgroup, no vertex input.
void draw_record_batch(const gl::Buffer& commands, const RecordBatch& batch);
// The records the batch drew, in draw order (`vertices` per record): what a
// capture of the marks reports.
template <class Record>
std::vector<Record> drawn_records(const gl::Buffer& records, const gl::Buffer& commands, const RecordBatch& batch,
                                  uint32_t vertices) {
  std::vector<Record> all(batch.used), out;
  std::vector<DrawCommand> issued(size_t(batch.draws()));
  glGetNamedBufferSubData(records.id(), 0, GLsizeiptr(all.size() * sizeof(Record)), all.data());
  glGetNamedBufferSubData(commands.id(), 0, GLsizeiptr(issued.size() * sizeof(DrawCommand)), issued.data());
  for (const DrawCommand& cmd : issued)
    for (uint32_t r = cmd.first / vertices; r < (cmd.first + cmd.count) / vertices; ++r) out.push_back(all[r]);
  return out;
}

}  // namespace pointnpr
