// Obstacle view: what the selected vehicle's stereo pair sees (thesis 3.5), from above (north
// up, centred on the vehicle) and from the side (distance ahead along the heading against
// height), the decimated point cloud as dots coloured by height and each obstacle's cylinder
// with its safety radius, the avoidance map's occupied cells (height-coloured) with the planned
// path and its committed part; the count, nearest distance and range gate underneath.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <imgui.h>

#include "overlays/overlays.hpp"
#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {
namespace {

ImU32 HeightColour(double up_m) {
  // 0 m (ground) dark blue .. 4 m and above yellow.
  const float t = static_cast<float>(std::clamp(up_m / 4.0, 0.0, 1.0));
  return IM_COL32(static_cast<int>(40 + 215 * t), static_cast<int>(60 + 180 * t), static_cast<int>(200 - 160 * t), 200);
}

}  // namespace

void DrawObstacleViewPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Obstacles");
  const VehicleModel* v = model.selected();
  const Obstacles* obstacles = v ? v->reports.Fresh<Obstacles>(ctx.now, model.obstacles().params().stale_after_s) : nullptr;
  const PointCloud* cloud = v ? v->reports.Fresh<PointCloud>(ctx.now, model.obstacles().params().cloud_stale_after_s) : nullptr;
  const AvoidanceReport* avoid = v ? FreshAvoidance(*v, ctx.now) : nullptr;
  if (!v || !v->state || (!obstacles && !cloud && !avoid)) {
    ImGui::TextDisabled(v && v->stereo_unhealthy ? "stereo unavailable" : "no stereo obstacle reports");
    ImGui::End();
    return;
  }
  if (obstacles && !obstacles->healthy) ImGui::TextColored(ImVec4(1, 0.4f, 0.3f, 1), "stereo unhealthy: %s", obstacles->reason.c_str());
  const Eigen::Vector3d p_N = v->state->p_N;
  const double heading = v->state->euler.psi;
  const double reach = std::max(5.0, obstacles ? obstacles->range_gate_m + 2.0 : 10.0);  // [m] shown ahead
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const float w = avail.x, h_top = std::max(60.0f, avail.y * 0.55f), h_side = std::max(40.0f, avail.y - h_top - 40.0f);
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImU32 frame = IM_COL32(90, 90, 90, 255), cyl = IM_COL32(200, 80, 255, 230), margin = IM_COL32(200, 80, 255, 120);

  // From above: north up, the vehicle in the lower middle, `reach` metres to the top edge.
  const ImVec2 o = ImGui::GetCursorScreenPos();
  const float s_top = (h_top - 10) / static_cast<float>(reach);
  const ImVec2 me(o.x + w * 0.5f, o.y + h_top - 10);
  auto top = [&](double n, double e) {
    return ImVec2(me.x + static_cast<float>((e - p_N.y()) * s_top), me.y - static_cast<float>((n - p_N.x()) * s_top));
  };
  dl->AddRect(o, ImVec2(o.x + w, o.y + h_top), frame);
  dl->PushClipRect(o, ImVec2(o.x + w, o.y + h_top), true);
  const ImU32 path_colour = IM_COL32(120, 220, 255, 220), committed_colour = IM_COL32(60, 255, 120, 255);
  if (avoid) {
    const float half = std::max(1.0f, static_cast<float>(0.5 * avoid->cell_m * s_top));
    for (const Eigen::Vector3f& q : avoid->occupied_N) {
      if (-q.z() < 0.5f) continue;  // the ground
      const ImVec2 a = top(q.x(), q.y());
      dl->AddRectFilled(ImVec2(a.x - half, a.y - half), ImVec2(a.x + half, a.y + half), AvoidanceHeightColour(-q.z(), 110));
    }
    auto line = [&](const std::vector<Eigen::Vector3d>& p, ImU32 colour, float width) {
      for (std::size_t i = 0; i + 1 < p.size(); ++i)
        dl->AddLine(top(p[i].x(), p[i].y()), top(p[i + 1].x(), p[i + 1].y()), colour, width);
    };
    line(avoid->path_N, path_colour, 1.5f);
    line(avoid->Committed(), committed_colour, 3.0f);
  }
  if (cloud)
    for (const Eigen::Vector3f& q : cloud->p_N) {
      const ImVec2 a = top(q.x(), q.y());
      dl->AddRectFilled(a, ImVec2(a.x + 2, a.y + 2), HeightColour(-q.z()));
    }
  if (obstacles)
    for (const Obstacle& b : obstacles->obstacles) {
      const ImVec2 c = top(b.p_NE.x(), b.p_NE.y());
      dl->AddCircle(c, static_cast<float>(b.radius_m * s_top), cyl, 32, 2.0f);
      dl->AddCircle(c, static_cast<float>(b.safety_radius_m * s_top), margin, 32, 1.0f);
    }
  // The vehicle and its field of view direction.
  const ImVec2 nose(me.x + 10 * static_cast<float>(std::sin(heading)), me.y - 10 * static_cast<float>(std::cos(heading)));
  dl->AddTriangleFilled(nose, ImVec2(me.x - 5, me.y + 4), ImVec2(me.x + 5, me.y + 4), IM_COL32(255, 255, 255, 255));
  dl->PopClipRect();
  dl->AddText(ImVec2(o.x + 4, o.y + 2), frame, "from above, north up");
  ImGui::Dummy(ImVec2(w, h_top + 4));

  // From the side: distance ahead along the heading (right) against height above home (up).
  const ImVec2 o2 = ImGui::GetCursorScreenPos();
  const double height_span = 8.0;
  const float sx = (w - 10) / static_cast<float>(reach), sy = h_side / static_cast<float>(height_span);
  const Eigen::Vector2d ahead(std::cos(heading), std::sin(heading));
  auto side = [&](double n, double e, double down) {
    const double x = (Eigen::Vector2d(n, e) - p_N.head<2>()).dot(ahead);
    return ImVec2(o2.x + 5 + static_cast<float>(x * sx), o2.y + h_side - static_cast<float>(-down * sy));
  };
  dl->AddRect(o2, ImVec2(o2.x + w, o2.y + h_side), frame);
  dl->PushClipRect(o2, ImVec2(o2.x + w, o2.y + h_side), true);
  if (avoid) {
    // The cells within 2 m either side of the heading line: what stands in the way ahead.
    const float half = std::max(1.0f, static_cast<float>(0.5 * avoid->cell_m * sx));
    const Eigen::Vector2d left(-ahead.y(), ahead.x());
    for (const Eigen::Vector3f& q : avoid->occupied_N) {
      if (std::abs((q.head<2>().cast<double>() - p_N.head<2>()).dot(left)) > 2.0) continue;
      const ImVec2 a = side(q.x(), q.y(), q.z());
      dl->AddRectFilled(ImVec2(a.x - half, a.y - half), ImVec2(a.x + half, a.y + half), AvoidanceHeightColour(-q.z(), 110));
    }
    const std::vector<Eigen::Vector3d> committed = avoid->Committed();
    for (std::size_t i = 0; i + 1 < committed.size(); ++i)
      dl->AddLine(side(committed[i].x(), committed[i].y(), committed[i].z()),
                  side(committed[i + 1].x(), committed[i + 1].y(), committed[i + 1].z()), committed_colour, 3.0f);
  }
  if (cloud)
    for (const Eigen::Vector3f& q : cloud->p_N) {
      const ImVec2 a = side(q.x(), q.y(), q.z());
      dl->AddRectFilled(a, ImVec2(a.x + 2, a.y + 2), HeightColour(-q.z()));
    }
  if (obstacles)
    for (const Obstacle& b : obstacles->obstacles) {
      const double x = (b.p_NE - p_N.head<2>()).dot(ahead);
      const ImVec2 a(o2.x + 5 + static_cast<float>((x - b.radius_m) * sx), side(0, 0, b.top_down_m).y);
      const ImVec2 c(o2.x + 5 + static_cast<float>((x + b.radius_m) * sx), side(0, 0, b.bottom_down_m).y);
      dl->AddRect(a, c, cyl, 0, 0, 2.0f);
    }
  const ImVec2 vehicle = side(p_N.x(), p_N.y(), p_N.z());
  dl->AddCircleFilled(vehicle, 4, IM_COL32(255, 255, 255, 255));
  dl->PopClipRect();
  dl->AddText(ImVec2(o2.x + 4, o2.y + 2), frame, "from the side, ahead along the heading");
  ImGui::Dummy(ImVec2(w, h_side + 4));
  if (obstacles && obstacles->healthy) {
    char nearest[32] = "-";
    if (obstacles->nearest_m >= 0) std::snprintf(nearest, sizeof nearest, "%.1f m", obstacles->nearest_m);
    ImGui::Text("%zu obstacles, nearest %s, range gate %.1f m (depth error limit)", obstacles->obstacles.size(), nearest,
                obstacles->range_gate_m);
  }
  if (avoid) {
    ImGui::Text("avoidance map: %zu occupied cells around, %lld nodes; path %.1f m, %.1f m of it seen free", avoid->occupied_N.size(),
                static_cast<long long>(avoid->map_cells), avoid->PathLength(), avoid->seen_free_m);
    ImGui::Dummy(DrawAvoidanceLegend(dl, ImGui::GetCursorScreenPos()));
  }
  ImGui::End();
}

}  // namespace uav::gcs
