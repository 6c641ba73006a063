#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <random>

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

// The clusters are the connected components of "closer than the tolerance": checked against the
// definition itself (every pair compared) on clouds built to have pairs on both sides of the
// tolerance, at many scales, including far from the origin and negative coordinates.
std::vector<std::vector<int>> ClustersByEveryPair(const std::vector<Eigen::Vector3f>& p, double tol, int min_points) {
  std::vector<int> parent(p.size());
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> find = [&](int i) { return parent[i] == i ? i : parent[i] = find(parent[i]); };
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j)
      if ((p[i] - p[j]).squaredNorm() < static_cast<float>(tol * tol)) parent[find(static_cast<int>(i))] = find(static_cast<int>(j));
  std::map<int, std::vector<int>> by_root;
  for (std::size_t i = 0; i < p.size(); ++i) by_root[find(static_cast<int>(i))].push_back(static_cast<int>(i));
  std::vector<std::vector<int>> out;
  for (auto& [root, members] : by_root)
    if (static_cast<int>(members.size()) >= min_points) out.push_back(members);
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.size() != b.size() ? a.size() > b.size() : a.front() < b.front();
  });
  return out;
}

TEST(EuclideanClusters, AreTheComponentsOfCloserThanTheTolerance) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const double tol = 0.05 + 0.1 * (trial % 5);
    std::uniform_real_distribution<float> offset(-1000.0f, 1000.0f);
    const Eigen::Vector3f origin = trial % 2 ? Eigen::Vector3f(offset(rng), offset(rng), offset(rng)) : Eigen::Vector3f::Zero();
    // Blobs and chains whose gaps are drawn around the tolerance, so joins hang on single pairs.
    std::vector<Eigen::Vector3f> pts;
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), gap(0.7f, 1.3f);
    for (int blob = 0; blob < 6; ++blob) {
      Eigen::Vector3f at = origin + Eigen::Vector3f(unit(rng), unit(rng), unit(rng)) * static_cast<float>(20 * tol);
      for (int k = 0; k < 40; ++k) {
        pts.push_back(at);
        at += Eigen::Vector3f(unit(rng), unit(rng), unit(rng)).normalized() * static_cast<float>(tol) * gap(rng);
      }
    }
    std::shuffle(pts.begin(), pts.end(), rng);
    for (int min_points : {1, 5}) {
      const auto got = EuclideanClusters(pts, tol, min_points);
      const auto want = ClustersByEveryPair(pts, tol, min_points);
      ASSERT_EQ(got, want) << "trial " << trial << ", tolerance " << tol << ", min_points " << min_points;
    }
  }
}

TEST(EuclideanClusters, RejectBadInput) {
  EXPECT_THROW(EuclideanClusters({Eigen::Vector3f::Zero()}, 0.0, 1), std::invalid_argument);
  EXPECT_THROW(EuclideanClusters({Eigen::Vector3f::Zero()}, NAN, 1), std::invalid_argument);
  EXPECT_THROW(EuclideanClusters({Eigen::Vector3f(NAN, 0, 0)}, 0.2, 1), std::invalid_argument);
  EXPECT_TRUE(EuclideanClusters({}, 0.2, 1).empty());
}

TEST(VoxelFilter, RejectsBadLeaf) {
  EXPECT_THROW(VoxelDownsample({}, 0.0f), std::invalid_argument);
  EXPECT_THROW(VoxelDownsample({}, NAN), std::invalid_argument);
}

}  // namespace
}  // namespace uav::vision
