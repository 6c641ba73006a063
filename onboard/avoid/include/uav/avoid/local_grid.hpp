#pragma once
// A dense window of the map around the vehicle, at the planning resolution, with the Euclidean
// distance from each cell to the nearest occupied one (the clearance the planner keeps). Built
// from the octree at each replan: a fixed-size array is what A* and the distance transform want,
// and it bounds the planner's time whatever the map holds. The exact distance transform is the
// separable one of Felzenszwalb and Huttenlocher (2012), linear in the cells.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "uav/avoid/occupancy_map.hpp"

namespace uav::avoid {

class LocalGrid {
 public:
  LocalGrid() = default;
  // The window [centre - half_extent, centre + half_extent] at `resolution_m`. A cell is
  // occupied when any occupied leaf of the map overlaps it, free when a free one does and no
  // occupied one, otherwise unknown. The ground is what the cameras saw of it, as any surface.
  static LocalGrid FromMap(const OccupancyMap& map, const Eigen::Vector3d& centre_N,
                           const Eigen::Vector3d& half_extent_m, double resolution_m, bool distances = true);
  // This grid (read from `map` and kept current since) moved to be centred on centre_N, its
  // size kept: the cells it still covers are kept, only the rest is read from the map (a slab
  // of the tree instead of the whole window), in its own memory (no distances).
  void Recentre(const OccupancyMap& map, const Eigen::Vector3d& centre_N);
  // Becomes the window [centre - half_extent, centre + half_extent] copied out of a larger grid
  // of the same resolution (cells outside it unknown), its distances computed. Its own memory
  // is reused: allocated anew at each replan, its pages were faulted in anew each time.
  void Extract(const LocalGrid& big, const Eigen::Vector3d& centre_N, const Eigen::Vector3d& half_extent_m);
  // An all-unknown window (tests fill it with Set).
  LocalGrid(const Eigen::Vector3d& min_N, const Eigen::Vector3i& size, double resolution_m);

  void Set(const Eigen::Vector3i& c, Cell state) { cells_[Index(c)] = state; }
  // The cell holding p_N, if the window has it.
  void SetAt(const Eigen::Vector3d& p_N, Cell state) {
    const Eigen::Vector3i c = CellOf(p_N);
    if (Contains(c)) Set(c, state);
  }
  // Computes the distance field from the occupied cells (call after the last Set).
  void ComputeDistances();

  bool Contains(const Eigen::Vector3i& c) const {
    return c.x() >= 0 && c.y() >= 0 && c.z() >= 0 && c.x() < size_.x() && c.y() < size_.y() && c.z() < size_.z();
  }
  Eigen::Vector3i CellOf(const Eigen::Vector3d& p_N) const;
  Eigen::Vector3d Centre(const Eigen::Vector3i& c) const { return min_N_ + (c.cast<double>().array() + 0.5).matrix() * res_; }
  Cell State(const Eigen::Vector3i& c) const { return cells_[Index(c)]; }
  // [m] from the cell's centre to the nearest occupied cell's centre; large where none is (and
  // before ComputeDistances).
  float Distance(const Eigen::Vector3i& c) const { return distance_.empty() ? kFar : distance_[Index(c)]; }
  // Outside the window: unknown, and no obstacle known.
  Cell StateAt(const Eigen::Vector3d& p_N) const;
  float DistanceAt(const Eigen::Vector3d& p_N) const;

  const Eigen::Vector3i& size() const { return size_; }
  const Eigen::Vector3d& min_N() const { return min_N_; }
  double resolution() const { return res_; }
  int Index(const Eigen::Vector3i& c) const { return (c.z() * size_.y() + c.y()) * size_.x() + c.x(); }
  static constexpr float kFar = 1e3f;

 private:
  // Marks the cells of the box [lo, hi) from the map's known leaves there (read at the planning
  // cell's size when it is the map's times 2^k): occupied where any occupied leaf overlaps,
  // free where a free one does and no occupied one.
  void Fill(const OccupancyMap& map, const Eigen::Vector3d& lo_N, const Eigen::Vector3d& hi_N);

  Eigen::Vector3d min_N_ = Eigen::Vector3d::Zero();
  Eigen::Vector3i size_ = Eigen::Vector3i::Zero();
  double res_ = 1.0;
  std::vector<Cell> cells_;
  std::vector<float> distance_;  // empty until ComputeDistances
  std::vector<Cell> spare_;      // Recentre's scratch, kept: a fresh block each time cost page faults
};

}  // namespace uav::avoid
