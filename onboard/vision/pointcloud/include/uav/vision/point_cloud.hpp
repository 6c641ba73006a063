#pragma once
// Point-cloud operations of the stereo obstacle pipeline (thesis 3.5): voxel-grid
// down-sampling, removal of the ground plane, Euclidean clustering, and PCD files. PCL-free
// interface; PCL is used inside one translation unit only.
#include <string>
#include <vector>

#include <Eigen/Core>

namespace uav::vision {

// Returns one point (the centroid) per occupied cubic voxel of edge `leaf_m` [m].
// Throws std::invalid_argument when leaf_m is not a positive finite number.
std::vector<Eigen::Vector3f> VoxelDownsample(const std::vector<Eigen::Vector3f>& points, float leaf_m);

// Indices of the points on the plane with the most inliers (RANSAC) among planes whose normal
// is within max_tilt_rad of `normal`, within distance_m of it; empty when no such plane holds
// at least min_inliers points.
std::vector<int> PlaneInliers(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& normal,
                              double max_tilt_rad, double distance_m, int min_inliers);

// Euclidean clusters (points joined when closer than tolerance_m), each the indices of its
// points, largest first; clusters of fewer than min_points are dropped.
std::vector<std::vector<int>> EuclideanClusters(const std::vector<Eigen::Vector3f>& points, double tolerance_m,
                                                int min_points);

// Writes a binary PCD file (opens in pcl_viewer) through a temporary name, so a failed write
// leaves no half-written file. Throws std::runtime_error naming the path.
void WritePcd(const std::string& path, const std::vector<Eigen::Vector3f>& points);

}  // namespace uav::vision
