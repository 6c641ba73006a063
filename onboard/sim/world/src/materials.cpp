// Procedural, tileable material textures (issue 4): varied enough for corner tracking where real
// surfaces are (gravel, roofs, crops) and nearly featureless where real grass and walls are.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "scene_impl.hpp"

namespace uav::world {

namespace {

constexpr int kSize = 512;        // texels per side: 5.12 m at 1 cm
constexpr double kTexel = 0.01;   // [m]

double Smooth(double t) { return t * t * (3.0 - 2.0 * t); }

// Value noise on a lattice of `cell` texels, periodic over kSize texels (cell divides kSize).
class PeriodicNoise {
 public:
  PeriodicNoise(int cell_x, int cell_y, uint64_t seed)
      : cx_(cell_x), cy_(cell_y), nx_(kSize / cell_x), ny_(kSize / cell_y), seed_(seed) {}
  double operator()(int i, int j) const {
    const double x = static_cast<double>(i) / cx_, y = static_cast<double>(j) / cy_;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const double ax = Smooth(x - x0), ay = Smooth(y - y0);
    auto v = [&](int a, int b) {
      a = ((a % nx_) + nx_) % nx_;
      b = ((b % ny_) + ny_) % ny_;
      return Unit(HashCombine(seed_, static_cast<uint64_t>(a) * 73856093u ^ static_cast<uint64_t>(b) * 19349663u));
    };
    const double top = v(x0, y0) * (1 - ax) + v(x0 + 1, y0) * ax;
    const double bottom = v(x0, y0 + 1) * (1 - ax) + v(x0 + 1, y0 + 1) * ax;
    return top * (1 - ay) + bottom * ay;
  }

 private:
  int cx_, cy_, nx_, ny_;
  uint64_t seed_;
};

// Sum of octaves from `coarse` down to `fine` texels per cell, zero mean, roughly unit range.
class Fbm {
 public:
  Fbm(int coarse, int fine, uint64_t seed) {
    double amp = 1.0;
    for (int c = coarse; c >= fine; c /= 2, amp *= 0.55) {
      octaves_.emplace_back(c, c, HashCombine(seed, c));
      amps_.push_back(amp);
      total_ += amp;
    }
  }
  double operator()(int i, int j) const {
    double s = 0;
    for (size_t k = 0; k < octaves_.size(); ++k) s += amps_[k] * (octaves_[k](i, j) - 0.5);
    return 2.0 * s / total_;
  }

 private:
  std::vector<PeriodicNoise> octaves_;
  std::vector<double> amps_;
  double total_ = 0;
};

using Bgr = std::array<double, 3>;
Bgr Scale(const Bgr& c, double k) { return {c[0] * k, c[1] * k, c[2] * k}; }
Bgr Mix(const Bgr& a, const Bgr& b, double t) {
  return {a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t};
}
double CellRandom(uint64_t seed, int a, int b) {
  return Unit(HashCombine(seed, (static_cast<uint64_t>(a) << 32) ^ static_cast<uint32_t>(b)));
}

Texture Build(int size, double texel_m, const std::function<Bgr(int, int)>& texel) {
  Texture t;
  t.size = size;
  t.texel_m = texel_m;
  std::vector<uint8_t> level(static_cast<size_t>(size) * size * 4);
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const Bgr c = texel(i, j);
      for (int k = 0; k < 3; ++k)
        level[(j * size + i) * 4 + k] =
            static_cast<uint8_t>(std::clamp(std::lround(c[k] * 255.0), 0L, 255L));
    }
  t.levels.push_back(std::move(level));
  for (int n = size / 2; n >= 1; n /= 2) {
    const std::vector<uint8_t>& up = t.levels.back();
    std::vector<uint8_t> down(static_cast<size_t>(n) * n * 4);
    const int m = n * 2;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
          const int s = up[((2 * j) * m + 2 * i) * 4 + k] + up[((2 * j) * m + 2 * i + 1) * 4 + k] +
                        up[((2 * j + 1) * m + 2 * i) * 4 + k] + up[((2 * j + 1) * m + 2 * i + 1) * 4 + k];
          down[(j * n + i) * 4 + k] = static_cast<uint8_t>((s + 2) / 4);
        }
    t.levels.push_back(std::move(down));
  }
  t.Finish();
  return t;
}

}  // namespace

const std::vector<std::string>& MaterialNames() {
  static const std::vector<std::string> names = {
      "grass", "grass_low", "field", "soil", "gravel", "asphalt", "roof_tiles", "roof_metal",
      "brick", "plaster", "concrete", "bark", "foliage", "plain", "dark", "red", "blue", "yellow", "orange"};
  return names;
}

Texture MakeMaterialTexture(const std::string& name, uint64_t seed) {
  const uint64_t s = HashCombine(seed, HashString(name));
  if (name == "grass" || name == "grass_low") {
    // Real grass from 10 m is nearly uniform: low contrast, which is what defeats trackers.
    const double k = name == "grass" ? 1.0 : 0.3;
    const Fbm patches(128, 16, s), blades(4, 2, s + 1);
    return Build(kSize, kTexel, [&](int i, int j) {
      const Bgr base{0.16, 0.40, 0.24};
      return Scale(base, 1.0 + k * (0.22 * patches(i, j) + 0.18 * blades(i, j)));
    });
  }
  if (name == "field") {
    const Fbm noise(64, 2, s);
    return Build(kSize, kTexel, [&](int i, int j) {
      const double row = 0.5 + 0.5 * std::cos(2.0 * M_PI * i / 64.0);  // 0.64 m crop rows
      const Bgr soil{0.16, 0.27, 0.38}, crop{0.14, 0.46, 0.30};
      return Scale(Mix(soil, crop, Smooth(std::clamp(row * 1.4 - 0.2 + 0.3 * noise(i, j), 0.0, 1.0))),
                   1.0 + 0.15 * noise(j, i));
    });
  }
  if (name == "soil") {
    const Fbm noise(128, 4, s), clods(8, 2, s + 1);
    return Build(kSize, kTexel, [&](int i, int j) {
      return Scale(Bgr{0.17, 0.29, 0.42}, 1.0 + 0.3 * noise(i, j) + 0.2 * clods(i, j));
    });
  }
  if (name == "gravel") {
    const Fbm noise(64, 8, s);
    return Build(kSize, kTexel, [&](int i, int j) {
      const double stone = CellRandom(s, i / 2, j / 2);  // 2 cm stones
      const double tint = CellRandom(s + 7, i / 2, j / 2);
      return Scale(Mix(Bgr{0.50, 0.53, 0.56}, Bgr{0.38, 0.45, 0.55}, tint),
                   0.62 + 0.7 * stone * stone + 0.12 * noise(i, j));
    });
  }
  if (name == "asphalt") {
    const Fbm noise(64, 2, s);
    return Build(kSize, kTexel, [&](int i, int j) {
      return Scale(Bgr{0.25, 0.25, 0.26}, 1.0 + 0.12 * noise(i, j) + 0.15 * (CellRandom(s, i, j) - 0.5));
    });
  }
  if (name == "roof_tiles") {
    const Fbm noise(32, 2, s);
    return Build(kSize, kTexel, [&](int i, int j) {
      const int row = j / 32, shift = (row % 2) * 16;
      const int col = (i + shift) / 32;
      const double tile = CellRandom(s, col, row);
      const bool gap = (j % 32) < 3 || ((i + shift) % 32) < 2;
      const double shade = 0.78 + 0.22 * (j % 32) / 32.0;  // tiles overlap: darker at their top
      return Scale(Bgr{0.20, 0.30, 0.62}, (gap ? 0.45 : shade) * (0.85 + 0.3 * tile) + 0.05 * noise(i, j));
    });
  }
  if (name == "roof_metal") {
    const Fbm noise(64, 4, s);
    return Build(kSize, kTexel, [&](int i, int j) {
      const double corrugation = std::sin(2.0 * M_PI * i / 16.0);
      return Scale(Bgr{0.56, 0.52, 0.46}, 1.0 + 0.18 * corrugation + 0.1 * noise(i, j));
    });
  }
  if (name == "brick") {
    const Fbm noise(16, 2, s);
    return Build(kSize, kTexel, [&](int i, int j) {
      const int row = j / 8, shift = (row % 2) * 16;
      const bool mortar = (j % 8) == 0 || ((i + shift) % 32) == 0;
      if (mortar) return Scale(Bgr{0.62, 0.66, 0.68}, 1.0 + 0.05 * noise(i, j));
      const double brick = CellRandom(s, (i + shift) / 32, row);
      return Scale(Bgr{0.18, 0.26, 0.55}, 0.8 + 0.4 * brick + 0.08 * noise(i, j));
    });
  }
  if (name == "plaster") {
    const Fbm noise(128, 4, s);
    return Build(kSize, kTexel, [&](int i, int j) {
      return Scale(Bgr{0.70, 0.80, 0.86}, 1.0 + 0.06 * noise(i, j));
    });
  }
  if (name == "concrete") {
    const Fbm noise(64, 2, s);
    return Build(kSize, kTexel, [&](int i, int j) {
      return Scale(Bgr{0.58, 0.60, 0.60}, 1.0 + 0.14 * noise(i, j) + 0.1 * (CellRandom(s, i, j) - 0.5));
    });
  }
  if (name == "bark") {
    const PeriodicNoise streaks(2, 64, s), coarse(16, 128, s + 1);
    return Build(kSize, kTexel, [&](int i, int j) {
      return Scale(Bgr{0.14, 0.22, 0.30}, 0.7 + 0.45 * streaks(i, j) + 0.2 * coarse(i, j));
    });
  }
  if (name == "foliage") {
    const Fbm leaves(32, 2, s);
    return Build(kSize, kTexel, [&](int i, int j) {
      const double l = leaves(i, j);
      return Scale(Bgr{0.10, 0.34, 0.16}, 0.9 + 0.9 * l);
    });
  }
  if (name == "plain") {  // featureless indoor walls (thesis 4.4)
    return Build(16, 0.1, [&](int, int) { return Bgr{0.72, 0.74, 0.75}; });
  }
  if (name == "dark") {  // cables, poles' paint
    return Build(16, 0.1, [&](int, int) { return Bgr{0.07, 0.07, 0.08}; });
  }
  // Saturated paint and cloth (tracking targets, thesis 3.7): a strong hue with a fine weave so
  // stereo and flow still find texture on them.
  const auto paint = [&](Bgr colour) {
    const Fbm weave(16, 2, s);
    return Build(kSize, kTexel, [&](int i, int j) { return Scale(colour, 0.85 + 0.3 * weave(i, j)); });
  };
  if (name == "red") return paint(Bgr{0.10, 0.12, 0.78});
  if (name == "blue") return paint(Bgr{0.75, 0.30, 0.08});
  if (name == "yellow") return paint(Bgr{0.10, 0.75, 0.85});
  if (name == "orange") return paint(Bgr{0.05, 0.40, 0.90});
  throw std::invalid_argument("unknown material '" + name + "'");
}

Texture MakeMacroTexture(uint64_t seed) {
  // 256 texels of 0.5 m: brightness drifts over tens of metres, so the 5 m detail tiles never
  // repeat visibly.
  Texture t;
  const uint64_t s = HashCombine(seed, 0x6d6163726full);
  std::vector<PeriodicNoise> octaves;
  for (int c = 64; c >= 2; c /= 2) octaves.emplace_back(c / 2, c / 2, HashCombine(s, c));
  return Build(256, 0.5, [&](int i, int j) {
    double v = 0, a = 1, total = 0;
    for (const auto& o : octaves) {
      v += a * (o(i, j) - 0.5);
      total += a;
      a *= 0.6;
    }
    v = 2 * v / total;
    // Stored halved so values above 1 fit a byte; GroundAlbedo doubles them.
    return Bgr{0.5 + 0.14 * v, 0.5 + 0.125 * v, 0.5 + 0.11 * v};
  });
}

double ValueNoise2(double x, double y, uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const int64_t x0 = static_cast<int64_t>(fx), y0 = static_cast<int64_t>(fy);
  const double ax = Smooth(x - fx), ay = Smooth(y - fy);
  auto v = [&](int64_t a, int64_t b) {
    return Unit(HashCombine(seed, static_cast<uint64_t>(a) * 73856093ull ^ static_cast<uint64_t>(b) * 19349663ull));
  };
  const double top = v(x0, y0) * (1 - ax) + v(x0 + 1, y0) * ax;
  const double bottom = v(x0, y0 + 1) * (1 - ax) + v(x0 + 1, y0 + 1) * ax;
  return top * (1 - ay) + bottom * ay;
}

}  // namespace uav::world
