#include "uav/avoid/local_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace uav::avoid {

namespace {
// Felzenszwalb-Huttenlocher 1-D squared distance transform of f (n samples, unit spacing): the
// lower envelope of the parabolas (q - v)^2 + f(v), built from the samples that have an
// obstacle within reach only (f < none), so "none" never enters the arithmetic and floats stay
// exact (squared distances in cells are small integers). Returns false when no sample has one.
bool Transform1D(const float* f, int n, float none, float* d, int* v, float* z) {
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] >= none) continue;
    if (k < 0) {
      k = 0, v[0] = q;
      z[0] = -std::numeric_limits<float>::infinity();
      z[1] = std::numeric_limits<float>::infinity();
      continue;
    }
    float s = ((f[q] + float(q) * q) - (f[v[k]] + float(v[k]) * v[k])) / (2.0f * (q - v[k]));
    while (s <= z[k]) {  // z[0] is -inf: stops at k = 0
      --k;
      s = ((f[q] + float(q) * q) - (f[v[k]] + float(v[k]) * v[k])) / (2.0f * (q - v[k]));
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = std::numeric_limits<float>::infinity();
  }
  if (k < 0) return false;
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    d[q] = float(q - v[k]) * (q - v[k]) + f[v[k]];
  }
  return true;
}
}  // namespace

LocalGrid::LocalGrid(const Eigen::Vector3d& min_N, const Eigen::Vector3i& size, double resolution_m)
    : min_N_(min_N), size_(size), res_(resolution_m),
      cells_(static_cast<std::size_t>(size.prod()), Cell::kUnknown) {}

LocalGrid LocalGrid::FromMap(const OccupancyMap& map, const Eigen::Vector3d& centre_N, const Eigen::Vector3d& half_extent_m,
                             double resolution_m, bool distances) {
  const Eigen::Vector3i size = (2.0 * half_extent_m / resolution_m).array().ceil().cast<int>().max(1);
  // Aligned to the resolution so that consecutive windows share their cells (no flicker).
  const Eigen::Vector3d min_N = ((centre_N - half_extent_m) / resolution_m).array().floor().matrix() * resolution_m;
  LocalGrid g(min_N, size, resolution_m);
  g.Fill(map, min_N, min_N + size.cast<double>() * resolution_m);
  if (distances) g.ComputeDistances();
  return g;
}

void LocalGrid::Fill(const OccupancyMap& map, const Eigen::Vector3d& lo_N, const Eigen::Vector3d& hi_N) {
  // A planning cell of 2^k map cells is read from the octree's inner cells at that size: 8^k
  // times fewer cells to visit.
  int coarser = 0;
  for (int k = 1; k <= 4; ++k)
    if (std::abs(res_ - map.resolution() * (1 << k)) < 1e-9) coarser = k;
  const Eigen::Vector3i box_lo = CellOf(lo_N + Eigen::Vector3d::Constant(1e-6)).cwiseMax(0);
  const Eigen::Vector3i box_hi = CellOf(hi_N - Eigen::Vector3d::Constant(1e-6)).cwiseMin(size_ - Eigen::Vector3i::Ones());
  map.ForEachKnown(lo_N, hi_N, [&](const Eigen::Vector3d& c, double leaf, Cell state) {
    const bool occupied = state == Cell::kOccupied;
    const Eigen::Vector3d lo = c.array() - 0.5 * leaf + 1e-6, hi = c.array() + 0.5 * leaf - 1e-6;
    const Eigen::Vector3i a = CellOf(lo).cwiseMax(box_lo), b = CellOf(hi).cwiseMin(box_hi);
    for (int z = a.z(); z <= b.z(); ++z)
      for (int y = a.y(); y <= b.y(); ++y)
        for (int x = a.x(); x <= b.x(); ++x) {
          Cell& cell = cells_[Index({x, y, z})];
          if (occupied) cell = Cell::kOccupied;
          else if (cell == Cell::kUnknown) cell = Cell::kFree;
        }
  }, coarser);
}

void LocalGrid::Recentre(const OccupancyMap& map, const Eigen::Vector3d& centre_N) {
  const Eigen::Vector3d half = 0.5 * size_.cast<double>() * res_;
  const Eigen::Vector3d min_N = ((centre_N - half) / res_).array().floor().matrix() * res_;
  // Old index = new index + offset; the overlap [lo, hi) in the new grid's cells, per axis.
  const Eigen::Vector3i offset = ((min_N - min_N_) / res_).array().round().cast<int>();
  if (offset == Eigen::Vector3i::Zero()) return;
  const Eigen::Vector3i lo = (-offset).cwiseMax(0).cwiseMin(size_);
  const Eigen::Vector3i hi = (size_ - offset).cwiseMin(size_).cwiseMax(lo);
  spare_.assign(cells_.size(), Cell::kUnknown);
  for (int z = lo.z(); z < hi.z(); ++z)
    for (int y = lo.y(); y < hi.y(); ++y)
      if (hi.x() > lo.x())
        std::copy_n(&cells_[Index(offset + Eigen::Vector3i(lo.x(), y, z))], hi.x() - lo.x(), &spare_[Index({lo.x(), y, z})]);
  cells_.swap(spare_);
  min_N_ = min_N;
  distance_.clear();
  // The rest, as up to six slabs: outside the overlap in x; inside it in x and outside in y;
  // inside in x and y and outside in z.
  auto fill = [&](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
    if ((b.array() > a.array()).all()) Fill(map, min_N_ + a.cast<double>() * res_, min_N_ + b.cast<double>() * res_);
  };
  const Eigen::Vector3i& n = size_;
  fill(Eigen::Vector3i::Zero(), {lo.x(), n.y(), n.z()});
  fill({hi.x(), 0, 0}, n);
  fill({lo.x(), 0, 0}, {hi.x(), lo.y(), n.z()});
  fill({lo.x(), hi.y(), 0}, {hi.x(), n.y(), n.z()});
  fill({lo.x(), lo.y(), 0}, {hi.x(), hi.y(), lo.z()});
  fill({lo.x(), lo.y(), hi.z()}, {hi.x(), hi.y(), n.z()});
}

void LocalGrid::Extract(const LocalGrid& big, const Eigen::Vector3d& centre_N, const Eigen::Vector3d& half_extent_m) {
  res_ = big.res_;
  size_ = (2.0 * half_extent_m / res_).array().ceil().cast<int>().max(1);
  min_N_ = ((centre_N - half_extent_m) / res_).array().floor().matrix() * res_;
  cells_.assign(static_cast<std::size_t>(size_.prod()), Cell::kUnknown);
  const Eigen::Vector3i offset = ((min_N_ - big.min_N_) / res_).array().round().cast<int>();
  for (int z = 0; z < size_.z(); ++z)
    for (int y = 0; y < size_.y(); ++y) {
      const Eigen::Vector3i first = offset + Eigen::Vector3i(0, y, z);
      if (first.y() < 0 || first.z() < 0 || first.y() >= big.size_.y() || first.z() >= big.size_.z()) continue;
      const int x0 = std::max(0, -first.x()), x1 = std::min(size_.x(), big.size_.x() - first.x());
      if (x1 <= x0) continue;
      std::copy_n(&big.cells_[big.Index(first + Eigen::Vector3i(x0, 0, 0))], x1 - x0, &cells_[Index({x0, y, z})]);
    }
  ComputeDistances();
}

void LocalGrid::ComputeDistances() {
  // Squared distances in cells, in distance_ itself, by three separable passes: along x the
  // nearest occupied cell of the line (two sweeps: there are no parabolas to intersect when
  // every sample is 0 or none), then along y and z the parabolas' envelope over each line,
  // copied out and written back; the last pass writes metres.
  const int nx = size_.x(), ny = size_.y(), nz = size_.z();
  constexpr float none = 1e30f;
  distance_.resize(cells_.size());
  float* sq = distance_.data();
  for (std::size_t line = 0; line < static_cast<std::size_t>(ny) * nz; ++line) {
    const Cell* c = &cells_[line * nx];
    float* out = sq + line * nx;
    int last = -1;
    for (int i = 0; i < nx; ++i) {
      if (c[i] == Cell::kOccupied) last = i;
      out[i] = last < 0 ? none : float(i - last) * (i - last);
    }
    last = -1;
    for (int i = nx - 1; i >= 0; --i) {
      if (c[i] == Cell::kOccupied) last = i;
      if (last >= 0) out[i] = std::min(out[i], float(last - i) * (last - i));
    }
  }
  // The y and z lines of one plane of cells (fixed z, fixed y) are copied out together, row by
  // row, into a small buffer (one line per row), and back: strided reads one cell at a time
  // were most of the time.
  const int n_max = std::max({nx, ny, nz});
  std::vector<float> block(static_cast<std::size_t>(nx) * n_max), d(n_max), z(n_max + 1);
  std::vector<uint8_t> any(nx);
  std::vector<int> v(n_max);
  const std::size_t sy = nx, sz = static_cast<std::size_t>(nx) * ny;
  for (int k = 0; k < nz; ++k) {
    float* plane = sq + k * sz;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) block[i * ny + j] = plane[j * sy + i];
    for (int i = 0; i < nx; ++i) {
      float* f = &block[i * ny];
      if (Transform1D(f, ny, none, d.data(), v.data(), z.data())) std::copy_n(d.data(), ny, f);
    }
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) plane[j * sy + i] = block[i * ny + j];
  }
  // Squared distances are whole cells: their metres from a table.
  std::vector<float> metres(static_cast<std::size_t>(nx) * nx + ny * ny + nz * nz);
  for (std::size_t i = 0; i < metres.size(); ++i) metres[i] = static_cast<float>(std::sqrt(double(i)) * res_);
  for (int j = 0; j < ny; ++j) {
    float* plane = sq + j * sy;
    for (int k = 0; k < nz; ++k)
      for (int i = 0; i < nx; ++i) block[i * nz + k] = plane[k * sz + i];
    for (int i = 0; i < nx; ++i) {
      float* f = &block[i * nz];
      any[i] = Transform1D(f, nz, none, d.data(), v.data(), z.data());
      if (any[i]) std::copy_n(d.data(), nz, f);
    }
    for (int k = 0; k < nz; ++k)
      for (int i = 0; i < nx; ++i)
        plane[k * sz + i] = any[i] ? metres[static_cast<std::size_t>(block[i * nz + k])] : kFar;
  }
}

Eigen::Vector3i LocalGrid::CellOf(const Eigen::Vector3d& p_N) const {
  return ((p_N - min_N_) / res_).array().floor().cast<int>();
}

Cell LocalGrid::StateAt(const Eigen::Vector3d& p_N) const {
  const Eigen::Vector3i c = CellOf(p_N);
  return Contains(c) ? State(c) : Cell::kUnknown;
}

float LocalGrid::DistanceAt(const Eigen::Vector3d& p_N) const {
  const Eigen::Vector3i c = CellOf(p_N);
  return Contains(c) ? Distance(c) : kFar;
}

}  // namespace uav::avoid
