// Live map panel: the files the selected vehicle offers (its finished maps), a save location and
// the Download action, with a progress bar per file. (The growing map's tiles come with the live
// tile stream.)
#include <imgui.h>
#include <cstdio>
#include <imgui_stdlib.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {

void DrawLiveMapPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Live map");
  const VehicleModel* v = model.selected();
  if (!v) {
    ImGui::TextDisabled("no vehicle selected");
    ImGui::End();
    return;
  }
  ImGui::TextUnformatted("Save to");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.6f);
  ImGui::InputText("##map:dir", &ctx.state.download_dir);
  RegisterLastItem(ctx, "map:dir");
  ImGui::SameLine();
  if (ImGui::Button("Download")) model.StartDownload(ctx.state.download_dir, ctx.now);
  RegisterLastItem(ctx, "map:download");
  if (!model.download_error().empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.3f, 1), "%s", model.download_error().c_str());
  const std::vector<FileOffer> offers = v->files.offers();
  if (offers.empty()) ImGui::TextDisabled("no map offered yet: the vehicle offers it after the survey, at landing");
  for (const FileOffer& o : offers) {
    const auto p = v->files.progress(o.transfer_id);
    const float fraction = o.chunks ? static_cast<float>(p->received) / o.chunks : 1.0f;
    char overlay[96];
    std::snprintf(overlay, sizeof overlay, "%s  %lld kB  %s", o.name.c_str(), static_cast<long long>((o.size + 1023) / 1024),
                  p->complete ? "saved" : p->failed ? "failed" : p->started ? "downloading" : "offered");
    ImGui::ProgressBar(p->complete ? 1.0f : fraction, ImVec2(-1, 0), overlay);
    auto saved = v->saved.find(o.transfer_id);
    if (saved != v->saved.end() && !saved->second.empty()) ImGui::TextDisabled("  %s", saved->second.c_str());
  }
  ImGui::End();
}

}  // namespace uav::gcs
