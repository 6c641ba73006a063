#pragma once
// The display behind the panels. Both platforms own the ImGui context; the same DrawGcs runs
// between NewFrame() and Render() on either.
#include <cstdint>
#include <memory>
#include <string>

namespace uav::gcs {

class Platform {
 public:
  virtual ~Platform() = default;
  // Prepares the platform's part of a frame (input, display size). False when the window closed.
  virtual bool NewFrame(double dt) = 0;
  virtual void Render() = 0;
  // Saves the next rendered frame as a PNG (written to a temporary name, then renamed).
  // 1: saved; 0: pending, call again after the next Render(); -1: failed, *error says why.
  virtual int Screenshot(const std::string& path, std::string* error) = 0;
  virtual bool has_display() const = 0;
  // Uploads an RGBA image into texture `slot` (created on first use, replaced after) and returns
  // its ImTextureID; nullptr where nothing is drawn (headless).
  virtual void* UpdateTexture(int slot, const uint8_t* rgba, int width, int height) = 0;
  // The first connected gamepad in GLFW's standard layout (6 axes, 15 buttons); false when there
  // is none (or no display).
  virtual bool ReadGamepad(float axes[6], bool buttons[15]) { return false; }
};

// Headless: ImGui's null backend (no renderer; fonts built, draw data produced and discarded).
std::unique_ptr<Platform> MakeNullPlatform(int width, int height);

// A GLFW window with an OpenGL 3.3 core context. Throws std::runtime_error when no display can
// be opened. `ini_path` keeps the window layout between runs ("" to not keep it).
std::unique_ptr<Platform> MakeGlfwPlatform(int width, int height, const std::string& title,
                                           const std::string& ini_path);

}  // namespace uav::gcs
