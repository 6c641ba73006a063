#include "uav/gcs/speaker.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <sstream>
#include <vector>

extern char** environ;

namespace uav::gcs {
namespace {

bool OnPath(const std::string& program) {
  if (program.find('/') != std::string::npos) return access(program.c_str(), X_OK) == 0;
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':'))
    if (!dir.empty() && access((dir + "/" + program).c_str(), X_OK) == 0) return true;
  return false;
}

}  // namespace

Speaker::Speaker(std::string program) : program_(std::move(program)), available_(OnPath(program_)) {
  if (available_) thread_ = std::thread([this] { Run(); });
}

Speaker::~Speaker() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void Speaker::Say(const std::string& sentence) {
  if (!available_) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back(sentence);
    while (queue_.size() > kQueued) queue_.pop_front();
  }
  wake_.notify_one();
}

int Speaker::spoken() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return spoken_;
}

void Speaker::Run() {
  for (;;) {
    std::string sentence;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
      if (stop_) return;
      sentence = std::move(queue_.front());
      queue_.pop_front();
    }
    // The text is one argument (no shell): nothing in a vehicle's message can run a command.
    std::vector<char*> argv = {program_.data(), sentence.data(), nullptr};
    pid_t pid = 0;
    if (posix_spawnp(&pid, program_.c_str(), nullptr, nullptr, argv.data(), environ) == 0) {
      int status = 0;
      waitpid(pid, &status, 0);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    ++spoken_;
  }
}

}  // namespace uav::gcs
