#pragma once
// Segmentation: connected components on an octree level (CloudCompare's
// Label Connected Components), colour region growing (PCL's
// RegionGrowingRGB, seed 004), split by an integer attribute.
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/local_points.h"
#include "geometry/neighbors.h"

namespace pointnpr::geometry {

// CloudCompare's octree: the cube of edge 1.01 * (largest bounding-box
// extent) centred on the bounding box (CCMiscTools::MakeMinAndMaxCubical),
// cells of edge cube/2^level. Points in 26-connected occupied cells form a
// component; components with fewer than min_points points get label -1.
// Labels 0.. by decreasing size (ties: the component holding the lowest
// point index first). cell_size > 0 overrides the level (cells anchored at
// the same cube corner). Original order; all points identical: one cell.
// Cells are computed in double; CloudCompare computes them in float32, so
// a point within float rounding of a cell wall can land in the other cell
// there. float32 = true replays CloudCompare's float arithmetic (DgmOctree:
// cube in float, cell position = int((p - min) / cell_size(21)) >> (21 -
// level)) on the coordinates as given - those CloudCompare works on, after
// its global shift - and then gives its partition exactly.
struct Components {
  std::vector<int32_t> labels;
  int32_t count = 0;         // kept components
  double cell_size = 0.0;
};
Components connected_components(std::span<const double> xyz, int level, uint32_t min_points, double cell_size = 0.0,
                                bool float32 = false);

// PCL RegionGrowingRGB (no normal or curvature test), step by step: (1)
// from seeds in index order, regions grow breadth-first over each point's
// k nearest neighbours while the RGB distance between a point and its
// neighbour is <= point_color_threshold; (2) each segment's neighbours are
// the region_neighbours nearest segments that its points' region_neighbours
// nearest points reach (at the nearest such point distance); in segment
// order, a segment takes each unlabelled neighbour within
// distance_threshold whose mean colour (truncated to integers) differs by
// < region_color_threshold into its region; (3) regions smaller than
// min_cluster_size, in region order, join the region of their nearest
// neighbouring segment; (4) regions outside [min_cluster_size,
// max_cluster_size] get label -1. Thresholds are distances, as PCL's
// setters make them (they square them). PCL's defaults are k = 30,
// region_neighbours = 100; region_neighbours = 0 here means k. Exactly
// PCL's partition but where two distances tie (PCL's kNN and its sort of
// region neighbours break ties arbitrarily): see bench/pcl_region_growing.
// Colours: packed RGBA8 in LocalPoints order. Labels in original order,
// 0.. by decreasing size.
struct RegionGrowingParams {
  int k = 30;
  int region_neighbours = 0;
  double distance_threshold = 0.05;
  double point_color_threshold = 6.0;
  double region_color_threshold = 5.0;
  uint32_t min_cluster_size = 10;
  uint32_t max_cluster_size = 0xffffffffu;
};
Components region_growing_rgb(const LocalPoints& pts, const Neighborhoods& nb, const std::vector<uint32_t>& colors_sorted,
                              const RegionGrowingParams& params);

// Groups of point indices sharing a value, by increasing value.
struct Group {
  int64_t value;
  std::vector<uint32_t> indices;
};
std::vector<Group> split_by_attribute(std::span<const int64_t> values);

// Relabels so that labels are 0.. by decreasing size (ties: lowest first
// index); entries < 0 stay -1. Returns the number of labels.
int32_t relabel_by_size(std::vector<int32_t>& labels);

}  // namespace pointnpr::geometry
