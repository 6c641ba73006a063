#pragma once
// The vehicle's 3-D map of what it has sensed (thesis 7.2 needs one: path planning acts on a
// model of the surroundings, not on the last image). Occupancy is an OctoMap octree of log-odds
// cells (Hornung et al. 2013): a stereo ray clears the cells it crosses and marks the one it
// ends in, an obstacle cylinder or a ranged wire marks the cells it covers. A cell no ray has
// crossed is unknown, kept apart from free: the planner and the safety layer treat it as not
// free. Positions are local NED [m]. OctoMap stays out of this header.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace uav::avoid {

enum class Cell : uint8_t { kUnknown = 0, kFree = 1, kOccupied = 2 };

struct MapParams {
  double resolution_m = 0.2;    // edge of the smallest cell
  double hit_probability = 0.7;   // of a cell a ray ends in (OctoMap's default)
  double miss_probability = 0.4;  // of a cell a ray crosses
  // A cell is occupied at or above this probability (two consistent hits: one stereo outlier is
  // not an obstacle), free at or below free_probability (one ray through it), and unknown in
  // between: a cell seen both ways is not counted on either way until the evidence settles.
  double occupied_probability = 0.8;
  double free_probability = 0.45;
  int max_rays = 2000;            // per scan, after merging the rays that end in one 2x2x2-cell block
  std::size_t max_cells = 2'000'000;  // memory bound in nodes: past it, the cells farthest from the vehicle go
  void Validate() const;          // throws std::invalid_argument naming the bad field
};

// One stereo pair's contribution, fused at its capture time: the points are already placed in N
// with the pose estimated at the exposure, the origin is the left camera's centre then.
struct RangeScan {
  int64_t utime = 0;
  Eigen::Vector3d origin_N = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3f> p_N;  // reprojected points; those beyond max_range_m clear only
  double max_range_m = 0.0;          // the range the depth is trusted to (the error model's gate)
};

class OccupancyMap {
 public:
  explicit OccupancyMap(const MapParams& params = {});
  ~OccupancyMap();
  OccupancyMap(OccupancyMap&&) noexcept;
  OccupancyMap& operator=(OccupancyMap&&) noexcept;

  // Rays from the origin to each point: cells crossed are observed free, the end cell occupied
  // (points past max_range_m: free up to it, no end cell). Non-finite points are skipped. Rays
  // ending in the same block of 2x2x2 cells are cast once, and at most max_rays are (evenly
  // spread): a scan costs what the map can resolve, not what the camera delivers.
  void InsertScan(const RangeScan& scan);
  // A vertical cylinder (a detected obstacle, its radius grown by one standard deviation of its
  // axis position): every cell whose centre it contains is marked occupied.
  void InsertCylinder(const Eigen::Vector2d& p_NE, double top_down_m, double bottom_down_m, double radius_m);
  // A polyline (a ranged wire) thickened to radius_m.
  void InsertPolyline(const std::vector<Eigen::Vector3d>& p_N, double radius_m);
  // The space the vehicle's body is in, a flat disc radius_m across and height_m high about
  // p_N: every cell whose centre is within radius_m of p_N across the ground, and which reaches
  // into the disc's height, is observed free once (a miss), except cells held occupied (an
  // obstacle the body touches stays in the map; cells within one cell of the centre are cleared
  // regardless). The vehicle has been there: the column it took off through and the cells beside
  // its own camera are never in view.
  void InsertBody(const Eigen::Vector3d& p_N, double radius_m, double height_m);
  // Sets one cell to certainly occupied or certainly free (tests).
  void Mark(const Eigen::Vector3d& p_N, bool occupied);

  Cell At(const Eigen::Vector3d& p_N) const;
  double resolution() const;
  std::size_t cells() const;  // nodes held (leaves and the inner ones above them; O(1))
  // Keeps the map within max_cells by dropping the leaves farthest from p_N. Returns how many
  // went (0 when within the bound).
  std::size_t EnforceBound(const Eigen::Vector3d& p_N);

  // Calls f(centre_N, size_m, state) for every free or occupied leaf inside the box (both ends
  // incl.), or, with `coarser` > 0, for every such cell 2^coarser leaves wide (OctoMap keeps
  // each inner cell at its most occupied child: occupied when any leaf in it is, free when all
  // its known leaves are).
  template <class F>
  void ForEachKnown(const Eigen::Vector3d& min_N, const Eigen::Vector3d& max_N, F&& f, int coarser = 0) const {
    VisitKnown(min_N, max_N, [&](const Eigen::Vector3d& c, double s, Cell state) { f(c, s, state); }, coarser);
  }
  // The cells 2^coarser leaves wide that changed since the last call, with their state now:
  // what a dense copy of the map needs to stay current. `complete` is false when the changes
  // since the last call are not all known (the memory bound rebuilt the tree): copy it anew.
  struct Change {
    Eigen::Vector3d centre_N;
    Cell state;
  };
  std::vector<Change> TakeChanges(int coarser, bool* complete);

  // Occupied leaf centres (at the finest resolution, expanded), for drawing and messages.
  std::vector<Eigen::Vector3f> OccupiedCentres(const Eigen::Vector3d& min_N, const Eigen::Vector3d& max_N) const;

  // Writes the map as an OctoMap binary tree (.bt, opens in octovis): to a temporary file first,
  // renamed into place, so a failed write leaves no half file. Returns "" or what went wrong.
  std::string SaveBinary(const std::string& path) const;
  // Reads a .bt file; throws std::runtime_error naming the file when it cannot.
  static OccupancyMap LoadBinary(const std::string& path, const MapParams& params = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  void VisitKnown(const Eigen::Vector3d& min_N, const Eigen::Vector3d& max_N,
                  const std::function<void(const Eigen::Vector3d&, double, Cell)>& f, int coarser = 0) const;
};

}  // namespace uav::avoid
