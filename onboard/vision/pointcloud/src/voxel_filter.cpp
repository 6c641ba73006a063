#include "uav/vision/voxel_filter.hpp"

#include <cmath>
#include <stdexcept>

#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace uav::vision {

std::vector<Eigen::Vector3f> VoxelDownsample(const std::vector<Eigen::Vector3f>& points,
                                             float leaf_m) {
  if (!std::isfinite(leaf_m) || leaf_m <= 0.0f)
    throw std::invalid_argument("voxel leaf size must be a positive finite number of metres");
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(points.size());
  for (const auto& p : points) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
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

}  // namespace uav::vision
