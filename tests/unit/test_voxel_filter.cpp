#include <gtest/gtest.h>

#include <cmath>

#include "uav/vision/point_cloud.hpp"

namespace uav::vision {
namespace {

TEST(VoxelFilter, OnePointPerOccupiedVoxelAtTheCentroid) {
  std::vector<Eigen::Vector3f> pts;
  // 8 points in the voxel [0,1)^3 and 2 in [2,3)x[0,1)x[0,1).
  for (int i = 0; i < 8; ++i) pts.emplace_back(0.1f + 0.1f * i, 0.5f, 0.5f);
  pts.emplace_back(2.2f, 0.2f, 0.2f);
  pts.emplace_back(2.4f, 0.4f, 0.4f);
  auto out = VoxelDownsample(pts, 1.0f);
  ASSERT_EQ(out.size(), 2u);
  std::sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.x() < b.x(); });
  EXPECT_NEAR(out[0].x(), 0.45f, 1e-5);
  EXPECT_NEAR(out[1].x(), 2.3f, 1e-5);
  EXPECT_NEAR(out[1].y(), 0.3f, 1e-5);
}

TEST(VoxelFilter, RejectsBadLeaf) {
  EXPECT_THROW(VoxelDownsample({}, 0.0f), std::invalid_argument);
  EXPECT_THROW(VoxelDownsample({}, NAN), std::invalid_argument);
}

}  // namespace
}  // namespace uav::vision
