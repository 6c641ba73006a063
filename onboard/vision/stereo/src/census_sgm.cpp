#include "census_sgm.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>

// How it is fast (thesis 3.5.1 asks for dense disparity at the camera's rate):
// - Rows are streamed top to bottom: the cost row, the paths' previous row and the sum stay in
//   the cache (about 1 MB at 640 x 128), never a whole cost volume.
// - Five paths (left, right, up, up-left, up-right), each step a few vector operations over the
//   disparities (GCC vector extensions; the hot functions are compiled for AVX2 and for plain
//   x86-64 and picked at run time, so one binary runs on any x86-64).
// - The census costs use the CPU's vector popcount where it has one (AVX-512 VPOPCNTDQ).
// - The image is cut into two horizontal strips, one per core; the lower strip starts its
//   downward paths kWarmupRows above its first row so that the seam does not show.
namespace uav::vision::detail {
namespace {

#if defined(__x86_64__)
#define UAV_SGM_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define UAV_SGM_CLONES  // elsewhere (an ARM flight computer) the compiler's own vector width
#endif
#define UAV_SGM_INLINE static inline __attribute__((always_inline))

typedef uint16_t V16 __attribute__((vector_size(32)));  // 16 disparities at once
constexpr int kLanes = 16;
constexpr int kStrips = 2;       // fixed, so that the result does not depend on the thread count
constexpr int kWarmupRows = 24;  // rows above a strip that only run its downward paths
constexpr int kCensusW = 9, kCensusH = 7;  // 62 bits
constexpr uint16_t kGuard = 0x3FFF;        // beyond the disparity range: never the minimum
constexpr uint16_t kNoPartner = 64;        // cost where the partner is outside the right image

UAV_SGM_INLINE V16 Load(const uint16_t* p) {
  V16 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
UAV_SGM_INLINE void Store(uint16_t* p, V16 v) { std::memcpy(p, &v, sizeof v); }
UAV_SGM_INLINE V16 Min(V16 a, V16 b) { return a < b ? a : b; }
// A macro, not a function: GCC 12 builds a splat made in a plain inline function lane by lane
// (eight vpinsrw) even where it is inlined into the AVX2 clone; written in place it is one
// vpbroadcastw. That alone was a third of the matcher's time.
#define UAV_SGM_SPLAT(x) (V16{} + static_cast<uint16_t>(x))
UAV_SGM_INLINE V16 Iota() { return V16{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15}; }
UAV_SGM_INLINE uint16_t HorizontalMin(V16 a) {
  a = Min(a, __builtin_shuffle(a, V16{8, 9, 10, 11, 12, 13, 14, 15, 0, 1, 2, 3, 4, 5, 6, 7}));
  a = Min(a, __builtin_shuffle(a, V16{4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11}));
  a = Min(a, __builtin_shuffle(a, V16{2, 3, 0, 1, 6, 7, 4, 5, 10, 11, 8, 9, 14, 15, 12, 13}));
  a = Min(a, __builtin_shuffle(a, V16{1, 0, 3, 2, 5, 4, 7, 6, 9, 8, 11, 10, 13, 12, 15, 14}));
  return a[0];
}
UAV_SGM_INLINE bool AnyLane(V16 a) {
  uint64_t w[4];
  std::memcpy(w, &a, sizeof w);
  return (w[0] | w[1] | w[2] | w[3]) != 0;
}

// Census transform: bit k of a pixel says whether its k-th neighbour in the 9 x 7 window is darker.
UAV_SGM_CLONES void Census(const cv::Mat& image, cv::Mat& out) {
  constexpr int rx = kCensusW / 2, ry = kCensusH / 2;
  const int W = image.cols;
  cv::Mat padded;
  cv::copyMakeBorder(image, padded, ry, ry, rx, rx, cv::BORDER_REPLICATE);
  out.create(image.size(), CV_64F);  // 64-bit codes
  for (int v = 0; v < image.rows; ++v) {
    uint64_t* code = out.ptr<uint64_t>(v);
    const uint8_t* centre = padded.ptr<uint8_t>(v + ry) + rx;
    std::fill(code, code + W, 0);
    for (int dy = -ry; dy <= ry; ++dy)
      for (int dx = -rx; dx <= rx; ++dx) {
        if (dy == 0 && dx == 0) continue;
        const uint8_t* neighbour = padded.ptr<uint8_t>(v + ry + dy) + rx + dx;
        for (int u = 0; u < W; ++u) code[u] = (code[u] << 1) | uint64_t(neighbour[u] < centre[u]);
      }
  }
}

// Matching costs of one row: C[u * D + d] = Hamming distance of left u and right u - d. The right
// row comes reversed (right_reversed[k] = right[W - 1 - k]) so that d ascends in memory.
#define UAV_SGM_ROW_COST                                                                      \
  for (int u = 0; u < W; ++u) {                                                               \
    uint16_t* __restrict c = C + u * D;                                                       \
    const uint64_t l = left[u];                                                               \
    const uint64_t* __restrict r = right_reversed + (W - 1 - u);                              \
    const int n = std::min(D, u + 1);                                                         \
    for (int d = 0; d < n; ++d) c[d] = static_cast<uint16_t>(__builtin_popcountll(l ^ r[d])); \
    for (int d = n; d < D; ++d) c[d] = kNoPartner;                                            \
  }
#if defined(__x86_64__)
__attribute__((target("avx512f,avx512bw,avx512vl,avx512vpopcntdq,avx2,popcnt"))) void RowCostVectorPopcount(
    const uint64_t* left, const uint64_t* right_reversed, int W, int D, uint16_t* C) {
  UAV_SGM_ROW_COST
}
#endif
UAV_SGM_CLONES void RowCostScalarPopcount(const uint64_t* left, const uint64_t* right_reversed, int W, int D, uint16_t* C) {
  UAV_SGM_ROW_COST
}
using RowCostFn = void (*)(const uint64_t*, const uint64_t*, int, int, uint16_t*);
RowCostFn PickRowCost() {
#if defined(__x86_64__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512vpopcntdq") && __builtin_cpu_supports("avx512bw")) return RowCostVectorPopcount;
#endif
  return RowCostScalarPopcount;
}

// One step along a path (Hirschmueller's Eq. 13): L(p, d) = C(p, d) + min(L(p-r, d),
// L(p-r, d+-1) + P1, min_k L(p-r, k) + P2) - min_k L(p-r, k). `prev` has guards at [-1] and [D].
// Returns min_d L(p, d); adds L(p, .) to `sum`.
UAV_SGM_INLINE uint16_t PathStep(const uint16_t* __restrict c, const uint16_t* __restrict prev, uint16_t prev_min, int D,
                                 uint16_t* __restrict out, uint16_t* __restrict sum, V16 p1, uint16_t p2) {
  const V16 jump = UAV_SGM_SPLAT(prev_min + p2), base = UAV_SGM_SPLAT(prev_min);
  V16 lowest = UAV_SGM_SPLAT(0xFFFF);
  for (int d = 0; d < D; d += kLanes) {
    const V16 m = Min(Min(Load(prev + d), jump), Min(Load(prev + d - 1), Load(prev + d + 1)) + p1);
    const V16 o = Load(c + d) + m - base;
    Store(out + d, o);
    Store(sum + d, Load(sum + d) + o);
    lowest = Min(lowest, o);
  }
  return HorizontalMin(lowest);
}

// Aggregates row v along the five paths into `sum` and, unless v is a warm-up row, writes its
// disparities. The downward paths' rows are swapped in place for the next row.
// The three downward paths of one pixel at once (up, up-left, up-right: the same recurrence
// from three pixels of the last row); they are the first to reach `sum`, so it is written, not
// added to. A path that starts here takes `start` (zeros with guards: L = C).
UAV_SGM_INLINE void DownSteps(const uint16_t* __restrict c, const uint16_t* const prev[3], const uint16_t prev_min[3], int D,
                              uint16_t* const out[3], uint16_t out_min[3], uint16_t* __restrict sum, V16 p1, uint16_t p2) {
  const uint16_t *__restrict a = prev[0], *__restrict b = prev[1], *__restrict e = prev[2];
  uint16_t *__restrict oa = out[0], *__restrict ob = out[1], *__restrict oe = out[2];
  const V16 ja = UAV_SGM_SPLAT(prev_min[0] + p2), jb = UAV_SGM_SPLAT(prev_min[1] + p2), je = UAV_SGM_SPLAT(prev_min[2] + p2);
  const V16 ba = UAV_SGM_SPLAT(prev_min[0]), bb = UAV_SGM_SPLAT(prev_min[1]), be = UAV_SGM_SPLAT(prev_min[2]);
  V16 la = UAV_SGM_SPLAT(0xFFFF), lb = la, le = la;
  for (int d = 0; d < D; d += kLanes) {
    const V16 cost = Load(c + d);
    const V16 xa = cost + Min(Min(Load(a + d), ja), Min(Load(a + d - 1), Load(a + d + 1)) + p1) - ba;
    const V16 xb = cost + Min(Min(Load(b + d), jb), Min(Load(b + d - 1), Load(b + d + 1)) + p1) - bb;
    const V16 xe = cost + Min(Min(Load(e + d), je), Min(Load(e + d - 1), Load(e + d + 1)) + p1) - be;
    Store(oa + d, xa);
    Store(ob + d, xb);
    Store(oe + d, xe);
    Store(sum + d, xa + xb + xe);
    la = Min(la, xa);
    lb = Min(lb, xb);
    le = Min(le, xe);
  }
  out_min[0] = HorizontalMin(la);
  out_min[1] = HorizontalMin(lb);
  out_min[2] = HorizontalMin(le);
}

struct RowBuffers {
  std::vector<uint16_t> cost, sum;                 // W x D
  std::vector<uint16_t> start;                     // a path's start (zeros, guards at the ends)
  std::vector<uint16_t> down[3], down_next[3];     // up, up-left, up-right: W x (D + 2), guards
  std::vector<uint16_t> down_min[3], down_min_next[3];
  std::vector<uint16_t> along[2];                  // left-right paths: the last pixel and this one
  std::vector<uint16_t> right_min, right_arg;      // the right image's best disparity, reversed
  std::vector<int> best;
  std::vector<uint64_t> right_reversed;
  int W = 0, D = 0;
  // Sized once per thread and image size: allocating them per call cost more in page faults
  // than a third of the matching.
  void Resize(int width, int disparities) {
    if (width == W && disparities == D) return;
    W = width;
    D = disparities;
    const std::size_t n = static_cast<std::size_t>(W), stride = static_cast<std::size_t>(D + 2);
    cost.assign(n * D, 0);
    sum.assign(n * D, 0);
    for (int k = 0; k < 3; ++k) {
      down[k].assign(n * stride, kGuard);
      down_next[k].assign(n * stride, kGuard);
      down_min[k].assign(n, 0);
      down_min_next[k].assign(n, 0);
    }
    start.assign(stride, 0);
    start.front() = start.back() = kGuard;
    along[0].assign(stride, kGuard);
    along[1].assign(stride, kGuard);
    right_min.assign(n + D, 0);
    right_arg.assign(n + D, 0);
    best.assign(n, 0);
    right_reversed.assign(n, 0);
  }
};

UAV_SGM_INLINE uint16_t PathStart(const uint16_t* __restrict c, int D, uint16_t* __restrict out, uint16_t* __restrict sum) {
  uint16_t lowest = 0xFFFF;
  for (int d = 0; d < D; ++d) {
    out[d] = c[d];
    sum[d] += c[d];
    lowest = std::min(lowest, c[d]);
  }
  return lowest;
}

// Winner-takes-all at one pixel with the uniqueness test; meanwhile the right image's pixels on
// this pixel's diagonal keep their best (rmin, rarg: index d is right pixel u - d). -1: not unique.
UAV_SGM_INLINE int Winner(const uint16_t* __restrict total, int D, uint16_t* __restrict rmin, uint16_t* __restrict rarg,
                          unsigned unique_scale) {
  V16 lowest = UAV_SGM_SPLAT(0xFFFF), arg = V16{}, dv = Iota();
  for (int d = 0; d < D; d += kLanes) {
    const V16 x = Load(total + d), r = Load(rmin + d);
    arg = x < lowest ? dv : arg;
    lowest = Min(lowest, x);
    Store(rarg + d, x <= r ? dv : Load(rarg + d));  // ties: the smaller disparity (pixels come right to left)
    Store(rmin + d, Min(r, x));
    dv += static_cast<uint16_t>(kLanes);
  }
  const uint16_t best_cost = HorizontalMin(lowest);
  const int best = HorizontalMin(lowest == UAV_SGM_SPLAT(best_cost) ? arg : UAV_SGM_SPLAT(0xFFFF));
  // No disparity beyond the winner's neighbours within uniqueness_pct of its cost.
  const V16 limit = UAV_SGM_SPLAT(static_cast<unsigned>(best_cost) * unique_scale / 100u), lo = UAV_SGM_SPLAT(best - 1), hi = UAV_SGM_SPLAT(best + 1);
  V16 rival = V16{};
  dv = Iota();
  for (int d = 0; d < D; d += kLanes) {
    rival |= (Load(total + d) <= limit) & ((dv < lo) | (dv > hi));
    dv += static_cast<uint16_t>(kLanes);
  }
  return AnyLane(rival) ? -1 : best;
}

UAV_SGM_CLONES void AggregateRow(RowBuffers& b, int W, int D, bool first_row, bool warmup, uint16_t p1, uint16_t p2,
                                 unsigned unique_scale, int lr_max_diff, int16_t* out) {
  const int stride = D + 2;
  const V16 p1v = UAV_SGM_SPLAT(p1);
  uint16_t* sum = b.sum.data();
  const uint16_t* cost = b.cost.data();
  // Up, up-left and up-right: from the last row's pixel above, above-left and above-right.
  for (int u = 0; u < W; ++u) {
    const uint16_t* prev[3];
    uint16_t prev_min[3], out_min[3];
    uint16_t* out_path[3];
    for (int k = 0; k < 3; ++k) {
      const int from = u + (k == 0 ? 0 : (k == 1 ? -1 : 1));
      const bool starts = first_row || from < 0 || from >= W;
      prev[k] = starts ? b.start.data() + 1 : &b.down[k][static_cast<std::size_t>(from) * stride + 1];
      prev_min[k] = starts ? 0 : b.down_min[k][from];
      out_path[k] = &b.down_next[k][static_cast<std::size_t>(u) * stride + 1];
    }
    DownSteps(cost + u * D, prev, prev_min, D, out_path, out_min, sum + u * D, p1v, p2);
    for (int k = 0; k < 3; ++k) b.down_min_next[k][u] = out_min[k];
  }
  for (int k = 0; k < 3; ++k) {
    std::swap(b.down[k], b.down_next[k]);
    std::swap(b.down_min[k], b.down_min_next[k]);
  }
  if (warmup) return;
  // Left to right.
  uint16_t m = PathStart(cost, D, &b.along[0][1], sum);
  for (int u = 1; u < W; ++u) {
    m = PathStep(cost + u * D, &b.along[0][1], m, D, &b.along[1][1], sum + u * D, p1v, p2);
    std::swap(b.along[0], b.along[1]);
  }
  // Right to left; a pixel's sum is then complete and its winner is taken at once, while it
  // is in the cache. Sub-pixel: the parabola through the winner and its neighbours (1/16 px).
  std::fill(b.right_min.begin(), b.right_min.end(), 0xFFFF);
  for (int u = W - 1; u >= 0; --u) {
    uint16_t* total = sum + u * D;
    m = u == W - 1 ? PathStart(cost + u * D, D, &b.along[1][1], total)
                   : PathStep(cost + u * D, &b.along[0][1], m, D, &b.along[1][1], total, p1v, p2);
    std::swap(b.along[0], b.along[1]);
    const int best = Winner(total, D, &b.right_min[static_cast<std::size_t>(W - 1 - u)],
                            &b.right_arg[static_cast<std::size_t>(W - 1 - u)], unique_scale);
    b.best[static_cast<std::size_t>(u)] = best;
    if (best < 0 || best > u) {
      out[u] = -16;
      continue;
    }
    int d16 = 16 * best;
    if (best > 0 && best < D - 1) {
      const int cm = total[best - 1], c0 = total[best], cp = total[best + 1], den = cm + cp - 2 * c0;
      if (den > 0) d16 += (8 * (cm - cp) + (cm > cp ? den / 2 : -den / 2)) / den;
    }
    out[u] = static_cast<int16_t>(std::max(d16, 1));
  }
  // Left-right check: the right pixel the winner points at must point back.
  for (int u = 0; u < W; ++u) {
    const int best = b.best[static_cast<std::size_t>(u)];
    if (best < 0 || best > u) continue;
    const int back = b.right_arg[static_cast<std::size_t>(W - 1 - (u - best))];
    if (std::abs(back - best) > lr_max_diff) out[u] = -16;
  }
}

}  // namespace

cv::Mat CensusSemiGlobalMatch(const cv::Mat& left8, const cv::Mat& right8, const CensusSgmParams& p) {
  CV_Assert(left8.type() == CV_8UC1 && right8.type() == CV_8UC1 && left8.size() == right8.size());
  CV_Assert(p.num_disparities % kLanes == 0 && p.num_disparities > 0);
  static const RowCostFn row_cost = PickRowCost();
  const int W = left8.cols, H = left8.rows, D = p.num_disparities;
  cv::Mat census[2];
  cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& r) {
    for (int i = r.start; i < r.end; ++i) Census(i == 0 ? left8 : right8, census[i]);
  });
  cv::Mat d16(H, W, CV_16S, cv::Scalar(-16));
  const unsigned unique_scale = 100u + static_cast<unsigned>(p.uniqueness_pct);
  cv::parallel_for_(cv::Range(0, kStrips), [&](const cv::Range& r) {
    for (int strip = r.start; strip < r.end; ++strip) {
      const int v0 = H * strip / kStrips, v1 = H * (strip + 1) / kStrips, start = std::max(0, v0 - kWarmupRows);
      thread_local RowBuffers b;
      b.Resize(W, D);
      for (int v = start; v < v1; ++v) {
        const uint64_t* right = census[1].ptr<uint64_t>(v);
        for (int k = 0; k < W; ++k) b.right_reversed[static_cast<std::size_t>(k)] = right[W - 1 - k];
        row_cost(census[0].ptr<uint64_t>(v), b.right_reversed.data(), W, D, b.cost.data());
        AggregateRow(b, W, D, v == start, v < v0, static_cast<uint16_t>(p.p1), static_cast<uint16_t>(p.p2), unique_scale,
                     p.lr_max_diff_px, d16.ptr<int16_t>(v));
      }
      // Each strip's speckles on its own core: a blob across the seam is judged by its parts.
      if (p.speckle_window_px > 0) {
        cv::Mat rows = d16.rowRange(v0, v1);
        cv::filterSpeckles(rows, -16, p.speckle_window_px, 16 * p.speckle_range_px);
      }
    }
  });
  return d16;
}

}  // namespace uav::vision::detail
