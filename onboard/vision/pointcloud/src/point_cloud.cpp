#include "uav/vision/point_cloud.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <pcl/ModelCoefficients.h>
#include <pcl/console/print.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
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
  const auto cloud = ToPcl(points);
  auto tree = pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  tree->setInputCloud(cloud);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> extraction;
  extraction.setClusterTolerance(tolerance_m);
  extraction.setMinClusterSize(std::max(1, min_points));
  extraction.setMaxClusterSize(static_cast<int>(points.size()));
  extraction.setSearchMethod(tree);
  extraction.setInputCloud(cloud);
  std::vector<pcl::PointIndices> found;
  extraction.extract(found);  // largest first
  std::vector<std::vector<int>> clusters;
  clusters.reserve(found.size());
  for (pcl::PointIndices& c : found) clusters.push_back(std::move(c.indices));
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
