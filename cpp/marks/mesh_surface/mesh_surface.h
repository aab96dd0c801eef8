#pragma once
// The mesh_surface mark (marks/mesh_surface/mesh_surface.cpp): how a segment's objects
// with faces are drawn. Every style has one (Style::surface) beside its
// point mark; the renderer asks it what to do with each mesh.
#include <set>

#include "core/params.h"
#include "render/gpu_mesh.h"

namespace pointnpr {

// surface: triangles, drawn by this mark; points: the mesh's vertices, drawn
// by the style's point mark; sampled: points sampled on the surface
// (sample_density per square scene unit), drawn by the point mark.
enum class MeshMode { Surface = 0, Points = 1, Sampled = 2 };
MeshMode mesh_mode(const ParamValues& surface_params);
double mesh_sample_density(const ParamValues& surface_params);
// The per-corner attributes the surface reads with these parameters.
std::set<MeshAttribute> mesh_attributes(const ParamValues& surface_params);

}  // namespace pointnpr
