// PointNPR's colour region growing against PCL's RegionGrowingRGB, side by
// side on the same points and parameters: the number of regions, whether
// the partitions are identical (regions compared as sets of points), how
// many points lie in regions both agree on, and the time of each (PCL
// single-threaded, as it is; PointNPR on all cores, its kNN included).
// Built only where PCL is installed (apt-get install libpcl-dev); see
// docs/geometry.md.
//
//   pcl_region_growing [--jitter] <cloud> [k region_neighbours distance point_colour region_colour min_size]
//
// --jitter moves every point by up to 1 % of the median point spacing
// (seeded): scans stored on a grid (LAS, quantised PLY) have countless
// equal distances, which PCL's kNN breaks in no particular order and
// PointNPR by index, so their partitions differ through ties alone.
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/region_growing_rgb.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "geometry/analysis.h"
#include "io/readers.h"

using namespace pointnpr;

namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

int main(int argc, char** argv) {
  const bool jitter = argc > 1 && std::string(argv[1]) == "--jitter";
  if (jitter) {
    --argc;
    ++argv;
  }
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s <cloud> [k region_neighbours distance point_colour region_colour min_size]\n",
                 argv[0]);
    return 2;
  }
  PointData data = read_point_cloud(argv[1]);
  if (jitter) {
    geometry::Analysis spacing(data.positions);
    std::vector<float> r = spacing.local_resolution(1)->r;
    std::nth_element(r.begin(), r.begin() + long(r.size() / 2), r.end());
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-1e-2 * r[r.size() / 2], 1e-2 * r[r.size() / 2]);
    for (double& v : data.positions) v += u(rng);
  }
  const auto* rgb = data.get<uint8_t>("colors");
  if (!rgb) {
    std::fprintf(stderr, "%s has no colours\n", argv[1]);
    return 2;
  }
  geometry::RegionGrowingParams prm;
  prm.k = argc > 2 ? std::stoi(argv[2]) : 30;
  prm.region_neighbours = argc > 3 ? std::stoi(argv[3]) : 100;
  prm.distance_threshold = argc > 4 ? std::stod(argv[4]) : 0.05;
  prm.point_color_threshold = argc > 5 ? std::stod(argv[5]) : 6.0;
  prm.region_color_threshold = argc > 6 ? std::stod(argv[6]) : 5.0;
  prm.min_cluster_size = argc > 7 ? uint32_t(std::stoul(argv[7])) : 10;
  const size_t n = data.num_points();
  std::vector<uint32_t> colors(n);
  for (size_t i = 0; i < n; ++i)
    colors[i] = uint32_t((*rgb)[3 * i]) | uint32_t((*rgb)[3 * i + 1]) << 8 | uint32_t((*rgb)[3 * i + 2]) << 16;

  // Ours, from the double positions (LocalPoints: float offsets from the
  // bounding-box centre).
  const auto t0 = std::chrono::steady_clock::now();
  geometry::Analysis ours(data.positions, colors);
  const geometry::Components mine = ours.region_growing_rgb(prm);
  const double ours_s = seconds_since(t0);

  // PCL, on exactly the same float offsets.
  const geometry::LocalPoints& lp = ours.points();
  pcl::PointCloud<pcl::PointXYZRGB>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZRGB>);
  cloud->resize(n);
  for (size_t s = 0; s < n; ++s) {
    auto& q = (*cloud)[lp.original[s]];
    q.x = lp.points[s].x;
    q.y = lp.points[s].y;
    q.z = lp.points[s].z;
    const uint32_t c = colors[lp.original[s]];
    q.r = uint8_t(c);
    q.g = uint8_t(c >> 8);
    q.b = uint8_t(c >> 16);
  }
  const auto t1 = std::chrono::steady_clock::now();
  pcl::search::KdTree<pcl::PointXYZRGB>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZRGB>);
  pcl::RegionGrowingRGB<pcl::PointXYZRGB> reg;
  reg.setInputCloud(cloud);
  reg.setSearchMethod(tree);
  reg.setNumberOfNeighbours(unsigned(prm.k));
  reg.setNumberOfRegionNeighbours(unsigned(prm.region_neighbours));
  reg.setDistanceThreshold(float(prm.distance_threshold));
  reg.setPointColorThreshold(float(prm.point_color_threshold));
  reg.setRegionColorThreshold(float(prm.region_color_threshold));
  reg.setMinClusterSize(int(prm.min_cluster_size));
  std::vector<pcl::PointIndices> clusters;
  reg.extract(clusters);
  const double pcl_s = seconds_since(t1);

  // Regions as sorted point sets; agreement = points in regions both have.
  std::vector<std::vector<uint32_t>> theirs, mine_sets(size_t(mine.count));
  for (const auto& c : clusters) {
    theirs.emplace_back(c.indices.begin(), c.indices.end());
    std::sort(theirs.back().begin(), theirs.back().end());
  }
  for (size_t i = 0; i < n; ++i)
    if (mine.labels[i] >= 0) mine_sets[size_t(mine.labels[i])].push_back(uint32_t(i));
  std::map<std::vector<uint32_t>, int> index;
  for (const auto& set : theirs) ++index[set];
  size_t agreed = 0;
  for (const auto& set : mine_sets)
    if (auto it = index.find(set); it != index.end() && it->second > 0) {
      --it->second;
      agreed += set.size();
    }
  size_t in_theirs = 0;
  for (const auto& set : theirs) in_theirs += set.size();
  const bool identical = agreed == in_theirs && theirs.size() == mine_sets.size();
  std::printf("| %s%s | %zu | %d / %d | %d / %d | %zu / %zu | %s | %.2f %% | %.3f | %.3f | %.1fx |\n", argv[1], jitter ? " (jittered)" : "", n,
              prm.k, prm.region_neighbours, int(theirs.size()), int(mine.count), in_theirs,
              size_t(std::count_if(mine.labels.begin(), mine.labels.end(), [](int32_t l) { return l >= 0; })),
              identical ? "yes" : "no", in_theirs ? 100.0 * double(agreed) / double(in_theirs) : 100.0, pcl_s,
              ours_s, pcl_s / ours_s);
  return 0;
}
