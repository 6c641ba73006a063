#pragma once
// Voxel-grid down-sampling of a point cloud (thesis 3.5: the stereo pipeline's voxel grid
// filter). PCL-free interface; PCL is used inside only.
#include <vector>

#include <Eigen/Core>

namespace uav::vision {

// Returns one point (the centroid) per occupied cubic voxel of edge `leaf_m` [m].
// Throws std::invalid_argument when leaf_m is not a positive finite number.
std::vector<Eigen::Vector3f> VoxelDownsample(const std::vector<Eigen::Vector3f>& points,
                                             float leaf_m);

}  // namespace uav::vision
