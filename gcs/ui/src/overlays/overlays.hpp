#pragma once
// What the map and video panels draw over their picture, one file per overlay: each report type's
// drawing lives beside its kind (power_lines_overlay.cpp draws wires on the map and on the
// video), so a new report adds a file here rather than lines to a panel. Internal to the panels.
#include <imgui.h>

#include "uav/gcs/gcs_model.hpp"

namespace uav::gcs {

// The map: local NED metres, north up, around a centre.
struct MapCanvas {
  ImDrawList* dl = nullptr;
  ImVec2 centre;                 // [px] screen position of (centre_n, centre_e)
  double centre_n = 0, centre_e = 0, px_per_m = 1;
  ImVec2 ToScreen(double n, double e) const {
    return ImVec2(centre.x + static_cast<float>((e - centre_e) * px_per_m),
                  centre.y - static_cast<float>((n - centre_n) * px_per_m));
  }
};

// A camera picture: normalised image coordinates (0..1, x right, y down) over a screen rectangle.
struct ImageCanvas {
  ImDrawList* dl = nullptr;
  ImVec2 p0, size;  // [px] top-left corner and size on screen
  ImVec2 ToScreen(double nx, double ny) const {
    return ImVec2(p0.x + static_cast<float>(nx) * size.x, p0.y + static_cast<float>(ny) * size.y);
  }
};

// The survey being planned: coverage of each capture leg (until the real map arrives), path, polygon.
void DrawSurveyOnMap(GcsModel& model, const MapCanvas& m);
// The mission being edited (the mission editor's items).
void DrawMissionPlanOnMap(GcsModel& model, const MapCanvas& m);
// The accepted mission, home, the geofence, the trails and the vehicle.
void DrawVehicleOnMap(GcsModel& model, const VehicleModel* v, const MapCanvas& m);
// Power lines (thesis 3.6).
void DrawPowerLinesOnMap(const GcsModel& model, const VehicleModel& v, const MapCanvas& m, double now);
void DrawPowerLinesOnImage(const GcsModel& model, const VehicleModel& v, const VideoFeed& feed, const ImageCanvas& c,
                           double now);
// Stereo obstacles (thesis 3.5).
void DrawObstaclesOnMap(const GcsModel& model, const VehicleModel& v, const MapCanvas& m, double now);
void DrawObstaclesOnImage(const GcsModel& model, const VehicleModel& v, const VideoFeed& feed, const ImageCanvas& c,
                          double now);
// Obstacle avoidance (thesis 7.2): the vehicle's map, its path and the committed part of it.
const AvoidanceReport* FreshAvoidance(const VehicleModel& v, double now);  // nullptr: none or stale
ImU32 AvoidanceHeightColour(double up_m, int alpha);
void DrawAvoidanceOnMap(const VehicleModel& v, const MapCanvas& m, double now);  // with its legend
// The avoidance map's legend (cell heights, path, committed part, goal) with its top left at `at`;
// returns its size.
ImVec2 DrawAvoidanceLegend(ImDrawList* dl, ImVec2 at);
// Depth from motion (thesis 3.4).
void DrawDepthGridOnImage(const GcsModel& model, const VehicleModel& v, const VideoFeed& feed, const ImageCanvas& c,
                          double now);
// Active stereo's laser dots and height (thesis ch. 4).
void DrawActiveStereoOnImage(const GcsModel& model, const VehicleModel& v, const VideoFeed& feed,
                             const ImageCanvas& c, double now);
// The tracker's box, window and state (thesis 3.7), or the selection still unanswered.
void DrawTrackOnImage(const VehicleModel& v, const VideoFeed& feed, const ImageCanvas& c, double now);

}  // namespace uav::gcs
