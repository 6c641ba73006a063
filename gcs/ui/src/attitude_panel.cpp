// Attitude indicator (a primary flight display): the artificial horizon rolled and pitched with
// the vehicle and its pitch ladder, the roll scale, the speed (the pitot's airspeed, else the
// ground speed), the altitude and the climb rate beside it, the heading below. A window of its
// own, opened from the status bar. For U-Lion the nose is x_B, along the fuselage toward the
// rotor: it stands 80-90 degrees up in hover and near the horizon on the wing, where the indicator
// reads as a fixed wing's.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <imgui.h>

#include "uav/gcs/gcs_ui.hpp"
#include "uav/shared/frames.hpp"

namespace uav::gcs {

HorizonLine AttitudeHorizon(double roll_rad, double pitch_rad, const Eigen::Vector2d& centre_px, double px_per_rad,
                            double half_length_px) {
  // Screen axes: x right, y down. Banked right, the horizon turns the other way (its right end
  // rises); nose up, it moves down along the wings' normal.
  const Eigen::Vector2d along(std::cos(roll_rad), -std::sin(roll_rad));
  const Eigen::Vector2d down(std::sin(roll_rad), std::cos(roll_rad));
  const Eigen::Vector2d mid = centre_px + down * pitch_rad * px_per_rad;
  return {mid - along * half_length_px, mid + along * half_length_px, down};
}

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kPitchSpanDeg = 25.0;  // half the ball's height shows this much pitch

ImVec2 V(const Eigen::Vector2d& p) { return ImVec2(static_cast<float>(p.x()), static_cast<float>(p.y())); }

void DrawHorizon(ImDrawList* dl, const VehicleState& s, const Eigen::Vector2d& c, double radius) {
  const double px_per_rad = radius / (kPitchSpanDeg * kDeg);
  const double big = 4 * radius;
  const HorizonLine h = AttitudeHorizon(s.euler.phi, s.euler.theta, c, px_per_rad, big);
  const Eigen::Vector2d up = -h.down_px * big;
  // Ground first (the whole ball), then the sky's half-plane over it.
  dl->AddRectFilled(V(c - Eigen::Vector2d(radius, radius)), V(c + Eigen::Vector2d(radius, radius)), IM_COL32(134, 88, 45, 255));
  dl->AddQuadFilled(V(h.left_px), V(h.right_px), V(h.right_px + up), V(h.left_px + up), IM_COL32(60, 130, 210, 255));
  dl->AddLine(V(h.left_px), V(h.right_px), IM_COL32_WHITE, 2.0f);
  // The pitch ladder every 10 degrees (5-degree ticks shorter), labelled.
  const Eigen::Vector2d along = (h.right_px - h.left_px).normalized();
  const int nose = static_cast<int>(std::lround(s.euler.theta / kDeg));
  for (int k = (nose / 5 - 6) * 5; k <= (nose / 5 + 6) * 5; k += 5) {
    if (k == 0 || k < -90 || k > 90) continue;
    const Eigen::Vector2d mid = c + h.down_px * (s.euler.theta - k * kDeg) * px_per_rad;
    if ((mid - c).norm() > 0.85 * radius) continue;
    const double half = k % 10 == 0 ? 0.28 * radius : 0.14 * radius;
    dl->AddLine(V(mid - along * half), V(mid + along * half), IM_COL32_WHITE, 1.5f);
    if (k % 10 == 0) {
      char text[8];
      std::snprintf(text, sizeof text, "%d", k);
      dl->AddText(V(mid + along * (half + 4) - Eigen::Vector2d(0, 7)), IM_COL32_WHITE, text);
    }
  }
  // The roll scale over the top: ticks at 10, 20, 30, 45 and 60 degrees, the pointer at the bank.
  for (int a : {-60, -45, -30, -20, -10, 0, 10, 20, 30, 45, 60}) {
    const double t = a * kDeg;
    const Eigen::Vector2d dir(std::sin(t), -std::cos(t));
    const double inner = a % 30 == 0 ? 0.86 : 0.91;
    dl->AddLine(V(c + dir * inner * radius), V(c + dir * 0.97 * radius), IM_COL32_WHITE, 1.5f);
  }
  const Eigen::Vector2d pointer(std::sin(-s.euler.phi), -std::cos(-s.euler.phi));
  const Eigen::Vector2d side(pointer.y(), -pointer.x());
  const Eigen::Vector2d tip = c + pointer * 0.85 * radius;
  dl->AddTriangleFilled(V(tip), V(tip - pointer * 12 + side * 7), V(tip - pointer * 12 - side * 7), IM_COL32(255, 220, 0, 255));
  // The aircraft, fixed: wings and the centre dot.
  const ImU32 yellow = IM_COL32(255, 220, 0, 255);
  const float w = static_cast<float>(0.45 * radius), x = static_cast<float>(c.x()), y = static_cast<float>(c.y());
  dl->AddLine(ImVec2(x - w, y), ImVec2(x - 0.35f * w, y), yellow, 4.0f);
  dl->AddLine(ImVec2(x + 0.35f * w, y), ImVec2(x + w, y), yellow, 4.0f);
  dl->AddLine(ImVec2(x - 0.35f * w, y), ImVec2(x - 0.18f * w, y + 0.15f * w), yellow, 4.0f);
  dl->AddLine(ImVec2(x + 0.35f * w, y), ImVec2(x + 0.18f * w, y + 0.15f * w), yellow, 4.0f);
  dl->AddCircleFilled(ImVec2(x, y), 3.5f, yellow);
}

}  // namespace

void DrawAttitudePanel(GcsModel& model, UiContext& ctx) {
  UiState& st = ctx.state;
  if (!st.show_attitude) return;
  // Over the plots' right half: the map and the command bar stay in view.
  PlaceWindow("Attitude");
  if (!ImGui::Begin("Attitude", &st.show_attitude)) {
    ImGui::End();
    return;
  }
  const VehicleModel* v = model.selected();
  if (!v || !v->state) {
    ImGui::TextDisabled(v ? "no state from %s yet" : "no vehicle selected", model.selected_id().c_str());
    ImGui::End();
    return;
  }
  const VehicleState& s = *v->state;
  const bool pitot = s.airspeed_m_s >= 0;
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const float tape = 70.0f, text_h = ImGui::GetTextLineHeightWithSpacing();
  const float size = std::max(60.0f, std::min(avail.x - 2 * tape, avail.y - 2 * text_h));
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("##attitude", ImVec2(avail.x, size));
  RegisterLastItem(ctx, "attitude:horizon");
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const Eigen::Vector2d c(origin.x + avail.x / 2, origin.y + size / 2);
  const double radius = size / 2;
  dl->PushClipRect(V(c - Eigen::Vector2d(radius, radius)), V(c + Eigen::Vector2d(radius, radius)), true);
  DrawHorizon(dl, s, c, radius);
  dl->PopClipRect();
  // Speed left, altitude and climb right, as on a fixed wing's display.
  char text[48];
  const double climb = -(RotationNBFromEuler(s.euler) * s.v_B).z();
  std::snprintf(text, sizeof text, "%s\n%5.1f m/s", pitot ? "AS" : "GS", pitot ? s.airspeed_m_s : s.ground_speed());
  dl->AddText(ImVec2(origin.x + 4, static_cast<float>(c.y() - text_h)), IM_COL32_WHITE, text);
  std::snprintf(text, sizeof text, "ALT\n%6.1f m\n%+5.1f m/s", s.altitude(), climb);
  dl->AddText(ImVec2(static_cast<float>(c.x() + radius + 6), static_cast<float>(c.y() - text_h)), IM_COL32_WHITE, text);
  const double heading = std::fmod(s.euler.psi / kDeg + 360.0, 360.0);
  ImGui::Text("HDG %03.0f   roll %+.0f   pitch %+.0f", heading, s.euler.phi / kDeg, s.euler.theta / kDeg);
  if (s.vehicle_type == VehicleType::kTailSitter)
    ImGui::Text("%s   AOA %.0f deg", std::string(Name(s.vtol_mode)).c_str(), s.alpha_rad / kDeg);
  ImGui::End();
}

}  // namespace uav::gcs
