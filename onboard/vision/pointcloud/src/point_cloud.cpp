#include "uav/vision/point_cloud.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <cstdio>
#include <stdexcept>

#include <pcl/ModelCoefficients.h>
#include <pcl/console/print.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/segmentation/sac_segmentation.h>

namespace uav::vision {

namespace {
pcl::PointCloud<pcl::PointXYZ>::Ptr ToPcl(const std::vector<Eigen::Vector3f>& points) {
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(points.size());
  for (const auto& p : points) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  return cloud;
}
}  // namespace

std::vector<Eigen::Vector3f> VoxelDownsample(const std::vector<Eigen::Vector3f>& points, float leaf_m) {
  if (!std::isfinite(leaf_m) || leaf_m <= 0.0f)
    throw std::invalid_argument("voxel leaf size must be a positive finite number of metres");
  const auto cloud = ToPcl(points);
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(cloud);
  grid.setLeafSize(leaf_m, leaf_m, leaf_m);
  pcl::PointCloud<pcl::PointXYZ> out;
  grid.filter(out);
  std::vector<Eigen::Vector3f> result;
  result.reserve(out.size());
  for (const auto& p : out) result.emplace_back(p.x, p.y, p.z);
  return result;
}

std::vector<int> PlaneInliers(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& normal,
                              double max_tilt_rad, double distance_m, int min_inliers) {
  if (static_cast<int>(points.size()) < std::max(3, min_inliers)) return {};
  // A scene without such a plane is an answer here, not an error worth PCL's console message.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  pcl::SACSegmentation<pcl::PointXYZ> seg;
  seg.setOptimizeCoefficients(true);
  seg.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setAxis(normal);
  seg.setEpsAngle(max_tilt_rad);
  seg.setDistanceThreshold(distance_m);
  seg.setMaxIterations(200);
  seg.setInputCloud(ToPcl(points));
  pcl::PointIndices inliers;
  pcl::ModelCoefficients coefficients;
  seg.segment(inliers, coefficients);
  if (static_cast<int>(inliers.indices.size()) < min_inliers) return {};
  return inliers.indices;
}

std::vector<std::vector<int>> EuclideanClusters(const std::vector<Eigen::Vector3f>& points, double tolerance_m,
                                                int min_points) {
  if (!(std::isfinite(tolerance_m) && tolerance_m > 0))
    throw std::invalid_argument("cluster tolerance must be a positive number of metres");
  if (points.empty()) return {};
  // The connected components of "closer than tolerance_m", as PCL's EuclideanClusterExtraction
  // finds them, without its radius search per point (55 of the 90 ms of an obstacle pass on a
  // KITTI pair, 20,000 voxels). Cells of edge tolerance / sqrt(3): two points in one cell are
  // within the tolerance (the cell's diagonal), so a cell is joined whole at once; two cells
  // are compared point by point only while they are in different clusters, and only when
  // their nearest corners are within the tolerance (offsets up to 2 cells, not all three 2).
  const double cell = tolerance_m / std::sqrt(3.0) * (1.0 - 1e-9);
  const float tolerance2 = static_cast<float>(tolerance_m * tolerance_m);
  const std::size_t n = points.size();
  // Cell coordinates from the cloud's lowest corner, 21 bits an axis packed into one key (a
  // cloud up to 2^21 cells across: 240 km at 20 cm), with 2 cells of margin for the neighbours.
  std::vector<std::array<int64_t, 3>> at(n);
  std::array<int64_t, 3> lowest{INT64_MAX, INT64_MAX, INT64_MAX};
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f& p = points[i];
    if (!p.allFinite()) throw std::invalid_argument("point " + std::to_string(i) + " is not finite");
    for (std::size_t a = 0; a < 3; ++a) {
      const double k = std::floor(p[static_cast<int>(a)] / cell);
      if (std::abs(k) > 1e15) throw std::invalid_argument("point " + std::to_string(i) + " is too far for the cluster grid");
      at[i][a] = static_cast<int64_t>(k);
      lowest[a] = std::min(lowest[a], at[i][a]);
    }
  }
  constexpr int64_t kAxis = int64_t{1} << 21;
  const auto pack = [](int64_t x, int64_t y, int64_t z) { return static_cast<uint64_t>((x * kAxis + y) * kAxis + z); };
  std::vector<uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::array<int64_t, 3> k;
    for (std::size_t a = 0; a < 3; ++a) {
      k[a] = at[i][a] - lowest[a] + 2;
      if (k[a] >= kAxis - 2) throw std::invalid_argument("the cloud is too wide for the cluster grid (over 2^21 cells across)");
    }
    key[i] = pack(k[0], k[1], k[2]);
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return key[static_cast<std::size_t>(a)] < key[static_cast<std::size_t>(b)]; });
  // Cells as runs of `order`: cell c holds order[range[c].first, range[c].second), found by its
  // key in an open-addressing table (linear probing, at most half full).
  std::vector<uint64_t> cell_keys;
  std::vector<std::pair<int, int>> range;
  for (int b = 0; b < static_cast<int>(n);) {
    const uint64_t k = key[static_cast<std::size_t>(order[static_cast<std::size_t>(b)])];
    int e = b + 1;
    while (e < static_cast<int>(n) && key[static_cast<std::size_t>(order[static_cast<std::size_t>(e)])] == k) ++e;
    cell_keys.push_back(k);
    range.emplace_back(b, e);
    b = e;
  }
  std::size_t slots = 16;
  int slot_bits = 4;
  while (slots < 2 * cell_keys.size()) slots *= 2, ++slot_bits;
  constexpr uint64_t kEmpty = ~uint64_t{0};
  std::vector<uint64_t> slot_key(slots, kEmpty);
  std::vector<int> slot_cell(slots, -1);
  const auto slot_of = [&](uint64_t k) {
    // MurmurHash3's finaliser: neighbouring cells' keys differ in a few low bits.
    uint64_t h = k ^ (k >> 33);
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    std::size_t s = static_cast<std::size_t>(h >> (64 - slot_bits));
    while (slot_key[s] != kEmpty && slot_key[s] != k) s = (s + 1) & (slots - 1);
    return s;
  };
  for (int c = 0; c < static_cast<int>(cell_keys.size()); ++c) {
    const std::size_t s = slot_of(cell_keys[static_cast<std::size_t>(c)]);
    slot_key[s] = cell_keys[static_cast<std::size_t>(c)];
    slot_cell[s] = c;
  }
  // The neighbours' key offsets: each pair of cells once (the neighbour after this one in key
  // order), and not the corners two cells away on every axis (their nearest points are over the
  // tolerance). Nearest first: once the near cells are joined, most far ones are already in the
  // same cluster and cost no comparison.
  std::vector<std::pair<int64_t, int64_t>> by_distance;  // (squared centre distance, offset)
  for (int64_t dx = -2; dx <= 2; ++dx)
    for (int64_t dy = -2; dy <= 2; ++dy)
      for (int64_t dz = -2; dz <= 2; ++dz) {
        const int64_t offset = (dx * kAxis + dy) * kAxis + dz;
        if (offset > 0 && !(std::abs(dx) == 2 && std::abs(dy) == 2 && std::abs(dz) == 2))
          by_distance.emplace_back(dx * dx + dy * dy + dz * dz, offset);
      }
  std::sort(by_distance.begin(), by_distance.end());
  std::vector<int64_t> offsets;
  for (const auto& [distance2, offset] : by_distance) offsets.push_back(offset);
  // Union-find over cells (a cell is one cluster or part of one).
  std::vector<int> parent(cell_keys.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int i) {
    while (parent[static_cast<std::size_t>(i)] != i)
      i = parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    return i;
  };
  for (int c = 0; c < static_cast<int>(cell_keys.size()); ++c) {
    const auto [b0, e0] = range[static_cast<std::size_t>(c)];
    for (const int64_t offset : offsets) {
      const std::size_t s = slot_of(cell_keys[static_cast<std::size_t>(c)] + static_cast<uint64_t>(offset));
      const int d = slot_cell[s];
      if (d < 0 || find(c) == find(d)) continue;
      const auto [b1, e1] = range[static_cast<std::size_t>(d)];
      bool near = false;
      for (int i = b0; i < e0 && !near; ++i)
        for (int j = b1; j < e1 && !near; ++j)
          near = (points[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])] -
                  points[static_cast<std::size_t>(order[static_cast<std::size_t>(j)])])
                     .squaredNorm() < tolerance2;
      if (near) parent[static_cast<std::size_t>(find(c))] = find(d);
    }
  }
  // Clusters as PCL gives them: indices ascending, largest first (ties: the lowest index first).
  std::vector<std::vector<int>> by_root(cell_keys.size());
  for (int c = 0; c < static_cast<int>(cell_keys.size()); ++c) {
    const auto [b, e] = range[static_cast<std::size_t>(c)];
    std::vector<int>& members = by_root[static_cast<std::size_t>(find(c))];
    for (int i = b; i < e; ++i) members.push_back(order[static_cast<std::size_t>(i)]);
  }
  std::vector<std::vector<int>> clusters;
  for (std::vector<int>& members : by_root) {
    if (members.empty() || static_cast<int>(members.size()) < std::max(1, min_points)) continue;
    std::sort(members.begin(), members.end());
    clusters.push_back(std::move(members));
  }
  std::sort(clusters.begin(), clusters.end(), [](const std::vector<int>& a, const std::vector<int>& b) {
    return a.size() != b.size() ? a.size() > b.size() : a.front() < b.front();
  });
  return clusters;
}

void WritePcd(const std::string& path, const std::vector<Eigen::Vector3f>& points) {
  const auto cloud = ToPcl(points);
  cloud->width = static_cast<uint32_t>(cloud->size());
  cloud->height = 1;
  const std::string temporary = path + ".part";
  if (pcl::io::savePCDFileBinary(temporary, *cloud) != 0) {
    std::remove(temporary.c_str());
    throw std::runtime_error("cannot write point cloud " + path);
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw std::runtime_error("cannot write point cloud " + path);
  }
}

}  // namespace uav::vision
