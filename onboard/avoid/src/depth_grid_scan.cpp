#include "uav/avoid/depth_grid_scan.hpp"

namespace uav::avoid {

RangeScan DepthGridScan(const DepthGrid& grid, const CameraIntrinsics& k, const Eigen::Isometry3d& T_NC, int min_features,
                        double max_relative_sigma) {
  RangeScan scan;
  scan.utime = grid.utime;
  scan.origin_N = T_NC.translation();
  scan.max_range_m = grid.obstacle_depth_m;
  if (!grid.healthy || grid.cols <= 0 || grid.rows <= 0 || !T_NC.matrix().allFinite()) return scan;
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      const DepthCell& cell = grid.at(r, c);
      if (cell.state == CellState::kUnknown || !(cell.depth_m > 0) || cell.features < min_features ||
          !(cell.sigma_m <= max_relative_sigma * cell.depth_m))
        continue;
      // The cell's centre pixel, undistorted, at the depth along the optical axis.
      const Eigen::Vector2d uv((c + 0.5) * k.width / grid.cols - 0.5, (r + 0.5) * k.height / grid.rows - 0.5);
      const Eigen::Vector2d xy = Unproject(k, uv);
      const Eigen::Vector3d p_C(xy.x() * cell.depth_m, xy.y() * cell.depth_m, cell.depth_m);
      scan.p_N.push_back((T_NC * p_C).cast<float>());
    }
  return scan;
}

}  // namespace uav::avoid
