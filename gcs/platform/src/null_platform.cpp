#include <imgui.h>

#include "uav/gcs/platform.hpp"

namespace uav::gcs {
namespace {

class NullPlatform : public Platform {
 public:
  NullPlatform(int width, int height) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // headless runs never touch the operator's layout
    // Like the OpenGL 3 backend: draw lists beyond 64k vertices are split by vertex offset.
    io.BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;
    io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
    unsigned char* pixels;
    int w, h;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);  // the null backend still needs a font atlas
    // Key indices as GLFW numbers them, so scripted keys mean the same in both platforms.
    io.KeyMap[ImGuiKey_Tab] = 258;
    io.KeyMap[ImGuiKey_Enter] = 257;
    io.KeyMap[ImGuiKey_Backspace] = 259;
    io.KeyMap[ImGuiKey_UpArrow] = 265;
    io.KeyMap[ImGuiKey_DownArrow] = 264;
    io.KeyMap[ImGuiKey_Escape] = 256;
    io.KeyMap[ImGuiKey_A] = 65;
  }
  ~NullPlatform() override { ImGui::DestroyContext(); }
  bool NewFrame(double dt) override {
    ImGui::GetIO().DeltaTime = static_cast<float>(dt > 0 ? dt : 1.0 / 60.0);
    return true;
  }
  void Render() override { ImGui::Render(); }
  int Screenshot(const std::string&, std::string* error) override {
    *error = "no display in headless mode";
    return -1;
  }
  bool has_display() const override { return false; }
  void* UpdateTexture(int, const uint8_t*, int, int) override { return nullptr; }
};

}  // namespace

std::unique_ptr<Platform> MakeNullPlatform(int width, int height) {
  return std::make_unique<NullPlatform>(width, height);
}

}  // namespace uav::gcs
