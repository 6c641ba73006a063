// Two lines across the top (they fit 1600 px). The first: whether this GCS signs what it sends
// (red when not), every vehicle's link quality (heartbeat age, message rate, messages lost to
// sequence gaps) and signing state (red when it executes unsigned messages, with the count it
// refused), the selected vehicle's task, arming, flight mode, altitude and battery. The second:
// its ground speed, heading, GPS fix and satellites, distance to home, failsafe, a power-line
// warning, stereo obstacles and obstacle avoidance's state.
#include <algorithm>
#include <cmath>
#include <cctype>
#include <string>

#include <imgui.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {

namespace {

// One vehicle's link: up or lost, heartbeat age, rate, losses, signing, and a slow simulator.
void DrawVehicleLink(const GcsModel& model, UiContext& ctx, const std::string& id, const VehicleModel& veh) {
  const ImVec4 red(1, 0.3f, 0.3f, 1), green(0.4f, 0.9f, 0.4f, 1), amber(1, 0.7f, 0.2f, 1);
  const bool up = veh.LinkUp(ctx.now, model.telemetry_params());
  const bool sel = id == model.selected_id();
  ImGui::TextColored(up ? ImVec4(0.4f, 0.9f, 0.4f, 1) : ImVec4(1, 0.3f, 0.3f, 1), "%s%s %s %.1fs %.0f/s %lld lost",
                     sel ? ">" : "", id.c_str(), up ? "UP" : "LOST", std::min(veh.HeartbeatAge(ctx.now), 99.9),
                     veh.MessageRate(ctx.now), static_cast<long long>(veh.sequence_gaps));
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("%s: heartbeat %.1f s ago, %.0f messages/s, %lld messages lost (sequence gaps)", id.c_str(),
                      veh.HeartbeatAge(ctx.now), veh.MessageRate(ctx.now), static_cast<long long>(veh.sequence_gaps));
  if (veh.heartbeat) {
    ImGui::SameLine();
    const bool signing = veh.heartbeat->signing;
    ImGui::TextColored(signing ? green : red, signing ? "signed" : "UNSIGNED");
    if (veh.heartbeat->signature_rejections > 0) {
      ImGui::SameLine();
      ImGui::TextColored(amber, "%lld refused", static_cast<long long>(veh.heartbeat->signature_rejections));
    }
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("%s %s; %lld messages refused by its signature check since it started (the reasons are in "
                        "the messages)",
                        id.c_str(),
                        signing ? "executes only messages signed with its key"
                                : "was started with --insecure: it executes unsigned messages from anyone",
                        static_cast<long long>(veh.heartbeat->signature_rejections));
    if (veh.heartbeat->SimSlow()) {  // the simulator, not the link, is slow
      ImGui::SameLine();
      ImGui::TextColored(amber, "SIM %.2fx", veh.heartbeat->sim_rate);
      RegisterLastItem(ctx, "status:sim:" + id);
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("%s's simulator runs at %.2fx where %.3gx was asked: its clock is slow, its link is judged on "
                          "its clock (heartbeat %.1f s old in simulated time)",
                          id.c_str(), veh.heartbeat->sim_rate, veh.heartbeat->sim_rate_asked,
                          veh.HeartbeatAgeOnVehicleClock(ctx.now));
    }
  }
  ImGui::SameLine();
  ImGui::TextDisabled("|");
  ImGui::SameLine();
}

// Ground speed, heading, the GPS fix (amber without a 3-D fix) and the distance to home.
void DrawGlance(const VehicleState& s) {
  // The second line starts here.
  const double heading_deg = std::fmod(std::round(s.heading() * 180.0 / M_PI), 360.0);  // 359.7 reads 000
  ImGui::Text("GS %.1f m/s | HDG %03.0f |", s.ground_speed(), heading_deg);
  ImGui::SameLine();
  const char* fix = s.gps_fix >= 3 ? "3D" : s.gps_fix == 2 ? "2D" : "no fix";
  if (s.gps_fix >= 3) ImGui::Text("GPS %s %d sats", fix, s.gps_satellites);
  else ImGui::TextColored(ImVec4(1, 0.7f, 0.2f, 1), "GPS %s %d sats", fix, s.gps_satellites);
  ImGui::SameLine();
  ImGui::Text("| HOME %.0f m", s.home_distance());
  if (s.vehicle_type == VehicleType::kTailSitter) {
    // U-Lion: its mode (a transition with its progress, in amber), the pitot's airspeed and alpha.
    const bool transitioning = s.vtol_mode == VtolMode::kTransitionToWing || s.vtol_mode == VtolMode::kTransitionToHover;
    std::string mode = Spoken(Name(s.vtol_mode));
    for (char& c : mode) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    ImGui::SameLine();
    if (transitioning)
      ImGui::TextColored(ImVec4(1, 0.75f, 0.2f, 1), "| %s %.0f %%", mode.c_str(), 100.0 * s.transition_progress);
    else
      ImGui::Text("| %s", mode.c_str());
    ImGui::SameLine();
    ImGui::Text("| AS %.1f m/s | AOA %.0f", s.airspeed_m_s, s.alpha_rad * 180.0 / M_PI);
  }
}

// The selected vehicle's perception warnings: a near wire, obstacles or a stereo channel down,
// and what obstacle avoidance is doing.
void DrawPerceptionWarnings(UiContext& ctx, const VehicleModel* v) {
  // A power line nearer than the warning distance, in red (the messages say when it started).
  const std::optional<PowerLines>& lines = v->reports.Get<PowerLines>().newest;
  if (v->wire_warning && lines) {
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "| WIRE %.1f m", lines->nearest_m);
  }
  // Stereo obstacles from telemetry (count, nearest surface), and a stereo channel that is down.
  if (v->stereo_unhealthy) {
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "| STEREO DOWN");
  } else if (v->state && v->state->obstacle_count > 0) {
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(0.85f, 0.5f, 1, 1), "| OBS %d, %.1f m", v->state->obstacle_count, v->state->nearest_obstacle_m);
  }
  // Obstacle avoidance while a task travels: avoiding in amber, blocked, no path or no data in
  // red (the messages say why).
  if (v->state && v->state->avoid_state != AvoidState::kOff) {
    const AvoidState a = v->state->avoid_state;
    std::string name(Name(a));
    for (char& c : name) c = c == '_' ? ' ' : static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    const bool bad = a == AvoidState::kBlocked || a == AvoidState::kNoPath || a == AvoidState::kNoData;
    const ImVec4 colour = bad ? ImVec4(1, 0.3f, 0.3f, 1) : a == AvoidState::kAvoiding ? ImVec4(1, 0.75f, 0.2f, 1) : ImVec4(0.5f, 0.85f, 0.5f, 1);
    ImGui::SameLine();
    ImGui::TextColored(colour, "| AVOID %s, %.1f m/s", name.c_str(), v->state->avoid_speed_limit_m_s);
    RegisterLastItem(ctx, "status:avoid:" + v->id);
  }
}

}  // namespace

void DrawStatusBarPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Status", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings);
  const ImVec4 red(1, 0.3f, 0.3f, 1);
  // The Parameters window of the selected vehicle, where it is always in reach.
  if (model.selected()) {
    if (ImGui::SmallButton("Parameters")) ctx.state.show_parameters = !ctx.state.show_parameters;
    RegisterLastItem(ctx, "status:params");
    ImGui::SameLine();
    if (ImGui::SmallButton(model.sticks().enabled() ? "STICKS ON" : "Sticks")) ctx.state.show_sticks = !ctx.state.show_sticks;
    RegisterLastItem(ctx, "status:sticks");
    ImGui::SameLine();
    if (ImGui::SmallButton("Attitude")) ctx.state.show_attitude = !ctx.state.show_attitude;
    RegisterLastItem(ctx, "status:attitude");
    ImGui::SameLine();
  }
  if (model.signing_key_id().empty() && !model.replay()) {
    ImGui::TextColored(red, "INSECURE");
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("started with --insecure: commands go out unsigned; start with --key FILE (uav-keygen)");
    ImGui::SameLine();
    ImGui::TextDisabled("|");
    ImGui::SameLine();
  }
  if (model.vehicles().empty()) {
    ImGui::Text("GCS %s  |  no vehicle on the bus", model.gcs_name().c_str());
    ImGui::End();
    return;
  }
  for (const auto& [id, veh] : model.vehicles()) DrawVehicleLink(model, ctx, id, veh);
  const VehicleModel* v = model.selected();
  if (!v->state) {
    ImGui::Text("%s: task %s | %s | no state yet", v->id.c_str(), v->task ? std::string(Name(*v->task)).c_str() : "unknown",
                v->armed ? "ARMED" : "disarmed");
  } else {
    const VehicleState& s = *v->state;
    ImGui::Text("%s: task %s | %s | mode %s | alt %.1f m | battery %.2f V (%.0f %%)", v->id.c_str(),
                std::string(Name(s.task)).c_str(), s.armed ? "ARMED" : "disarmed",
                std::string(Name(s.flight_mode)).c_str(), s.altitude(), s.battery_voltage_v,
                100.0 * s.battery_remaining);
    DrawGlance(s);
    // The vehicle's failsafe in red, so it cannot be missed (the reason is in the messages).
    if (s.failsafe != FailsafeAction::kNone) {
      std::string name(Name(s.failsafe));
      for (char& c : name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      ImGui::SameLine();
      ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "| FAILSAFE %s%s", name.c_str(),
                         s.failsafe == FailsafeAction::kManual ? " (RC switch)" : "");
      if (ImGui::IsItemHovered()) {  // the whole story on hover: the vehicle's newest failsafe message
        const auto& lines = model.log().lines();
        for (auto it = lines.rbegin(); it != lines.rend(); ++it) {
          if (it->vehicle_id != v->id || it->text.find("failsafe") == std::string::npos) continue;
          ImGui::BeginTooltip();
          ImGui::PushTextWrapPos(ImGui::GetFontSize() * 35.0f);
          ImGui::TextUnformatted(it->text.c_str());
          ImGui::PopTextWrapPos();
          ImGui::EndTooltip();
          break;
        }
      }
    }
  }
  DrawPerceptionWarnings(ctx, v);
  if (model.replay()) {
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(0.4f, 0.7f, 1, 1), "| REPLAY (nothing is sent)");
  }
  ImGui::End();
}

}  // namespace uav::gcs
