#pragma once
// The survey planner behind the map and survey panels: the area polygon (latitude/longitude, so
// it does not move when the map origin does), the survey parameters, and the plan, recomputed
// on every edit. The mission editor (mission_editor.hpp) places it among other items. No ImGui here.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "uav/shared/geodesy.hpp"
#include "uav/waypoints/mission.hpp"

namespace uav::gcs {

struct CameraChoice {
  std::string name;  // file stem, e.g. "sim_downward_640x480"
  waypoints::CameraSpec spec;
};

class SurveyPlanner {
 public:
  // Cameras from `camera_dir` (*.camera); the first is selected. `origin` is the map origin and
  // the mission's home until SetOrigin moves it.
  SurveyPlanner(const std::string& camera_dir, const GeodeticPoint& origin);

  void SetOrigin(const GeodeticPoint& origin);
  const GeodeticPoint& origin() const { return origin_; }
  Eigen::Vector2d ToMap(const GeodeticPoint& g) const;  // north, east [m] from the origin
  GeodeticPoint FromMap(const Eigen::Vector2d& ne) const;

  // ---- Editing (map coordinates).
  void AddVertex(const Eigen::Vector2d& ne);
  void InsertVertex(std::size_t before, const Eigen::Vector2d& ne);
  void MoveVertex(std::size_t i, const Eigen::Vector2d& ne);
  void DeleteVertex(std::size_t i);
  void Clear();
  // Index of the vertex within radius_m of `ne`, or -1.
  int VertexNear(const Eigen::Vector2d& ne, double radius_m) const;

  // ---- Parameters: edit params() then call ParamsChanged().
  waypoints::SurveyParams& params() { return params_; }
  const waypoints::SurveyParams& params() const { return params_; }
  void ParamsChanged() { Replan(); }
  const std::vector<CameraChoice>& cameras() const { return cameras_; }
  int camera_index() const { return camera_index_; }
  void SelectCamera(int i);

  // ---- Results.
  const std::vector<GeodeticPoint>& polygon() const { return polygon_; }
  std::vector<Eigen::Vector2d> polygon_map() const;
  const std::optional<waypoints::SurveyPlan>& plan() const { return plan_; }
  // Why there is no plan (too few vertices, invalid polygon or parameters), or the overlap
  // problem of a plan that must not be flown; "" when the plan is good.
  const std::string& problem() const { return problem_; }
  // The mission to upload or export; nullopt and *error when there is none.
  std::optional<waypoints::Mission> MakeMission(std::string* error) const;

  // Takes over a survey of a loaded mission (its polygon, parameters and camera by name), with
  // `home` as the origin.
  void SetSurvey(const waypoints::SurveyDefinition& survey, const GeodeticPoint& home);


 private:
  void Replan();

  std::vector<CameraChoice> cameras_;
  int camera_index_ = 0;
  GeodeticPoint origin_;
  std::unique_ptr<LocalNedFrame> frame_;  // at origin_: the map draws every vertex each frame
  std::vector<GeodeticPoint> polygon_;
  waypoints::SurveyParams params_;
  std::optional<waypoints::SurveyPlan> plan_;
  std::string problem_;
};

}  // namespace uav::gcs
