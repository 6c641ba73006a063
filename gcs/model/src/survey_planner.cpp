#include "uav/gcs/survey_planner.hpp"

#include <algorithm>
#include <filesystem>

#include "uav/shared/parameters.hpp"

namespace uav::gcs {

SurveyPlanner::SurveyPlanner(const std::string& camera_dir, const GeodeticPoint& origin)
    : origin_(origin), frame_(std::make_unique<LocalNedFrame>(origin)) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(camera_dir, ec))
    if (e.path().extension() == ".camera") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    try {
      cameras_.push_back({f.stem().string(), waypoints::CameraFromParameters(ParameterSet::LoadFile(f.string(), uav::CameraParameterSchema()))});
    } catch (const std::exception&) {
      // A broken camera file is left out of the list; the others still work.
    }
  }
  // Prefer the simulator's survey camera so the planned mission matches the simulated images
  // (not its stereo camera, which also starts with "sim_").
  for (const char* prefix : {"sim_", "sim_downward"})
    for (std::size_t i = 0; i < cameras_.size(); ++i)
      if (cameras_[i].name.rfind(prefix, 0) == 0) {
        std::swap(cameras_[0], cameras_[i]);
        break;
      }
  if (cameras_.empty()) cameras_.push_back({"sim_downward_640x480", {4.8, 3.6, 3.6, 640, 480, true}});
  params_.camera = cameras_[0].spec;
  params_.altitude_m = 20.0;
  params_.turnaround_m = 5.0;
  Replan();
}

void SurveyPlanner::SetOrigin(const GeodeticPoint& origin) {
  ValidateGeodetic(origin);
  if (origin.latitude_deg == origin_.latitude_deg && origin.longitude_deg == origin_.longitude_deg &&
      origin.altitude_m == origin_.altitude_m)
    return;
  origin_ = origin;
  frame_ = std::make_unique<LocalNedFrame>(origin);
  Replan();
}

Eigen::Vector2d SurveyPlanner::ToMap(const GeodeticPoint& g) const {
  GeodeticPoint flat = g;
  flat.altitude_m = origin_.altitude_m;
  return frame_->ToNed(flat).head<2>();
}

GeodeticPoint SurveyPlanner::FromMap(const Eigen::Vector2d& ne) const {
  return frame_->ToGeodetic(Eigen::Vector3d(ne.x(), ne.y(), 0.0));
}

void SurveyPlanner::AddVertex(const Eigen::Vector2d& ne) { InsertVertex(polygon_.size(), ne); }

void SurveyPlanner::InsertVertex(std::size_t before, const Eigen::Vector2d& ne) {
  if (!ne.allFinite() || polygon_.size() >= waypoints::kMaxPolygonVertices) return;
  polygon_.insert(polygon_.begin() + static_cast<long>(std::min(before, polygon_.size())), FromMap(ne));
  Replan();
}

void SurveyPlanner::MoveVertex(std::size_t i, const Eigen::Vector2d& ne) {
  if (i >= polygon_.size() || !ne.allFinite()) return;
  polygon_[i] = FromMap(ne);
  Replan();
}

void SurveyPlanner::DeleteVertex(std::size_t i) {
  if (i >= polygon_.size()) return;
  polygon_.erase(polygon_.begin() + static_cast<long>(i));
  Replan();
}

void SurveyPlanner::Clear() {
  polygon_.clear();
  Replan();
}

int SurveyPlanner::VertexNear(const Eigen::Vector2d& ne, double radius_m) const {
  int best = -1;
  double best_d = radius_m;
  for (std::size_t i = 0; i < polygon_.size(); ++i) {
    const double d = (ToMap(polygon_[i]) - ne).norm();
    if (d <= best_d) best = static_cast<int>(i), best_d = d;
  }
  return best;
}

void SurveyPlanner::SelectCamera(int i) {
  if (i < 0 || i >= static_cast<int>(cameras_.size())) return;
  camera_index_ = i;
  const bool landscape = params_.camera.landscape;
  params_.camera = cameras_[i].spec;
  params_.camera.landscape = landscape;
  Replan();
}

std::vector<Eigen::Vector2d> SurveyPlanner::polygon_map() const {
  std::vector<Eigen::Vector2d> out;
  for (const auto& g : polygon_) out.push_back(ToMap(g));
  return out;
}

void SurveyPlanner::Replan() {
  plan_.reset();
  problem_.clear();
  if (polygon_.size() < 3) {
    problem_ = "draw the area: " + std::to_string(polygon_.size()) + " of at least 3 vertices";
    return;
  }
  try {
    plan_ = waypoints::PlanSurvey(polygon_, origin_, params_);
    problem_ = plan_->overlap_problem;
  } catch (const std::exception& e) {
    problem_ = e.what();
  }
}

std::optional<waypoints::Mission> SurveyPlanner::MakeMission(std::string* error) const {
  if (!plan_ || !problem_.empty()) {
    *error = problem_.empty() ? "no plan" : problem_;
    return std::nullopt;
  }
  try {
    return waypoints::MissionFromSurvey(polygon_, origin_, params_, *plan_);
  } catch (const std::exception& e) {
    *error = e.what();
    return std::nullopt;
  }
}

void SurveyPlanner::SetSurvey(const waypoints::SurveyDefinition& survey, const GeodeticPoint& home) {
  polygon_ = survey.polygon;
  params_ = survey.params;
  camera_index_ = 0;
  for (std::size_t i = 0; i < cameras_.size(); ++i)
    if (cameras_[i].name == survey.camera_name) camera_index_ = static_cast<int>(i);
  origin_ = home;
  frame_ = std::make_unique<LocalNedFrame>(home);
  Replan();
}

}  // namespace uav::gcs
