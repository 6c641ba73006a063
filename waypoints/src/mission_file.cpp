#include "uav/waypoints/mission_file.hpp"

#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "uav/shared/text_file.hpp"

namespace uav::waypoints {
namespace {

using Json = nlohmann::json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kFirmwarePx4 = 12;  // MAV_AUTOPILOT_PX4
constexpr int kVehicleQuadrotor = 2;  // MAV_TYPE_QUADROTOR

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// ---- .plan reading: every access names its JSON path in the error. ----
class PlanReader {
 public:
  explicit PlanReader(std::string origin) : origin_(std::move(origin)) {}

  [[noreturn]] void Fail(const std::string& path, const std::string& what) const {
    throw MissionFileError(origin_ + ": " + path + ": " + what);
  }
  const Json& Field(const Json& obj, const std::string& path, const char* key) const {
    if (!obj.is_object()) Fail(path, "is not a JSON object");
    auto it = obj.find(key);
    if (it == obj.end()) Fail(path, std::string("missing field \"") + key + "\"");
    return *it;
  }
  double Number(const Json& obj, const std::string& path, const char* key) const {
    const Json& v = Field(obj, path, key);
    if (!v.is_number()) Fail(path + "." + key, v.is_null() ? "is null (NaN)" : "is not a number");
    return v.get<double>();
  }
  bool Bool(const Json& obj, const std::string& path, const char* key) const {
    const Json& v = Field(obj, path, key);
    if (!v.is_boolean()) Fail(path + "." + key, "is not true or false");
    return v.get<bool>();
  }
  const Json& Array(const Json& obj, const std::string& path, const char* key) const {
    const Json& v = Field(obj, path, key);
    if (!v.is_array()) Fail(path + "." + key, "is not an array");
    return v;
  }

  MissionItem Item(const Json& j, const std::string& path, const GeodeticPoint& home) const {
    MissionItem it;
    const double command = Number(j, path, "command");
    const double frame = Number(j, path, "frame");
    if (command != std::floor(command)) Fail(path + ".command", "is not an integer");
    if (frame != std::floor(frame)) Fail(path + ".frame", "is not an integer");
    it.command = static_cast<int>(std::clamp(command, -1.0, 65536.0));
    it.frame = static_cast<int>(std::clamp(frame, -1.0, 256.0));
    it.autocontinue = Bool(j, path, "autoContinue");
    const Json& params = Array(j, path, "params");
    if (params.size() != 7) Fail(path + ".params", "has " + std::to_string(params.size()) + " values, not 7");
    static const char* const kNames[7] = {"param1", "param2", "param3", "param4", "latitude", "longitude", "altitude"};
    double v[7];
    for (int k = 0; k < 7; ++k) {
      const std::string where = path + ".params[" + std::to_string(k) + "] (" + kNames[k] + ")";
      if (params[k].is_null()) {
        v[k] = kNaN;  // QGroundControl writes NaN ("unused") as null
      } else if (params[k].is_number()) {
        v[k] = params[k].get<double>();
      } else {
        Fail(where, "is not a number");
      }
    }
    for (int k = 0; k < 4; ++k) it.param[k] = v[k];
    it.latitude_deg = v[4], it.longitude_deg = v[5], it.altitude_m = v[6];
    try {
      ValidateMissionItem(it, home, path);
    } catch (const std::invalid_argument& e) {
      throw MissionFileError(origin_ + ": " + e.what());
    }
    return it;
  }

 private:
  std::string origin_;
};

Json ItemJson(const MissionItem& it, int jump_id) {
  Json params = Json::array();
  for (double p : it.param) params.push_back(std::isnan(p) ? Json(nullptr) : Json(p));
  params.push_back(it.latitude_deg);
  params.push_back(it.longitude_deg);
  params.push_back(it.altitude_m);
  Json j = {{"autoContinue", it.autocontinue}, {"command", it.command}, {"doJumpId", jump_id},
            {"frame", it.frame}, {"params", params}, {"type", "SimpleItem"}};
  if (it.frame != mav_frame::kMission) {
    j["AMSLAltAboveTerrain"] = nullptr;
    j["Altitude"] = it.altitude_m;
    j["AltitudeMode"] = it.frame == mav_frame::kGlobal ? 2 : 1;
  }
  return j;
}

Json LatLonArray(const std::vector<GeodeticPoint>& pts) {
  Json a = Json::array();
  for (const auto& p : pts) a.push_back({p.latitude_deg, p.longitude_deg});
  return a;
}

}  // namespace

namespace {

// QGroundControl's geoFence (polygons and circles) and rallyPoints, appended to the items as
// MAVLink's fence and rally items. Both sections are optional.
void ReadFenceAndRally(const PlanReader& r, const Json& root, Mission* m) {
  auto lat_lon = [&](const Json& v, const std::string& path) {
    if (!v.is_array() || v.size() < 2 || !v[0].is_number() || !v[1].is_number()) r.Fail(path, "is not [latitude, longitude]");
    return std::pair<double, double>(v[0].get<double>(), v[1].get<double>());
  };
  auto add = [&](int command, double param1, double lat, double lon, double alt) {
    MissionItem it;
    it.command = command;
    it.frame = mav_frame::kGlobalRelativeAlt;
    it.param = {param1, 0, 0, 0};
    it.latitude_deg = lat, it.longitude_deg = lon, it.altitude_m = alt;
    if (m->items.size() >= kMaxMissionItems) r.Fail("geoFence", "brings the mission over " + std::to_string(kMaxMissionItems) + " items");
    m->items.push_back(it);
  };
  if (root.contains("geoFence")) {
    const Json& g = root["geoFence"];
    if (g.contains("polygons")) {
      const Json& polys = r.Array(g, "geoFence", "polygons");
      for (std::size_t i = 0; i < polys.size(); ++i) {
        const std::string path = "geoFence.polygons[" + std::to_string(i) + "]";
        const bool inclusion = r.Bool(polys[i], path, "inclusion");
        const Json& pts = r.Array(polys[i], path, "polygon");
        if (pts.size() < 3) r.Fail(path + ".polygon", "has fewer than 3 vertices");
        for (std::size_t k = 0; k < pts.size(); ++k) {
          const auto [lat, lon] = lat_lon(pts[k], path + ".polygon[" + std::to_string(k) + "]");
          add(inclusion ? mav_cmd::kNavFencePolygonVertexInclusion : mav_cmd::kNavFencePolygonVertexExclusion,
              static_cast<double>(pts.size()), lat, lon, 0);
        }
      }
    }
    if (g.contains("circles")) {
      const Json& circles = r.Array(g, "geoFence", "circles");
      for (std::size_t i = 0; i < circles.size(); ++i) {
        const std::string path = "geoFence.circles[" + std::to_string(i) + "]";
        const bool inclusion = r.Bool(circles[i], path, "inclusion");
        const Json& c = r.Field(circles[i], path, "circle");
        const auto [lat, lon] = lat_lon(r.Field(c, path + ".circle", "center"), path + ".circle.center");
        add(inclusion ? mav_cmd::kNavFenceCircleInclusion : mav_cmd::kNavFenceCircleExclusion,
            r.Number(c, path + ".circle", "radius"), lat, lon, 0);
      }
    }
  }
  if (root.contains("rallyPoints")) {
    const Json& pts = r.Array(root["rallyPoints"], "rallyPoints", "points");
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const std::string path = "rallyPoints.points[" + std::to_string(k) + "]";
      const auto [lat, lon] = lat_lon(pts[k], path);
      if (pts[k].size() < 3 || !pts[k][2].is_number()) r.Fail(path, "is not [latitude, longitude, altitude]");
      add(mav_cmd::kNavRallyPoint, 0, lat, lon, pts[k][2].get<double>());
    }
  }
}

// The fence and rally items of `m` as QGroundControl's geoFence and rallyPoints.
std::pair<Json, Json> FenceAndRallyJson(const Mission& m) {
  Json polygons = Json::array(), circles = Json::array(), points = Json::array();
  for (std::size_t i = 0; i < m.items.size(); ++i) {
    const MissionItem& it = m.items[i];
    if (it.command == mav_cmd::kNavFencePolygonVertexInclusion || it.command == mav_cmd::kNavFencePolygonVertexExclusion) {
      const auto n = static_cast<std::size_t>(it.param[0]);  // validated: the run of vertices
      Json poly = Json::array();
      for (std::size_t k = 0; k < n; ++k) poly.push_back({m.items[i + k].latitude_deg, m.items[i + k].longitude_deg});
      polygons.push_back({{"inclusion", it.command == mav_cmd::kNavFencePolygonVertexInclusion}, {"polygon", poly}, {"version", 1}});
      i += n - 1;
    } else if (it.command == mav_cmd::kNavFenceCircleInclusion || it.command == mav_cmd::kNavFenceCircleExclusion) {
      circles.push_back({{"circle", {{"center", {it.latitude_deg, it.longitude_deg}}, {"radius", it.param[0]}}},
                         {"inclusion", it.command == mav_cmd::kNavFenceCircleInclusion},
                         {"version", 1}});
    } else if (IsRallyItem(it.command)) {
      points.push_back({it.latitude_deg, it.longitude_deg, it.altitude_m});
    }
  }
  return {{{"circles", circles}, {"polygons", polygons}, {"version", 2}}, {{"points", points}, {"version", 2}}};
}

}  // namespace

Mission ParsePlan(const std::string& text, const std::string& origin) {
  Json root;
  try {
    root = Json::parse(text);  // the message names line and column
  } catch (const Json::exception& e) {  // a syntax error, or a number out of range ("1e999")
    throw MissionFileError(origin + ": not valid JSON: " + e.what());
  }
  PlanReader r(origin);
  const Json& type = r.Field(root, "(top level)", "fileType");
  if (type != "Plan") r.Fail("fileType", "is not \"Plan\"");
  const Json& mj = r.Field(root, "(top level)", "mission");
  Mission m;
  const Json& home = r.Array(mj, "mission", "plannedHomePosition");
  if (home.size() != 3) r.Fail("mission.plannedHomePosition", "needs [latitude, longitude, altitude]");
  for (int k = 0; k < 3; ++k)
    if (!home[k].is_number()) r.Fail("mission.plannedHomePosition[" + std::to_string(k) + "]", "is not a number");
  m.home = {home[0].get<double>(), home[1].get<double>(), home[2].get<double>()};
  try {
    ValidateGeodetic(m.home);
  } catch (const std::invalid_argument& e) {
    r.Fail("mission.plannedHomePosition", e.what());
  }
  m.cruise_speed_m_s = mj.contains("hoverSpeed") ? r.Number(mj, "mission", "hoverSpeed") : m.cruise_speed_m_s;
  if (!(m.cruise_speed_m_s > 0 && m.cruise_speed_m_s <= 15))
    r.Fail("mission.hoverSpeed", std::to_string(m.cruise_speed_m_s) + " m/s is outside (0, 15]");
  const Json& items = r.Array(mj, "mission", "items");
  if (items.size() > kMaxMissionItems)
    r.Fail("mission.items", "has " + std::to_string(items.size()) + " items, more than " + std::to_string(kMaxMissionItems));
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::string path = "mission.items[" + std::to_string(i) + "]";
    const Json& ij = items[i];
    const Json& t = r.Field(ij, path, "type");
    if (t == "SimpleItem") {
      m.items.push_back(r.Item(ij, path, m.home));
    } else if (t == "ComplexItem") {
      const Json& kind = r.Field(ij, path, "complexItemType");
      if (kind != "survey") r.Fail(path + ".complexItemType", "only \"survey\" is supported, not " + kind.dump());
      const Json& ts = r.Field(ij, path, "TransectStyleComplexItem");
      const std::string tpath = path + ".TransectStyleComplexItem";
      const Json& sub = r.Array(ts, tpath, "Items");
      if (sub.empty()) r.Fail(tpath + ".Items", "is empty");
      if (m.items.size() + sub.size() > kMaxMissionItems)
        r.Fail(tpath + ".Items", "brings the mission over " + std::to_string(kMaxMissionItems) + " items");
      SurveyDefinition def;
      def.first_item = m.items.size();
      for (std::size_t k = 0; k < sub.size(); ++k)
        m.items.push_back(r.Item(sub[k], tpath + ".Items[" + std::to_string(k) + "]", m.home));
      def.item_count = sub.size();
      const Json& poly = r.Array(ij, path, "polygon");
      for (std::size_t k = 0; k < poly.size(); ++k) {
        const std::string vpath = path + ".polygon[" + std::to_string(k) + "]";
        if (!poly[k].is_array() || poly[k].size() < 2 || !poly[k][0].is_number() || !poly[k][1].is_number())
          r.Fail(vpath, "is not [latitude, longitude]");
        def.polygon.push_back({poly[k][0].get<double>(), poly[k][1].get<double>(), 0.0});
      }
      const Json& cc = r.Field(ts, tpath, "CameraCalc");
      const std::string cpath = tpath + ".CameraCalc";
      def.camera_name = cc.value("CameraName", std::string("Custom Camera"));
      SurveyParams& p = def.params;
      p.grid_angle_deg = r.Number(ij, path, "angle");
      p.entry_corner = static_cast<int>(r.Number(ij, path, "entryLocation"));
      p.turnaround_m = r.Number(ts, tpath, "TurnAroundDistance");
      p.crosshatch = ts.contains("Refly90Degrees") && r.Bool(ts, tpath, "Refly90Degrees");
      p.front_overlap = r.Number(cc, cpath, "FrontalOverlap") / 100.0;
      p.side_overlap = r.Number(cc, cpath, "SideOverlap") / 100.0;
      p.speed_m_s = m.cruise_speed_m_s;
      bool have_camera = def.camera_name != "Manual (no camera)";
      if (have_camera) {
        p.camera.sensor_width_mm = r.Number(cc, cpath, "SensorWidth");
        p.camera.sensor_height_mm = r.Number(cc, cpath, "SensorHeight");
        p.camera.focal_length_mm = r.Number(cc, cpath, "FocalLength");
        p.camera.image_width_px = static_cast<int>(r.Number(cc, cpath, "ImageWidth"));
        p.camera.image_height_px = static_cast<int>(r.Number(cc, cpath, "ImageHeight"));
        p.camera.landscape = !cc.contains("Landscape") || r.Bool(cc, cpath, "Landscape");
        const bool by_distance = cc.contains("ValueSetIsDistance") ? r.Bool(cc, cpath, "ValueSetIsDistance")
                                 : cc.contains("FixedValueIsAltitude") ? r.Bool(cc, cpath, "FixedValueIsAltitude")
                                                                       : true;
        if (by_distance) p.altitude_m = r.Number(cc, cpath, "DistanceToSurface");
        else p.gsd_cm_per_px = r.Number(cc, cpath, "ImageDensity");
        // Our own settings; a QGroundControl file triggers by distance.
        if (ij.contains("uav")) {
          const Json& u = ij["uav"];
          p.capture_rate_hz = r.Number(u, path + ".uav", "capture_rate_hz");
          p.trigger_distance_m = r.Number(u, path + ".uav", "trigger_distance_m");
          p.camera_mount_yaw_deg = r.Number(u, path + ".uav", "camera_mount_yaw_deg");
          p.accel_m_s2 = r.Number(u, path + ".uav", "accel_m_s2");
          p.speed_m_s = r.Number(u, path + ".uav", "speed_m_s");
        } else {
          p.trigger_distance_m = r.Number(cc, cpath, "AdjustedFootprintFrontal");
        }
        try {
          ValidatePolygon(PolygonToNed(def.polygon, LocalNedFrame(m.home)));
        } catch (const std::invalid_argument& e) {
          r.Fail(path + ".polygon", e.what());
        }
        try {
          ValidateSurveyParams(p);
        } catch (const std::invalid_argument& e) {
          r.Fail(path, e.what());
        }
        m.surveys.push_back(def);
      }
    } else {
      r.Fail(path + ".type", "must be \"SimpleItem\" or \"ComplexItem\", not " + t.dump());
    }
  }
  ReadFenceAndRally(r, root, &m);
  try {
    ValidateMission(m);
  } catch (const std::invalid_argument& e) {
    throw MissionFileError(origin + ": " + e.what());
  }
  return m;
}

std::string FormatPlan(const Mission& m) {
  ValidateMission(m);
  Json items = Json::array();
  int jump = 1;
  std::size_t next_survey = 0;
  for (std::size_t i = 0; i < m.items.size();) {
    if (next_survey < m.surveys.size() && i == m.surveys[next_survey].first_item) {
      const SurveyDefinition& s = m.surveys[next_survey++];
      const SurveyParams& p = s.params;
      Json sub = Json::array();
      std::vector<GeodeticPoint> visual;
      for (std::size_t k = 0; k < s.item_count; ++k) {
        const MissionItem& it = m.items[s.first_item + k];
        sub.push_back(ItemJson(it, jump++));
        if (it.command == mav_cmd::kNavWaypoint) visual.push_back({it.latitude_deg, it.longitude_deg, 0});
      }
      const double alt = SurveyAltitude(p);
      const Footprint f = FootprintAt(p.camera, alt);
      Json camera = {{"version", 2},
                     {"CameraName", s.camera_name},
                     {"DistanceMode", 1},
                     {"DistanceToSurface", alt},
                     {"ValueSetIsDistance", p.altitude_m > 0},
                     {"ImageDensity", f.gsd_cm_per_px},
                     {"FrontalOverlap", p.front_overlap * 100.0},
                     {"SideOverlap", p.side_overlap * 100.0},
                     {"AdjustedFootprintFrontal", TriggerDistance(f, p.front_overlap)},
                     {"AdjustedFootprintSide", LineSpacing(f, p.side_overlap)},
                     {"SensorWidth", p.camera.sensor_width_mm},
                     {"SensorHeight", p.camera.sensor_height_mm},
                     {"FocalLength", p.camera.focal_length_mm},
                     {"ImageWidth", p.camera.image_width_px},
                     {"ImageHeight", p.camera.image_height_px},
                     {"Landscape", p.camera.landscape},
                     {"MinTriggerInterval", 0}};
      Json transect = {{"version", 2},
                       {"CameraCalc", camera},
                       {"CameraShots", 0},
                       {"CameraTriggerInTurnAround", false},
                       {"HoverAndCapture", false},
                       {"Refly90Degrees", p.crosshatch},
                       {"TurnAroundDistance", p.turnaround_m},
                       {"VisualTransectPoints", LatLonArray(visual)},
                       {"Items", sub}};
      items.push_back({{"type", "ComplexItem"},
                       {"complexItemType", "survey"},
                       {"version", 5},
                       {"angle", p.grid_angle_deg},
                       {"entryLocation", p.entry_corner},
                       {"flyAlternateTransects", false},
                       {"splitConcavePolygons", false},
                       {"polygon", LatLonArray(s.polygon)},
                       {"TransectStyleComplexItem", transect},
                       {"uav",
                        {{"speed_m_s", p.speed_m_s},
                         {"capture_rate_hz", p.capture_rate_hz},
                         {"trigger_distance_m", p.trigger_distance_m},
                         {"camera_mount_yaw_deg", p.camera_mount_yaw_deg},
                         {"accel_m_s2", p.accel_m_s2}}}});
      i += s.item_count;
    } else if (IsFenceItem(m.items[i].command) || IsRallyItem(m.items[i].command)) {
      ++i;  // in geoFence and rallyPoints
    } else {
      items.push_back(ItemJson(m.items[i], jump++));
      ++i;
    }
  }
  const auto [fence, rally] = FenceAndRallyJson(m);
  Json root = {{"fileType", "Plan"},
               {"groundStation", "uav-gcs"},
               {"version", 1},
               {"geoFence", fence},
               {"rallyPoints", rally},
               {"mission",
                {{"version", 2},
                 {"firmwareType", kFirmwarePx4},
                 {"vehicleType", kVehicleQuadrotor},
                 {"globalPlanAltitudeMode", 1},
                 {"cruiseSpeed", m.cruise_speed_m_s},
                 {"hoverSpeed", m.cruise_speed_m_s},
                 {"plannedHomePosition", {m.home.latitude_deg, m.home.longitude_deg, m.home.altitude_m}},
                 {"items", items}}}};
  return root.dump(4) + "\n";
}

Mission ParseWpl(const std::string& text, const std::string& origin) {
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  auto fail = [&](const std::string& what) -> void {
    throw MissionFileError(origin + ":" + std::to_string(line_no) + ": " + what);
  };
  if (!std::getline(in, line)) throw MissionFileError(origin + ": empty file");
  ++line_no;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != "QGC WPL 110") fail("first line must be \"QGC WPL 110\", got \"" + line.substr(0, 40) + "\"");
  Mission m;
  bool have_home = false;
  static const char* const kFields[12] = {"index", "current", "frame", "command", "param1", "param2", "param3",
                                          "param4", "latitude", "longitude", "altitude", "autocontinue"};
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    std::vector<std::string> fields;
    std::size_t pos = 0;
    while (pos <= line.size()) {
      const std::size_t tab = line.find('\t', pos);
      fields.push_back(line.substr(pos, tab == std::string::npos ? std::string::npos : tab - pos));
      if (tab == std::string::npos) break;
      pos = tab + 1;
    }
    if (fields.size() != 12)
      fail("has " + std::to_string(fields.size()) + " tab-separated fields, not 12");
    double v[12];
    for (int k = 0; k < 12; ++k) {
      const std::string& f = fields[k];
      char* end = nullptr;
      v[k] = std::strtod(f.c_str(), &end);
      if (f.empty() || end == f.c_str() || *end != '\0')
        fail("field " + std::to_string(k + 1) + " (" + kFields[k] + ") \"" + f.substr(0, 30) + "\" is not a number");
      if (std::isnan(v[k]) && (k < 4 || k > 7))
        fail("field " + std::to_string(k + 1) + " (" + kFields[k] + ") is NaN");
    }
    const std::size_t expected = have_home ? m.items.size() + 1 : 0;
    if (v[0] != static_cast<double>(expected))
      fail("index " + fields[0] + " out of sequence (expected " + std::to_string(expected) + ")");
    if (m.items.size() >= kMaxMissionItems) fail("more than " + std::to_string(kMaxMissionItems) + " items");
    if (v[11] != 0 && v[11] != 1) fail("field 12 (autocontinue) must be 0 or 1");
    if (!have_home) {
      m.home = {v[8], v[9], v[10]};
      try {
        ValidateGeodetic(m.home);
      } catch (const std::invalid_argument& e) {
        fail(std::string("home (item 0): ") + e.what());
      }
      have_home = true;
      continue;
    }
    MissionItem it;
    if (v[2] != std::floor(v[2]) || v[3] != std::floor(v[3])) fail("frame and command must be integers");
    it.frame = static_cast<int>(std::clamp(v[2], -1.0, 256.0));
    it.command = static_cast<int>(std::clamp(v[3], -1.0, 65536.0));
    for (int k = 0; k < 4; ++k) it.param[k] = v[4 + k];
    it.latitude_deg = v[8], it.longitude_deg = v[9], it.altitude_m = v[10];
    it.autocontinue = v[11] != 0;
    try {
      const std::string name = CommandName(it.command);
      ValidateMissionItem(it, m.home, "item " + fields[0] + " (" + (name.empty() ? "command " + fields[3] : name) + ")");
    } catch (const std::invalid_argument& e) {
      fail(e.what());
    }
    m.items.push_back(it);
  }
  if (!have_home) throw MissionFileError(origin + ": no home line (item 0)");
  try {
    ValidateMission(m);
  } catch (const std::invalid_argument& e) {
    throw MissionFileError(origin + ": " + e.what());
  }
  return m;
}

std::string FormatWpl(const Mission& m) {
  ValidateMission(m);
  std::ostringstream out;
  out << std::setprecision(17) << "QGC WPL 110\n";
  out << "0\t1\t0\t16\t0\t0\t0\t0\t" << m.home.latitude_deg << '\t' << m.home.longitude_deg << '\t'
      << m.home.altitude_m << "\t1\n";
  for (std::size_t i = 0; i < m.items.size(); ++i) {
    const MissionItem& it = m.items[i];
    out << i + 1 << "\t0\t" << it.frame << '\t' << it.command;
    for (double p : it.param) out << '\t' << p;
    out << '\t' << it.latitude_deg << '\t' << it.longitude_deg << '\t' << it.altitude_m << '\t'
        << (it.autocontinue ? 1 : 0) << '\n';
  }
  return out.str();
}

Mission ReadMissionFile(const std::string& path) {
  std::string text;
  try {
    text = ReadTextFile(path, "mission file");
  } catch (const std::runtime_error& e) {
    throw MissionFileError(e.what());
  }
  if (EndsWith(path, ".plan")) return ParsePlan(text, path);
  if (EndsWith(path, ".waypoints") || EndsWith(path, ".txt")) return ParseWpl(text, path);
  throw MissionFileError(path + ": unknown mission file type (use .plan, .waypoints or .txt)");
}

void WriteMissionFile(const std::string& path, const Mission& m) {
  std::string text;
  if (EndsWith(path, ".plan")) text = FormatPlan(m);
  else if (EndsWith(path, ".waypoints") || EndsWith(path, ".txt")) text = FormatWpl(m);
  else throw MissionFileError(path + ": unknown mission file type (use .plan, .waypoints or .txt)");
  WriteFileAtomically(path, text);
}

}  // namespace uav::waypoints
