#pragma once
// Depth from motion's grid (thesis 3.4) as a scan for the 3-D map: one ray per cell with a
// trusted depth, from the camera through the cell's centre to the cell's mean depth (along the
// optical axis), placed with the camera pose estimated at the frame. The grid is coarse (a cell
// spans a quarter of the image), so only cells whose converged features agree are used: a mean
// of a near trunk and a far background would draw a surface where there is none.
#include <Eigen/Geometry>

#include "uav/avoid/occupancy_map.hpp"
#include "uav/shared/camera_intrinsics.hpp"
#include "uav/shared/mono_depth.hpp"

namespace uav::avoid {

// Cells used: a depth, at least min_features converged features, and a standard error of the
// mean under max_relative_sigma of the depth. The scan's trusted range is the grid's obstacle
// depth (beyond it depth from motion only says "far": those rays clear up to it). Empty (no
// points) for an unhealthy grid.
RangeScan DepthGridScan(const DepthGrid& grid, const CameraIntrinsics& k, const Eigen::Isometry3d& T_NC,
                        int min_features = 3, double max_relative_sigma = 0.15);

}  // namespace uav::avoid
