#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <GL/gl.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include "uav/gcs/platform.hpp"

namespace uav::gcs {
namespace {

class GlfwPlatform : public Platform {
 public:
  GlfwPlatform(int width, int height, const std::string& title, const std::string& ini_path)
      : ini_path_(ini_path) {
    if (!glfwInit()) throw std::runtime_error("cannot initialise GLFW (is there a display? DISPLAY unset?)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
      glfwTerminate();
      throw std::runtime_error("cannot open an OpenGL 3.3 window");
    }
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(1);  // keep the display's frame rate, no faster
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = ini_path_.empty() ? nullptr : ini_path_.c_str();
    ImGui::StyleColorsDark();
    // Opaque panels: a window over another never shows both at once.
    ImGui::GetStyle().Colors[ImGuiCol_WindowBg].w = 1.0f;
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");
  }
  ~GlfwPlatform() override {
    for (const auto& t : textures_) glDeleteTextures(1, &t.second);
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window_);
    glfwTerminate();
  }
  void* UpdateTexture(int slot, const uint8_t* rgba, int width, int height) override {
    GLuint& tex = textures_[slot];
    if (tex == 0) glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    return reinterpret_cast<void*>(static_cast<intptr_t>(tex));
  }
  bool NewFrame(double) override {
    glfwPollEvents();
    if (glfwWindowShouldClose(window_)) return false;
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    return true;
  }
  void Render() override {
    ImGui::Render();
    int w, h;
    glfwGetFramebufferSize(window_, &w, &h);
    glViewport(0, 0, w, h);
    glClearColor(0.08f, 0.08f, 0.10f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    // Read back before the swap: this is exactly the frame being shown.
    if (!pending_screenshot_.empty()) {
      std::vector<unsigned char> rgb(static_cast<std::size_t>(w) * h * 3);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
      stbi_flip_vertically_on_write(1);
      const std::string tmp = pending_screenshot_ + ".tmp.png";
      screenshot_ok_ = stbi_write_png(tmp.c_str(), w, h, 3, rgb.data(), w * 3) != 0 &&
                       std::rename(tmp.c_str(), pending_screenshot_.c_str()) == 0;
      pending_screenshot_.clear();
    }
    glfwSwapBuffers(window_);
  }
  int Screenshot(const std::string& path, std::string* error) override {
    if (requested_ != path) {  // new request: captured at the end of the next Render()
      requested_ = path;
      pending_screenshot_ = path;
      return 0;
    }
    if (!pending_screenshot_.empty()) return 0;  // not rendered yet
    requested_.clear();
    if (!screenshot_ok_) {
      *error = "could not write '" + path + "'";
      return -1;
    }
    return 1;
  }
  bool has_display() const override { return true; }
  bool ReadGamepad(float axes[6], bool buttons[15]) override {
    for (int jid = GLFW_JOYSTICK_1; jid <= GLFW_JOYSTICK_LAST; ++jid) {
      GLFWgamepadstate state;
      if (!glfwJoystickIsGamepad(jid) || !glfwGetGamepadState(jid, &state)) continue;
      for (int i = 0; i < 6; ++i) axes[i] = state.axes[i];
      for (int i = 0; i < 15; ++i) buttons[i] = state.buttons[i] == GLFW_PRESS;
      return true;
    }
    return false;
  }

 private:
  GLFWwindow* window_ = nullptr;
  std::string ini_path_;
  std::string pending_screenshot_;
  std::string requested_;
  bool screenshot_ok_ = false;
  std::map<int, GLuint> textures_;
};

}  // namespace

std::unique_ptr<Platform> MakeGlfwPlatform(int width, int height, const std::string& title,
                                           const std::string& ini_path) {
  return std::make_unique<GlfwPlatform>(width, height, title, ini_path);
}

}  // namespace uav::gcs
