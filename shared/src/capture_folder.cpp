#include "uav/shared/capture_folder.hpp"

#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "uav/shared/text_file.hpp"

namespace uav {
namespace {

[[noreturn]] void Fail(const std::string& what) { throw std::invalid_argument(what); }

}  // namespace

CaptureSession ReadCaptureSession(const std::string& path) {
  using json = nlohmann::json;
  try {
    const json j = json::parse(ReadTextFile(path, "session file"));
    CaptureSession s;
    s.home.latitude_deg = j.at("home").at("latitude_deg");
    s.home.longitude_deg = j.at("home").at("longitude_deg");
    s.home.altitude_m = j.at("home").at("altitude_m");
    const json& c = j.at("camera");
    // Checked before converting: a float too large for an int is undefined behaviour.
    auto pixels = [&](const char* name) {
      const json& v = c.at(name);
      if (!v.is_number_integer() || v.get<double>() < 1 || v.get<double>() > 100000)
        Fail(path + ": camera " + name + " must be a whole number of pixels, 1 to 100000");
      return static_cast<int>(v.get<double>());
    };
    s.camera.width = pixels("width");
    s.camera.height = pixels("height");
    s.camera.fx = c.at("fx");
    s.camera.fy = c.at("fy");
    s.camera.cx = c.at("cx");
    s.camera.cy = c.at("cy");
    for (int i = 0; i < 5; ++i) s.camera.distortion[i] = c.at("distortion").at(i);
    for (int i = 0; i < 9; ++i) s.T_BC.linear()(i / 3, i % 3) = c.at("R_BC").at(i);
    for (int i = 0; i < 3; ++i) s.T_BC.translation()(i) = c.at("p_B").at(i);
    ValidateGeodetic(s.home);
    ValidateIntrinsics(s.camera);
    return s;
  } catch (const json::exception& e) {
    Fail(path + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    Fail(path + ": " + e.what());
  }
}

std::vector<CaptureRow> ReadCaptureRows(const std::string& path) {
  std::istringstream in(ReadTextFile(path, "poses file"));
  std::string line;
  if (!std::getline(in, line)) Fail(path + ": empty");
  std::map<std::string, int> col;
  size_t columns = 0;
  {
    std::istringstream h(line);
    std::string name;
    for (int i = 0; std::getline(h, name, ','); ++i, ++columns)
      if (!col.emplace(name, i).second) Fail(path + ": column '" + name + "' appears twice in the header");
  }
  for (const char* need : {"utime", "file", "est_north_m", "est_east_m", "est_down_m", "est_roll_rad", "est_pitch_rad", "est_yaw_rad"})
    if (!col.count(need)) Fail(path + ": no column '" + std::string(need) + "'");
  std::vector<CaptureRow> out;
  for (int row = 2; std::getline(in, line); ++row) {
    if (line.empty()) continue;
    std::vector<std::string> f;
    std::istringstream r(line);
    for (std::string v; std::getline(r, v, ',');) f.push_back(v);
    const std::string where = path + ":" + std::to_string(row);
    if (f.size() < columns) Fail(where + ": " + std::to_string(f.size()) + " fields, the header has " + std::to_string(columns));
    CaptureRow c;
    c.row = row;
    c.file = f[col["file"]];
    // The number in a column, or nullopt when it is not a finite number.
    auto num = [&](const char* name) -> std::optional<double> {
      const std::string& text = f[col[name]];
      try {
        size_t used = 0;
        const double v = std::stod(text, &used);
        if (std::isfinite(v) && used == text.size()) return v;
      } catch (const std::exception&) {
      }
      if (c.problem.empty()) c.problem = where + ": " + name + " is not a finite number: '" + text + "'";
      return std::nullopt;
    };
    const auto utime = num("utime");
    if (!utime) Fail(c.problem);
    if (!(*utime >= 0 && *utime < 9.2e18)) Fail(where + ": utime " + f[col["utime"]] + " is out of range");
    c.utime = static_cast<int64_t>(*utime);
    const auto n = num("est_north_m"), e = num("est_east_m"), d = num("est_down_m");
    const auto phi = num("est_roll_rad"), theta = num("est_pitch_rad"), psi = num("est_yaw_rad");
    if (n && e && d && phi && theta && psi) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = RotationNBFromEuler({*phi, *theta, *psi});
      T.translation() = Eigen::Vector3d(*n, *e, *d);
      c.T_NB_estimate = T;
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace uav
