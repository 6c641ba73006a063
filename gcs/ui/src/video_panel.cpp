// Video panel: the selected vehicle's camera preview, shown at the rate frames arrive, with the
// camera, frame rate and age underneath. Freeze holds a frame to pick a target on it, by clicking
// its four corners (thesis 3.7.3) or by dragging a rectangle; the selection goes to the vehicle
// in image coordinates normalised to 0..1 and the panel returns to live video, where the
// tracker's box, centre and state are drawn over the picture.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <imgui.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {
namespace {

constexpr float kDragPixels = 4.0f;

void SendSelection(GcsModel& model, UiContext& ctx, const VideoFeed& frame, TrackTarget::Method method,
                   const std::vector<std::array<float, 2>>& corners) {
  TrackTarget t;
  t.frame_utime = frame.utime;
  t.camera = frame.camera;
  t.method = method;
  float x0 = 1, y0 = 1, x1 = 0, y1 = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& c = corners[std::min(i, corners.size() - 1)];
    t.corners[i] = {c[0], c[1]};
    x0 = std::min(x0, c[0]), y0 = std::min(y0, c[1]), x1 = std::max(x1, c[0]), y1 = std::max(y1, c[1]);
  }
  t.x = x0;
  t.y = y0;
  t.width = x1 - x0;
  t.height = y1 - y0;
  if (model.SelectTarget(t, ctx.now)) model.FreezeVideo(false);  // back to live to watch it track
  ctx.state.video_clicks.clear();
}

}  // namespace

void DrawVideoPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Video");
  UiState& st = ctx.state;
  const VehicleModel* v = model.selected();
  if (!v || v->video.frames == 0) {
    ImGui::TextDisabled(v ? "no video from %s (start uav-onboard with --scene)" : "no vehicle selected",
                        v ? v->id.c_str() : "");
    ImGui::End();
    return;
  }
  const bool frozen = model.video().frozen().has_value() && model.video().frozen_vehicle() == v->id;
  const VideoFeed& feed = frozen ? *model.video().frozen() : v->video;
  if (ImGui::Button(frozen ? "Live" : "Freeze")) {
    model.FreezeVideo(!frozen);
    st.video_clicks.clear();
  }
  RegisterLastItem(ctx, "video:freeze");
  if (v->cameras.size() > 1) {
    // Which of the vehicle's cameras to watch (and pick targets on).
    ImGui::SameLine();
    ImGui::SetNextItemWidth(110);
    if (ImGui::BeginCombo("##camera", v->camera.c_str())) {
      for (const std::string& name : v->cameras)
        if (ImGui::Selectable(name.c_str(), name == v->camera)) model.ChooseVideoCamera(name);
      ImGui::EndCombo();
    }
  }
  ImGui::SameLine();
  if (ImGui::Button("Stop tracking")) {
    TrackTarget cancel;
    cancel.method = TrackTarget::kCancel;
    model.SelectTarget(cancel, ctx.now);
  }
  RegisterLastItem(ctx, "video:cancel");
  // Follow the locked target: asks for confirmation in the command bar, like its other actions.
  ImGui::SameLine();
  const bool locked = v->track && v->track->state == TrackStatus::kTracking;
  if (v->task == Task::kFollow) {
    ImGui::TextColored(ImVec4(0.4f, 1, 0.5f, 1), "FOLLOWING");
  } else {
    ImGui::BeginDisabled(!locked);
    if (ImGui::Button("Follow")) st.pending_confirmation = "follow";
    ImGui::EndDisabled();
    RegisterLastItem(ctx, "video:follow");
  }
  if (frozen) {
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "FROZEN: drag a box or click 4 corners (%zu/4), right click clears",
                       st.video_clicks.size());
  } else if (!model.video().error().empty()) {
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", model.video().error().c_str());
  }

  const int64_t shown = frozen ? -feed.frames - 1 : feed.frames;  // a frozen frame is its own texture
  if (ctx.update_texture && (st.video_frames_shown != shown || st.video_vehicle != v->id)) {
    st.video_texture = ctx.update_texture(0, feed.rgba.data(), feed.width, feed.height);
    st.video_frames_shown = shown;
    st.video_vehicle = v->id;
  }
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const float text_h = ImGui::GetTextLineHeightWithSpacing();
  const float scale = std::min(avail.x / feed.width, (avail.y - text_h) / feed.height);
  const ImVec2 size(feed.width * std::max(scale, 0.1f), feed.height * std::max(scale, 0.1f));
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("video:image", size);
  RegisterLastItem(ctx, "video:image");
  ImDrawList* dl = ImGui::GetWindowDrawList();
  if (st.video_texture) dl->AddImage(st.video_texture, p0, ImVec2(p0.x + size.x, p0.y + size.y));
  else dl->AddRectFilled(p0, ImVec2(p0.x + size.x, p0.y + size.y), IM_COL32(30, 30, 30, 255));  // headless
  if (frozen) dl->AddRect(p0, ImVec2(p0.x + size.x, p0.y + size.y), IM_COL32(255, 200, 80, 255), 0, 0, 2.0f);
  auto to_screen = [&](double nx, double ny) { return ImVec2(p0.x + static_cast<float>(nx) * size.x, p0.y + static_cast<float>(ny) * size.y); };
  auto normalised = [&](ImVec2 s) {
    return std::array<float, 2>{std::clamp((s.x - p0.x) / size.x, 0.0f, 1.0f), std::clamp((s.y - p0.y) / size.y, 0.0f, 1.0f)};
  };

  if (frozen) {
    const ImGuiIO& io = ImGui::GetIO();
    if (ImGui::IsItemActivated()) {
      st.video_press = normalised(io.MousePos);
      st.video_dragging = false;
    }
    if (ImGui::IsItemActive() && ImGui::IsMouseDragging(ImGuiMouseButton_Left, kDragPixels)) st.video_dragging = true;
    if (ImGui::IsItemActive() && st.video_dragging) {
      const auto cur = normalised(io.MousePos);
      dl->AddRect(to_screen(std::min(st.video_press[0], cur[0]), std::min(st.video_press[1], cur[1])),
                  to_screen(std::max(st.video_press[0], cur[0]), std::max(st.video_press[1], cur[1])),
                  IM_COL32(255, 220, 80, 255), 0, 0, 2.0f);
    }
    if (ImGui::IsItemDeactivated()) {
      const auto cur = normalised(io.MousePos);
      if (st.video_dragging) {
        SendSelection(model, ctx, feed, TrackTarget::kDrag,
                      {st.video_press, {cur[0], st.video_press[1]}, cur, {st.video_press[0], cur[1]}});
      } else {
        st.video_clicks.push_back(cur);
        if (st.video_clicks.size() == 4) SendSelection(model, ctx, feed, TrackTarget::kFourClicks, st.video_clicks);
      }
      st.video_dragging = false;
    }
    if (ImGui::IsItemHovered() && ImGui::IsMouseClicked(ImGuiMouseButton_Right)) st.video_clicks.clear();
    for (std::size_t i = 0; i < st.video_clicks.size(); ++i) {
      const ImVec2 c = to_screen(st.video_clicks[i][0], st.video_clicks[i][1]);
      dl->AddCircleFilled(c, 4.0f, IM_COL32(255, 220, 80, 255));
      if (i > 0) dl->AddLine(to_screen(st.video_clicks[i - 1][0], st.video_clicks[i - 1][1]), c, IM_COL32(255, 220, 80, 255), 1.5f);
    }
  } else {
    // The tracker's report over the live picture.
    if (v->track && v->track->state == TrackStatus::kRejected && ctx.now - v->track_received < 5.0) {
      const std::string text = "TARGET REJECTED: " + v->track->reason;
      dl->AddText(ImVec2(p0.x + 6, p0.y + 6), IM_COL32(255, 90, 90, 255), text.c_str());
    } else if (v->track && v->track->state != TrackStatus::kIdle && ctx.now - v->track_received < 2.0 &&
               (v->track->camera.empty() || v->track->camera == feed.camera)) {
      const TrackStatus& t = *v->track;
      // The search window the next frame starts from (the whole picture while lost).
      dl->AddRect(to_screen(t.window_x, t.window_y), to_screen(t.window_x + t.window_width, t.window_y + t.window_height),
                  IM_COL32(80, 200, 255, 160), 0.0f, 0, 1.0f);
      const ImU32 colour = t.state == TrackStatus::kTracking ? IM_COL32(80, 255, 120, 255) : IM_COL32(255, 170, 60, 255);
      const double c = std::cos(t.angle_rad), s = std::sin(t.angle_rad);
      // Oriented box: normalised units scaled by the picture's aspect so the rotation is true.
      const double aspect = static_cast<double>(size.y) / size.x;
      ImVec2 q[4];
      const double hx[4] = {-0.5, 0.5, 0.5, -0.5}, hy[4] = {-0.5, -0.5, 0.5, 0.5};
      for (int i = 0; i < 4; ++i) {
        const double dx = hx[i] * t.width, dy = hy[i] * t.height * aspect;
        q[i] = to_screen(t.center_x + c * dx - s * dy, t.center_y + (s * dx + c * dy) / aspect);
      }
      dl->AddPolyline(q, 4, colour, ImDrawFlags_Closed, 2.0f);
      const ImVec2 ctr = to_screen(t.center_x, t.center_y);
      dl->AddLine(ImVec2(ctr.x - 8, ctr.y), ImVec2(ctr.x + 8, ctr.y), colour, 2.0f);
      dl->AddLine(ImVec2(ctr.x, ctr.y - 8), ImVec2(ctr.x, ctr.y + 8), colour, 2.0f);
      char label[96];
      std::snprintf(label, sizeof label, "%s %s %.2f", t.state == TrackStatus::kTracking ? "TRACKING" : "LOST",
                    t.tracker.c_str(), t.confidence);
      dl->AddText(ImVec2(q[0].x, q[0].y - 16), colour, label);
    } else if (v->track_target && v->track_target->method != TrackTarget::kCancel) {
      // Sent, no answer yet: the selection, thin.
      const TrackTarget& t = *v->track_target;
      dl->AddRect(to_screen(t.x, t.y), to_screen(t.x + t.width, t.y + t.height), IM_COL32(255, 255, 255, 180));
    }
  }
  // Power lines over the picture, when they were found in this camera's image (thesis 3.6):
  // red nearer than the warning distance, orange ranged, thin yellow seen but not ranged.
  const WireWarningParams& wp = model.wires().params();
  if (const PowerLines* lines = v->FreshPowerLines(ctx.now, wp); lines && lines->camera == feed.camera) {
    for (const PowerLine& w : lines->wires) {
      if (w.image_uv.size() < 2) continue;
      const bool near = w.ranged() && w.range_m < wp.warn_distance_m;
      const ImU32 colour = near ? IM_COL32(255, 60, 60, 255) : w.ranged() ? IM_COL32(255, 160, 40, 255) : IM_COL32(255, 230, 80, 200);
      std::vector<ImVec2> pts;
      for (const auto& uv : w.image_uv) pts.push_back(to_screen(uv.x(), uv.y()));
      dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), colour, ImDrawFlags_None, w.ranged() ? 2.5f : 1.5f);
      if (w.ranged()) {
        char label[32];
        std::snprintf(label, sizeof label, "%.1f m", w.range_m);
        const ImVec2 at = pts[pts.size() / 2];
        dl->AddText(ImVec2(at.x + 4, at.y - 16), colour, label);
      }
    }
  }
  // Depth from motion (thesis 3.4, Fig. 3.11): the grid over the picture, each cell's depth and
  // state (red obstacle, green free, grey unknown with its reason on hover).
  if (const DepthGrid* grid = v->DepthGridOver(feed, ctx.now, model.obstacles().params())) {
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    for (int r = 0; r < grid->rows; ++r)
      for (int c = 0; c < grid->cols; ++c) {
        const DepthCell& cell = grid->at(r, c);
        const ImU32 colour = cell.state == CellState::kObstacle ? IM_COL32(255, 70, 70, 220)
                             : cell.state == CellState::kFree   ? IM_COL32(90, 230, 110, 200)
                                                                : IM_COL32(170, 170, 170, 150);
        const ImVec2 a = to_screen(static_cast<double>(c) / grid->cols, static_cast<double>(r) / grid->rows);
        const ImVec2 b = to_screen(static_cast<double>(c + 1) / grid->cols, static_cast<double>(r + 1) / grid->rows);
        dl->AddRect(a, b, colour, 0, 0, 1.0f);
        char label[48];
        if (cell.state == CellState::kUnknown) std::snprintf(label, sizeof label, "?");
        else std::snprintf(label, sizeof label, "%.1f m %s", cell.depth_m, cell.state == CellState::kObstacle ? "OBST" : "");
        dl->AddText(ImVec2(a.x + 4, a.y + 3), colour, label);
        if (cell.state == CellState::kUnknown && mouse.x >= a.x && mouse.x < b.x && mouse.y >= a.y && mouse.y < b.y &&
            ImGui::IsWindowHovered())
          ImGui::SetTooltip("%s", grid->healthy ? cell.reason.c_str() : grid->reason.c_str());
      }
  }
  // Active stereo (thesis ch. 4): each triangulated laser dot, green on the ground cluster the
  // height is measured to, orange on a nearer cluster (a table, a wall, a ledge), and the height.
  if (const ActiveStereoReport* as = v->ActiveStereoOver(feed, ctx.now, model.obstacles().params())) {
    for (const LaserDotReport& d : as->dots) {
      const bool ground = d.cluster < static_cast<int>(as->clusters.size()) && as->clusters[d.cluster].ground;
      dl->AddCircle(to_screen(d.u, d.v), 4.0f, ground ? IM_COL32(90, 230, 110, 230) : IM_COL32(255, 160, 40, 230), 0, 1.5f);
    }
    char label[96];
    if (as->healthy) std::snprintf(label, sizeof label, "height %.2f m (%zu dots, %zu clusters)", as->height_m, as->dots.size(), as->clusters.size());
    else std::snprintf(label, sizeof label, "no height: %s", as->reason.c_str());
    const ImVec2 at = to_screen(0.02, 0.02);
    dl->AddText(at, as->healthy ? IM_COL32(90, 230, 110, 255) : IM_COL32(255, 90, 90, 255), label);
  }
  // Stereo obstacles (thesis 3.5) as boxes around their projected cylinders, labelled with the
  // horizontal distance to their surface.
  if (const Obstacles* obstacles = v->FreshObstacles(ctx.now, model.obstacles().params());
      obstacles && obstacles->camera == feed.camera) {
    for (const Obstacle& o : obstacles->obstacles) {
      const ImU32 colour = IM_COL32(200, 80, 255, 230);
      const ImVec2 a = to_screen(o.image_box[0], o.image_box[1]), b = to_screen(o.image_box[2], o.image_box[3]);
      dl->AddRect(a, b, colour, 0, 0, 2.0f);
      char label[32];
      std::snprintf(label, sizeof label, "%.1f m", o.range_m);
      dl->AddText(ImVec2(a.x + 2, a.y + 2), colour, label);
    }
  }
  ImGui::Text("%s %dx%d (from %dx%d), %.0f fps, frame %lld%s", feed.camera.c_str(), feed.width, feed.height,
              feed.source_width, feed.source_height, v->video.Rate(ctx.now), static_cast<long long>(feed.frames),
              feed.rejected ? ", some frames rejected" : "");
  ImGui::End();
}

}  // namespace uav::gcs
