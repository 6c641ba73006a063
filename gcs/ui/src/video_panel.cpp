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

#include "overlays/overlays.hpp"
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

  // Each overlay can be hidden (a grid over plain ground must not hide the picture).
  UiState::VideoOverlays& show = st.video_overlays;
  const struct {
    bool* on;
    const char* label;
    const char* id;
  } overlays[] = {{&show.track, "box", "video:overlay:track"},
                  {&show.wires, "wires", "video:overlay:wires"},
                  {&show.depth, "depth", "video:overlay:depth"},
                  {&show.dots, "dots", "video:overlay:dots"},
                  {&show.obstacles, "obstacles", "video:overlay:obstacles"}};
  for (const auto& o : overlays) {
    ImGui::Checkbox(o.label, o.on);
    RegisterLastItem(ctx, o.id);
    ImGui::SameLine();
  }
  ImGui::NewLine();

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
  }
  // What the vehicle reports over the picture (overlays/).
  const ImageCanvas canvas{dl, p0, size};
  if (!frozen && show.track) DrawTrackOnImage(*v, feed, canvas, ctx.now);
  if (show.wires) DrawPowerLinesOnImage(model, *v, feed, canvas, ctx.now);
  if (show.depth) DrawDepthGridOnImage(model, *v, feed, canvas, ctx.now);
  if (show.dots) DrawActiveStereoOnImage(model, *v, feed, canvas, ctx.now);
  if (show.obstacles) DrawObstaclesOnImage(model, *v, feed, canvas, ctx.now);
  ImGui::Text("%s %dx%d (from %dx%d), %.0f fps, frame %lld%s", feed.camera.c_str(), feed.width, feed.height,
              feed.source_width, feed.source_height, v->video.Rate(ctx.now), static_cast<long long>(feed.frames),
              feed.rejected ? ", some frames rejected" : "");
  ImGui::End();
}

}  // namespace uav::gcs
