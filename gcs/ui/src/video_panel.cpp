// Video panel: the selected vehicle's camera preview, shown at the rate frames arrive, with the
// camera, frame rate and age underneath. (Target selection on a frozen frame is issue 6.)
#include <algorithm>

#include <imgui.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {

void DrawVideoPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Video");
  const VehicleModel* v = model.selected();
  if (!v || v->video.frames == 0) {
    ImGui::TextDisabled(v ? "no video from %s (start uav-onboard with --scene)" : "no vehicle selected",
                        v ? v->id.c_str() : "");
    ImGui::End();
    return;
  }
  const VideoFeed& feed = v->video;
  if (ctx.update_texture && (ctx.state.video_frames_shown != feed.frames || ctx.state.video_vehicle != v->id)) {
    ctx.state.video_texture = ctx.update_texture(0, feed.rgba.data(), feed.width, feed.height);
    ctx.state.video_frames_shown = feed.frames;
    ctx.state.video_vehicle = v->id;
  }
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const float text_h = ImGui::GetTextLineHeightWithSpacing();
  const float scale = std::min(avail.x / feed.width, (avail.y - text_h) / feed.height);
  const ImVec2 size(feed.width * std::max(scale, 0.1f), feed.height * std::max(scale, 0.1f));
  if (ctx.state.video_texture) {
    ImGui::Image(ctx.state.video_texture, size);
  } else {
    ImGui::Dummy(size);  // headless: same layout, nothing to draw
  }
  RegisterLastItem(ctx, "video:image");
  ImGui::Text("%s %dx%d (from %dx%d), %.0f fps, frame %lld%s", feed.camera.c_str(), feed.width, feed.height,
              feed.source_width, feed.source_height, feed.Rate(ctx.now), static_cast<long long>(feed.frames),
              feed.rejected ? ", some frames rejected" : "");
  ImGui::End();
}

}  // namespace uav::gcs
