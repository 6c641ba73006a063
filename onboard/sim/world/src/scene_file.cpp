// Scene files (resources/scenes/*.scene.json): objects, procedural generators, lighting,
// cameras and the seed. Every error names the file and the JSON path of the bad entry.
#include <filesystem>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "scene_impl.hpp"
#include "uav/shared/text_file.hpp"

namespace uav::world {

namespace {

using nlohmann::json;

struct SceneFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void Fail(const std::string& path, const std::string& what) const {
    throw SceneFileError(source_ + ": " + path + ": " + what);
  }
  // Whether object j has `key`; remembered, so a field nobody asked for is known to be unknown.
  bool Has(const json& j, const char* key) const {
    asked_[&j].insert(key);
    return j.is_object() && j.contains(key);
  }
  const json& Field(const json& j, const std::string& path, const char* key) const {
    if (!j.is_object()) Fail(path, "must be an object");
    if (!Has(j, key)) Fail(path, std::string("missing '") + key + "'");
    return j.at(key);
  }
  // Refuses a field no part of the reader asked for: a misspelt "colour" or a field of another
  // kind of object would otherwise be ignored without a word.
  void RefuseUnknownFields(const json& j, const std::string& path) const {
    if (j.is_array()) {
      for (std::size_t i = 0; i < j.size(); ++i) RefuseUnknownFields(j[i], path + "[" + std::to_string(i) + "]");
      return;
    }
    if (!j.is_object()) return;
    const auto asked = asked_.find(&j);
    if (asked == asked_.end()) return;  // read whole elsewhere (a wrapper copy), or not an object of ours
    for (const auto& [key, value] : j.items()) {
      if (!asked->second.count(key)) {
        std::string known;
        for (const std::string& k : asked->second) known += (known.empty() ? "" : ", ") + k;
        Fail(path, "unknown field '" + key + "' (fields here: " + known + ")");
      }
      RefuseUnknownFields(value, path + "." + key);
    }
  }
  double Number(const json& j, const std::string& path, const char* key, double lo, double hi) const {
    const json& v = Field(j, path, key);
    if (!v.is_number()) Fail(path + "." + key, "must be a number");
    const double x = v.get<double>();
    if (!std::isfinite(x) || x < lo || x > hi)
      Fail(path + "." + key, "must be in [" + Format(lo) + ", " + Format(hi) + "], got " + Format(x));
    return x;
  }
  double Number(const json& j, const std::string& path, const char* key, double lo, double hi, double fallback) const {
    return Has(j, key) ? Number(j, path, key, lo, hi) : fallback;
  }
  int Integer(const json& j, const std::string& path, const char* key, int lo, int hi) const {
    const json& v = Field(j, path, key);
    if (!v.is_number_integer()) Fail(path + "." + key, "must be an integer");
    const int64_t x = v.get<int64_t>();
    if (x < lo || x > hi) Fail(path + "." + key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<int>(x);
  }
  int Integer(const json& j, const std::string& path, const char* key, int lo, int hi, int fallback) const {
    return Has(j, key) ? Integer(j, path, key, lo, hi) : fallback;
  }
  bool Bool(const json& j, const std::string& path, const char* key, bool fallback) const {
    if (!Has(j, key)) return fallback;
    if (!j.at(key).is_boolean()) Fail(path + "." + key, "must be true or false");
    return j.at(key).get<bool>();
  }
  std::string String(const json& j, const std::string& path, const char* key) const {
    const json& v = Field(j, path, key);
    if (!v.is_string()) Fail(path + "." + key, "must be a string");
    return v.get<std::string>();
  }
  std::string String(const json& j, const std::string& path, const char* key, const std::string& fallback) const {
    return Has(j, key) ? String(j, path, key) : fallback;
  }
  std::string Material(const json& j, const std::string& path, const char* key, const std::string& fallback) const {
    const std::string m = String(j, path, key, fallback);
    if (m.empty() && !Has(j, key)) return m;  // optional, absent
    for (const auto& n : MaterialNames())
      if (n == m) return m;
    Fail(path + "." + key, "unknown material '" + m + "'");
  }
  std::vector<double> Vector(const json& j, const std::string& path, const char* key, size_t n, double lo, double hi) const {
    const json& v = Field(j, path, key);
    if (!v.is_array() || v.size() != n) Fail(path + "." + key, "must be an array of " + std::to_string(n) + " numbers");
    std::vector<double> out;
    for (size_t i = 0; i < n; ++i) {
      if (!v[i].is_number()) Fail(path + "." + key + "[" + std::to_string(i) + "]", "must be a number");
      const double x = v[i].get<double>();
      if (!std::isfinite(x) || x < lo || x > hi)
        Fail(path + "." + key + "[" + std::to_string(i) + "]", "must be in [" + Format(lo) + ", " + Format(hi) + "]");
      out.push_back(x);
    }
    return out;
  }
  Eigen::Vector3d Vec3(const json& j, const std::string& path, const char* key, double lo, double hi) const {
    const auto v = Vector(j, path, key, 3, lo, hi);
    return {v[0], v[1], v[2]};
  }
  Eigen::Vector2d Vec2(const json& j, const std::string& path, const char* key, double lo, double hi) const {
    const auto v = Vector(j, path, key, 2, lo, hi);
    return {v[0], v[1]};
  }
  // [lo, hi] range with lo <= hi.
  Eigen::Vector2d Range(const json& j, const std::string& path, const char* key, double lo, double hi) const {
    const Eigen::Vector2d r = Vec2(j, path, key, lo, hi);
    if (r.x() > r.y()) Fail(path + "." + key, "first value must not exceed the second");
    return r;
  }
  std::vector<std::string> Materials(const json& j, const std::string& path, const char* key,
                                     const std::vector<std::string>& fallback) const {
    if (!Has(j, key)) return fallback;
    const json& v = j.at(key);
    if (!v.is_array() || v.empty()) Fail(path + "." + key, "must be a non-empty array of material names");
    std::vector<std::string> out;
    for (size_t i = 0; i < v.size(); ++i) {
      json wrapper = {{"m", v[i]}};
      out.push_back(Material(wrapper, path + "." + key + "[" + std::to_string(i) + "]", "m", ""));
    }
    return out;
  }
  static std::string Format(double x) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
  }

 private:
  std::string source_;
  mutable std::map<const json*, std::set<std::string>> asked_;
};

constexpr double kBig = 1e5;  // [m] coordinates of anything in a scene

Eigen::Isometry3d PoseFromRpy(const Eigen::Vector3d& p, const Eigen::Vector3d& rpy_deg) {
  const Eigen::Vector3d r = rpy_deg * M_PI / 180.0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(r.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(r.y(), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(r.x(), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = p;
  return T;
}

// Deterministic uniform numbers for the generators.
class Draw {
 public:
  explicit Draw(uint64_t seed) : state_(seed) {}
  double Uniform(double lo, double hi) {
    state_ = SplitMix64(state_);
    return lo + (hi - lo) * Unit(state_);
  }
  size_t Pick(size_t n) { return std::min(n - 1, static_cast<size_t>(Uniform(0, n))); }

 private:
  uint64_t state_;
};

struct Footprint {
  Eigen::Vector2d c;
  double r;
};

bool Free(const std::vector<Footprint>& taken, const Eigen::Vector2d& c, double r, double clear_radius) {
  if (c.norm() < clear_radius + r) return false;
  for (const auto& f : taken)
    if ((f.c - c).norm() < f.r + r + 2.0) return false;
  return true;
}

// An obstacle-avoidance test field (docs/modules/avoidance.md): `count` obstacles in the region,
// 45 % trees (crown 0.8-2 m), 30 % poles (radius 0.15-0.6 m, 6-12 m tall), 10 % walls (2-6 m
// long, 0.3 m thick, 3-8 m high), 15 % boxes (1-3 m, 1-5 m high), overlapping as they fall;
// then `wires` cables between pole tops 3-15 m apart, hung at wire_height_m. Nothing within
// clear_radius_m of home or of the keep_clear_ne point (the far end: where the flight goes).
void GenerateObstacleField(const Reader& rd, const json& j, const std::string& p, int count, const std::vector<double>& region,
                           double clear, Draw& draw, Scene& scene) {
  const Eigen::Vector2d keep = rd.Has(j, "keep_clear_ne") ? rd.Vec2(j, p, "keep_clear_ne", -kBig, kBig) : Eigen::Vector2d::Zero();
  const int wires = rd.Integer(j, p, "wires", 0, 10000, 0);
  const Eigen::Vector2d wire_h = rd.Has(j, "wire_height_m") ? rd.Range(j, p, "wire_height_m", 0.5, 100) : Eigen::Vector2d(3, 8);
  auto clear_of_ends = [&](const Eigen::Vector2d& c, double r) { return c.norm() > clear + r && (c - keep).norm() > clear + r; };
  std::vector<Eigen::Vector3d> pole_tops;
  for (int placed = 0, attempt = 0; placed < count && attempt < 100 * count + 100; ++attempt) {
    const Eigen::Vector2d c(draw.Uniform(region[0], region[2]), draw.Uniform(region[1], region[3]));
    const double kind = draw.Uniform(0, 1);
    if (kind < 0.45) {
      const double crown = draw.Uniform(0.8, 2.0), height = std::max(6.0, 2 * crown + 1) + draw.Uniform(0, 8);
      if (!clear_of_ends(c, crown)) continue;
      scene.AddTree({c.x(), c.y(), 0}, height, crown);
    } else if (kind < 0.75) {
      const double r = draw.Uniform(0.15, 0.6), h = draw.Uniform(6, 12);
      if (!clear_of_ends(c, r)) continue;
      scene.AddCylinder("pole", {c.x(), c.y(), 0}, r, h, "concrete");
      pole_tops.emplace_back(c.x(), c.y(), -h);
    } else if (kind < 0.85) {
      const double len = draw.Uniform(2, 6), yaw = draw.Uniform(0, M_PI), h = draw.Uniform(3, 8);
      const std::string material = draw.Uniform(0, 1) < 0.5 ? "brick" : "plaster";
      if (!clear_of_ends(c, len / 2)) continue;
      scene.AddBox("wall", {c.x(), c.y(), -h / 2}, {len, 0.3, h}, yaw, material);
    } else {
      const double size = draw.Uniform(1, 3), h = draw.Uniform(1, 5), yaw = draw.Uniform(0, M_PI);
      if (!clear_of_ends(c, size)) continue;
      scene.AddBox("box", {c.x(), c.y(), -h / 2}, {size, size, h}, yaw, "concrete");
    }
    ++placed;
  }
  for (int w = 0, attempt = 0; w < wires && pole_tops.size() >= 2 && attempt < 200 * wires; ++attempt) {
    const Eigen::Vector3d& a = pole_tops[draw.Pick(pole_tops.size())];
    const Eigen::Vector3d& b = pole_tops[draw.Pick(pole_tops.size())];
    const Eigen::Vector2d ab = (b - a).head<2>();
    const double span = ab.norm();
    if (span < 3 || span > 15) continue;
    auto distance_to = [&](const Eigen::Vector2d& q) {
      const double t = std::clamp((q - a.head<2>()).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      return (a.head<2>() + t * ab - q).norm();
    };
    if (distance_to(Eigen::Vector2d::Zero()) < clear || distance_to(keep) < clear) continue;
    const double h = draw.Uniform(wire_h.x(), wire_h.y());
    scene.AddCable({a.x(), a.y(), -h}, {b.x(), b.y(), -h}, 0.3, 0.01);
    ++w;
  }
}

CameraSetup ReadCamera(const Reader& rd, const json& j, const std::string& path, const std::string& scene_dir,
                       const std::string& name, const std::string& default_file, double default_rate,
                       double default_preview_rate) {
  CameraSetup c;
  c.name = name;
  std::string file = rd.String(j, path, "file", default_file);
  if (!file.empty() && file[0] != '/') {
    // A relative camera file is looked for beside the scene, then in the cameras folder beside
    // the scenes folder (the shipped layout, resources/scenes and resources/cameras).
    const std::string beside = scene_dir + "/" + file, shipped = scene_dir + "/../cameras/" + file;
    std::error_code ec;
    if (std::filesystem::is_regular_file(beside, ec)) file = beside;
    else if (std::filesystem::is_regular_file(shipped, ec)) file = shipped;
    else
      rd.Fail(path + ".file", "camera file '" + file + "' is in neither " + beside + " nor " + shipped +
                                  ": copy it beside the scene, or give its absolute path (a scene copied to another "
                                  "folder takes its cameras along)");
  }
  try {
    c.intrinsics = IntrinsicsFromParameters(ParameterSet::LoadFile(file, uav::CameraParameterSchema()));
  } catch (const std::exception& e) {
    rd.Fail(path + ".file", e.what());
  }
  c.rate_hz = rd.Number(j, path, "rate_hz", 0.1, 100, default_rate);
  c.preview_rate_hz = rd.Number(j, path, "preview_rate_hz", 0, c.rate_hz, std::min(c.rate_hz, default_preview_rate));
  c.noise_sigma = rd.Number(j, path, "noise_sigma", 0, 49, c.noise_sigma);
  c.exposure_s = rd.Number(j, path, "exposure_s", 0, 0.5, c.exposure_s);
  c.blur_samples = rd.Integer(j, path, "blur_samples", 1, 16, c.blur_samples);
  c.supersample = rd.Integer(j, path, "supersample", 1, 4, c.supersample);
  c.auto_exposure = rd.Bool(j, path, "auto_exposure", c.auto_exposure);
  c.target_mean = rd.Number(j, path, "target_mean", 0.05, 0.95, c.target_mean);
  return c;
}

}  // namespace

Scene Scene::LoadFile(const std::string& path) { return Parse(ReadTextFile(path, "scene file"), path); }

Scene Scene::Parse(const std::string& text, const std::string& source) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    throw SceneFileError(source + ": not valid JSON: " + e.what());
  } catch (const json::exception& e) {  // a number too large for a double (1e999), ...
    throw SceneFileError(source + ": not a valid scene: " + e.what());
  }
  const Reader rd(source);
  if (!root.is_object()) rd.Fail("$", "must be an object");
  const int64_t seed_value = rd.Integer(root, "$", "seed", 0, 2147483647, 0);
  Scene scene(static_cast<uint64_t>(seed_value));
  scene.SetName(rd.String(root, "$", "name", "unnamed"));
  const std::string dir = source.find('/') == std::string::npos ? "." : source.substr(0, source.rfind('/'));

  try {
    scene.SetSky(rd.Bool(root, "$", "sky", true));
    if (rd.Has(root, "sun")) {
      const json& j = root["sun"];
      const double az = rd.Number(j, "$.sun", "azimuth_deg", -360, 360) * M_PI / 180;
      const double el = rd.Number(j, "$.sun", "elevation_deg", 5, 90) * M_PI / 180;
      SunLight sun;
      sun.to_sun_N = Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), -std::sin(el));
      sun.ambient = rd.Number(j, "$.sun", "ambient", 0, 1, sun.ambient);
      scene.SetSun(sun);
    }
    if (rd.Has(root, "ground")) {
      const json& j = root["ground"];
      const std::string p = "$.ground";
      GroundSpec g;
      const std::string layout = rd.String(j, p, "layout", "uniform");
      if (layout == "none") {
        g.enabled = false;
      } else if (layout == "uniform") {
        g.layout = GroundSpec::Layout::kUniform;
        g.material = rd.Material(j, p, "material", "grass");
      } else if (layout == "fields") {
        g.layout = GroundSpec::Layout::kFields;
        g.parcel_materials = rd.Materials(j, p, "parcel_materials", {"field", "grass", "soil", "gravel", "grass_low"});
        g.parcel_m = rd.Number(j, p, "parcel_m", 5, 1000, g.parcel_m);
        g.grid_yaw = rd.Number(j, p, "grid_yaw_deg", -360, 360, 0) * M_PI / 180;
        g.road_every = rd.Integer(j, p, "road_every", 0, 1000, g.road_every);
        g.road_width_m = rd.Number(j, p, "road_width_m", 0, 100, g.road_width_m);
        if (g.road_width_m >= g.parcel_m) rd.Fail(p + ".road_width_m", "must be below parcel_m");
      } else {
        rd.Fail(p + ".layout", "must be 'uniform', 'fields' or 'none', got '" + layout + "'");
      }
      if (g.enabled) scene.SetGround(g);
    }
    if (rd.Has(root, "clouds")) {
      const json& j = root["clouds"];
      const std::string p = "$.clouds";
      CloudShadows c;
      c.enabled = true;
      c.coverage = rd.Number(j, p, "coverage", 0, 1);
      c.darkness = rd.Number(j, p, "darkness", 0, 1, c.darkness);
      c.scale_m = rd.Number(j, p, "scale_m", 1, 10000, c.scale_m);
      if (rd.Has(j, "velocity_ne_mps")) c.velocity_NE = rd.Vec2(j, p, "velocity_ne_mps", -100, 100);
      scene.SetClouds(c);
    }

    std::vector<Footprint> taken;
    if (rd.Has(root, "objects")) {
      const json& list = root["objects"];
      if (!list.is_array()) rd.Fail("$.objects", "must be an array");
      for (size_t i = 0; i < list.size(); ++i) {
        const json& j = list[i];
        const std::string p = "$.objects[" + std::to_string(i) + "]";
        const std::string type = rd.String(j, p, "type");
        int id = -1;  // objects that may move
        if (type == "box") {
          const Eigen::Vector3d c = rd.Vec3(j, p, "center_ned", -kBig, kBig);
          const Eigen::Vector3d size = rd.Vec3(j, p, "size", 0.001, 1000);
          id = scene.AddBox(rd.String(j, p, "kind", "box"), c, size, rd.Number(j, p, "yaw_deg", -360, 360, 0) * M_PI / 180,
                            rd.Material(j, p, "material", "concrete"), rd.Material(j, p, "top_material", ""));
          taken.push_back({c.head<2>(), size.head<2>().norm() / 2});
        } else if (type == "building") {
          const Eigen::Vector2d at = rd.Vec2(j, p, "at_ne", -kBig, kBig);
          const Eigen::Vector2d fp = rd.Vec2(j, p, "footprint_m", 1, 500);
          const double h = rd.Number(j, p, "height_m", 1, 300);
          scene.AddBox("building", Eigen::Vector3d(at.x(), at.y(), -h / 2), Eigen::Vector3d(fp.x(), fp.y(), h),
                       rd.Number(j, p, "yaw_deg", -360, 360, 0) * M_PI / 180, rd.Material(j, p, "wall", "plaster"),
                       rd.Material(j, p, "roof", "roof_tiles"));
          taken.push_back({at, fp.norm() / 2});
        } else if (type == "cylinder") {
          const Eigen::Vector3d b = rd.Vec3(j, p, "base_ned", -kBig, kBig);
          const double r = rd.Number(j, p, "radius_m", 0.001, 100);
          id = scene.AddCylinder(rd.String(j, p, "kind", "cylinder"), b, r, rd.Number(j, p, "height_m", 0.001, 1000),
                                 rd.Material(j, p, "material", "concrete"));
          taken.push_back({b.head<2>(), r});
        } else if (type == "sphere") {
          id = scene.AddSphere(rd.String(j, p, "kind", "sphere"), rd.Vec3(j, p, "center_ned", -kBig, kBig),
                               rd.Number(j, p, "radius_m", 0.001, 100), rd.Material(j, p, "material", "concrete"));
        } else if (type == "tree") {
          const Eigen::Vector2d at = rd.Vec2(j, p, "at_ne", -kBig, kBig);
          const double h = rd.Number(j, p, "height_m", 1, 60);
          const double cr = rd.Number(j, p, "crown_radius_m", 0.2, 20);
          if (2 * cr >= h) rd.Fail(p + ".crown_radius_m", "crown diameter must be below the height");
          scene.AddTree(Eigen::Vector3d(at.x(), at.y(), 0), h, cr);
          taken.push_back({at, cr});
        } else if (type == "person") {
          const Eigen::Vector2d at = rd.Vec2(j, p, "at_ne", -kBig, kBig);
          id = scene.AddPerson(Eigen::Vector3d(at.x(), at.y(), 0), rd.Number(j, p, "height_m", 1.0, 2.3, 1.75),
                               rd.Material(j, p, "clothing", "concrete"));
          taken.push_back({at, 0.3});
        } else if (type == "room") {
          scene.AddRoom(rd.Vec3(j, p, "center_ned", -kBig, kBig), rd.Vec3(j, p, "size", 0.5, 1000),
                        rd.Material(j, p, "material", "plain"), rd.Material(j, p, "floor_material", ""));
        } else if (type == "power_line") {
          const json& poles = rd.Field(j, p, "poles_ne");
          if (!poles.is_array() || poles.size() < 2) rd.Fail(p + ".poles_ne", "must list at least two [n, e] poles");
          std::vector<Eigen::Vector2d> at;
          for (size_t k = 0; k < poles.size(); ++k) {
            json wrapper = {{"v", poles[k]}};
            at.push_back(rd.Vec2(wrapper, p + ".poles_ne[" + std::to_string(k) + "]", "v", -kBig, kBig));
          }
          const double h = rd.Number(j, p, "pole_height_m", 2, 100);
          const double pr = rd.Number(j, p, "pole_radius_m", 0.02, 2, 0.15);
          const double sag = rd.Number(j, p, "sag_m", 0, 50);
          const double cr = rd.Number(j, p, "cable_radius_m", 0.001, 0.2, 0.01);
          std::vector<double> offsets = {0.0};
          if (rd.Has(j, "wire_offsets_m")) {
            const json& o = j["wire_offsets_m"];
            if (!o.is_array() || o.empty()) rd.Fail(p + ".wire_offsets_m", "must be a non-empty array of numbers");
            offsets.clear();
            for (size_t k = 0; k < o.size(); ++k) {
              json wrapper = {{"v", o[k]}};
              offsets.push_back(rd.Number(wrapper, p + ".wire_offsets_m[" + std::to_string(k) + "]", "v", -10, 10));
            }
          }
          double arm = 0.3;
          for (double o : offsets) arm = std::max(arm, 2 * std::abs(o) + 0.3);
          for (size_t k = 0; k < at.size(); ++k) {
            scene.AddCylinder("pole", Eigen::Vector3d(at[k].x(), at[k].y(), 0), pr, h, "concrete");
            taken.push_back({at[k], pr});
          }
          for (size_t k = 0; k + 1 < at.size(); ++k) {
            const Eigen::Vector2d dir = (at[k + 1] - at[k]).normalized();
            const Eigen::Vector2d side(-dir.y(), dir.x());
            if (!((at[k + 1] - at[k]).norm() > 2 * sag + 0.5))
              rd.Fail(p + ".sag_m", "must be below half of every span");
            for (double o : offsets) {
              const Eigen::Vector2d a = at[k] + o * side, b = at[k + 1] + o * side;
              scene.AddCable(Eigen::Vector3d(a.x(), a.y(), -h + 0.2), Eigen::Vector3d(b.x(), b.y(), -h + 0.2), sag, cr);
            }
          }
          for (size_t k = 0; k < at.size(); ++k) {
            const Eigen::Vector2d dir = (at[std::min(k + 1, at.size() - 1)] - at[k == at.size() - 1 ? k - 1 : k]).normalized();
            scene.AddBox("crossarm", Eigen::Vector3d(at[k].x(), at[k].y(), -h + 0.1), Eigen::Vector3d(0.12, arm, 0.12),
                         std::atan2(dir.y(), dir.x()), "concrete");
          }
        } else if (type == "chessboard") {
          scene.AddChessboard(rd.Integer(j, p, "cols", 2, 50), rd.Integer(j, p, "rows", 2, 50),
                              rd.Number(j, p, "square_m", 0.001, 10),
                              PoseFromRpy(rd.Vec3(j, p, "origin_ned", -kBig, kBig), rd.Vec3(j, p, "rpy_deg", -360, 360)));
        } else {
          rd.Fail(p + ".type", "unknown object type '" + type + "'");
        }
        if (rd.Has(j, "path")) {
          const json& path = j["path"];
          const std::string pp = p + ".path";
          if (id < 0) rd.Fail(pp, "only boxes, cylinders, spheres and people can move");
          const json& points = rd.Field(path, pp, "waypoints_ne");
          if (!points.is_array() || points.size() < 2) rd.Fail(pp + ".waypoints_ne", "must list at least two [n, e] points");
          ObjectPath route;
          for (size_t k = 0; k < points.size(); ++k) {
            json wrapper = {{"v", points[k]}};
            route.waypoints_NE.push_back(rd.Vec2(wrapper, pp + ".waypoints_ne[" + std::to_string(k) + "]", "v", -kBig, kBig));
          }
          route.speed_mps = rd.Number(path, pp, "speed_mps", 0.01, 50);
          route.start_s = rd.Number(path, pp, "start_s", 0, 1e9, 0);
          route.loop = rd.Bool(path, pp, "loop", true);
          try {
            scene.SetPath(id, route);
          } catch (const std::invalid_argument& e) {
            rd.Fail(pp, e.what());
          }
        }
      }
    }

    if (rd.Has(root, "generate")) {
      const json& list = root["generate"];
      if (!list.is_array()) rd.Fail("$.generate", "must be an array");
      for (size_t i = 0; i < list.size(); ++i) {
        const json& j = list[i];
        const std::string p = "$.generate[" + std::to_string(i) + "]";
        const std::string type = rd.String(j, p, "type");
        const int count = rd.Integer(j, p, "count", 0, 100000);
        const auto region = rd.Vector(j, p, "region_ne", 4, -kBig, kBig);
        if (region[0] >= region[2] || region[1] >= region[3]) rd.Fail(p + ".region_ne", "must be [n_min, e_min, n_max, e_max]");
        const double clear = rd.Number(j, p, "clear_radius_m", 0, 10000, 15);
        Draw draw(HashCombine(scene.seed(), 1000 + i));
        if (type == "obstacle_field") {
          GenerateObstacleField(rd, j, p, count, region, clear, draw, scene);
          continue;
        }
        int placed = 0;
        for (int attempt = 0; attempt < 50 * count + 50 && placed < count; ++attempt) {
          const Eigen::Vector2d c(draw.Uniform(region[0], region[2]), draw.Uniform(region[1], region[3]));
          if (type == "buildings") {
            const Eigen::Vector2d fp_range = rd.Range(j, p, "footprint_m", 1, 500);
            const Eigen::Vector2d h_range = rd.Range(j, p, "height_m", 1, 300);
            const auto walls = rd.Materials(j, p, "walls", {"plaster", "brick", "concrete"});
            const auto roofs = rd.Materials(j, p, "roofs", {"roof_tiles", "roof_metal", "concrete"});
            const Eigen::Vector2d fp(draw.Uniform(fp_range.x(), fp_range.y()), draw.Uniform(fp_range.x(), fp_range.y()));
            const double h = draw.Uniform(h_range.x(), h_range.y());
            const double yaw = draw.Uniform(-M_PI, M_PI);
            const std::string& wall = walls[draw.Pick(walls.size())];
            const std::string& roof = roofs[draw.Pick(roofs.size())];
            if (!Free(taken, c, fp.norm() / 2, clear)) continue;
            scene.AddBox("building", Eigen::Vector3d(c.x(), c.y(), -h / 2), Eigen::Vector3d(fp.x(), fp.y(), h), yaw, wall, roof);
            taken.push_back({c, fp.norm() / 2});
          } else if (type == "trees") {
            const Eigen::Vector2d h_range = rd.Range(j, p, "height_m", 1, 60);
            const Eigen::Vector2d r_range = rd.Range(j, p, "crown_radius_m", 0.2, 20);
            const double h = draw.Uniform(h_range.x(), h_range.y());
            const double r = std::min(draw.Uniform(r_range.x(), r_range.y()), 0.45 * h);
            if (!Free(taken, c, r, clear)) continue;
            scene.AddTree(Eigen::Vector3d(c.x(), c.y(), 0), h, r);
            taken.push_back({c, r});
          } else if (type == "people") {
            const double h = draw.Uniform(1.55, 1.95);
            if (!Free(taken, c, 0.3, clear)) continue;
            scene.AddPerson(Eigen::Vector3d(c.x(), c.y(), 0), h);
            taken.push_back({c, 0.3});
          } else {
            rd.Fail(p + ".type", "unknown generator '" + type + "' (buildings, trees, people, obstacle_field)");
          }
          ++placed;
        }
      }
    }

    if (rd.Has(root, "cameras")) {
      const json& cams = root["cameras"];
      if (!cams.is_object()) rd.Fail("$.cameras", "must be an object");
      if (rd.Has(cams, "downward")) {
        const json& j = cams["downward"];
        const std::string p = "$.cameras.downward";
        CameraSetup c = ReadCamera(rd, j, p, dir, "downward", "sim_downward_640x480.camera", 5.0, 5.0);
        const Eigen::Vector3d mount = rd.Has(j, "mount_xyz_m") ? rd.Vec3(j, p, "mount_xyz_m", -5, 5) : Eigen::Vector3d(0, 0, 0.1);
        const double yaw = rd.Number(j, p, "mount_yaw_deg", -360, 360, 0) * M_PI / 180;
        c.T_BC = Eigen::Isometry3d::Identity();
        c.T_BC.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * RotationBCDownward();
        c.T_BC.translation() = mount;
        scene.SetDownwardCamera(c);
      }
      if (rd.Has(cams, "gimbal")) {
        const json& j = cams["gimbal"];
        const std::string p = "$.cameras.gimbal";
        CameraSetup c = ReadCamera(rd, j, p, dir, "gimbal", "sim_downward_640x480.camera", 10.0, 5.0);
        c.T_BC = Eigen::Isometry3d::Identity();
        c.T_BC.linear() = RotationBCForward();
        c.T_BC.translation() = rd.Has(j, "mount_xyz_m") ? rd.Vec3(j, p, "mount_xyz_m", -5, 5) : Eigen::Vector3d(0.1, 0, 0.15);
        scene.SetGimbalCamera(c);
      }
      // "stereo" is one rig (named "stereo") or a list of rigs, each with its own "name" and mount
      // (a forward pair for obstacles and odometry, a downward pair with the dot projector...).
      const json none = json::array();
      const json& rigs = rd.Has(cams, "stereo") ? cams["stereo"] : none;
      const bool listed = rigs.is_array();
      if (listed && rigs.size() > 8) rd.Fail("$.cameras.stereo", "at most 8 stereo rigs");
      for (size_t k = 0; k < (listed ? rigs.size() : 1); ++k) {
        const json& j = listed ? rigs[k] : rigs;
        const std::string p = "$.cameras.stereo" + (listed ? "[" + std::to_string(k) + "]" : std::string());
        if (!j.is_object()) rd.Fail(p, "must be an object");
        const std::string name = listed ? rd.String(j, p, "name") : rd.String(j, p, "name", "stereo");
        if (name.empty() || name.size() > 32) rd.Fail(p + ".name", "must be 1-32 characters");
        const CameraSetup c = ReadCamera(rd, j, p, dir, name, "sim_stereo_640x480.camera", 10.0,
                                           scene.downward_camera() || k > 0 ? 0.0 : 5.0);
        const Eigen::Vector3d mount = rd.Has(j, "mount_xyz_m") ? rd.Vec3(j, p, "mount_xyz_m", -5, 5) : Eigen::Vector3d(0.15, 0, 0);
        // Mount angles: the optical axis pitched up from the body x axis (-90: facing down), and
        // the pair rolled about it (a rolled baseline ranges the level wires a level one cannot:
        // a wire parallel to the baseline has no disparity to measure).
        const double pitch_up = rd.Number(j, p, "mount_pitch_deg", -90, 90, 0) * M_PI / 180;
        const double roll = rd.Number(j, p, "mount_roll_deg", -90, 90, 0) * M_PI / 180;
        Eigen::Isometry3d T_B_rig = Eigen::Isometry3d::Identity();
        T_B_rig.linear() = Eigen::AngleAxisd(pitch_up, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                           RotationBCForward() * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        T_B_rig.translation() = mount;
        LaserEmitter laser;
        if (rd.Has(j, "laser")) {
          const json& l = j["laser"];
          const std::string lp = p + ".laser";
          laser.enabled = rd.Bool(l, lp, "enabled", true);
          laser.rows = rd.Integer(l, lp, "rows", 1, 100, laser.rows);
          laser.cols = rd.Integer(l, lp, "cols", 1, 100, laser.cols);
          laser.pitch_rad = rd.Number(l, lp, "pitch_deg", 0.01, 10, laser.pitch_rad * 180 / M_PI) * M_PI / 180;
          laser.intensity = rd.Number(l, lp, "intensity", 1, 1000, laser.intensity);
          laser.roll_rad = rd.Number(l, lp, "roll_deg", -90, 90, 0) * M_PI / 180;
        }
        try {
          scene.AddStereoRig(MakeStereoSetup(c, T_B_rig, rd.Number(j, p, "baseline_m", 0.01, 2, 0.12), laser));
        } catch (const std::invalid_argument& e) {
          rd.Fail(p + ".name", e.what());
        }
      }
    }
  } catch (const SceneFileError&) {
    throw;
  } catch (const std::exception& e) {
    throw SceneFileError(source + ": " + e.what());
  }
  rd.RefuseUnknownFields(root, "$");
  return scene;
}

}  // namespace uav::world
