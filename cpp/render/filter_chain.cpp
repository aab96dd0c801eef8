#include "render/filter_chain.h"

#include <string>
#include <utility>

#include "gl/device.h"

namespace pointnpr {

FilterStep make_filter_step(const std::string& id, const std::map<std::string, std::vector<double>>& params,
                            const std::map<std::string, std::string>& paths) {
  const FilterInfo& info = find_filter(id);
  FilterStep step;
  step.info = &info;
  step.params = validate(info.schema, params, paths);
  step.filter = info.create();
  return step;
}

int total_footprint(const std::vector<FilterStep>& steps) {
  int total = 0;
  for (const FilterStep& f : steps) total += f.filter->footprint(f.params);
  return total;
}

const gl::Texture* run_filter_chain(const std::vector<FilterStep>& steps, const FilterChainImages& in, Rect& rect) {
  const gl::Texture* current = in.first;
  const gl::Texture* other = in.second;
  for (const FilterStep& f : steps) {
    rect = rect.grown(f.filter->footprint(f.params), in.image_size);
    FilterContext ctx;
    ctx.shaders = in.shaders;
    ctx.images = in.images;
    ctx.input = current;
    ctx.output = other;
    ctx.raster_depth = in.raster_depth;
    ctx.scratch = in.scratch;
    ctx.rect = rect;
    ctx.image_size = in.image_size;
    ctx.time = in.time;
    ctx.segment_seed = in.segment_seed;
    ctx.surface = in.surface;
    f.filter->apply(ctx, f.params);
    gl::check_gl(("filter " + f.info->schema.id).c_str());
    std::swap(current, other);
  }
  return current;
}

}  // namespace pointnpr
