#include "seed_runs.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "uav/shared/text_file.hpp"

extern char** environ;

namespace uav::simflight {
namespace {

// The last non-empty line of a file ("" when none).
std::string LastLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

bool Matches(const std::string& word, const std::string& option) {
  return word == option || word.rfind(option + "=", 0) == 0;
}

}  // namespace

std::vector<std::string> RepeatedArguments(int argc, char** argv, const std::vector<std::string>& options_with_value,
                                           const std::vector<std::string>& flags) {
  std::vector<std::string> kept;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (std::find(flags.begin(), flags.end(), word) != flags.end()) continue;
    const auto dropped = std::find_if(options_with_value.begin(), options_with_value.end(),
                                      [&](const std::string& o) { return Matches(word, o); });
    if (dropped == options_with_value.end()) {
      kept.push_back(word);
    } else if (word == *dropped) {
      ++i;  // "--name VALUE": the value too
    }
  }
  return kept;
}

std::string ThisExecutable() {
  std::error_code ec;
  const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot tell this program's own path (/proc/self/exe): " + ec.message());
  return p.string();
}

std::string ShellQuoted(const std::vector<std::string>& words) {
  std::string line;
  for (const std::string& w : words) {
    if (!line.empty()) line += ' ';
    const bool plain = !w.empty() && w.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_./=:,+@%") ==
                                         std::string::npos;
    if (plain) {
      line += w;
      continue;
    }
    line += '\'';
    for (char c : w) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += '\'';
  }
  return line;
}

std::vector<std::string> RunSeedsLocally(const std::string& program, const std::vector<std::string>& arguments, SeedRange seeds,
                                         int processes, const std::string& dir, int flight_failed_code,
                                         const std::function<void(int, int)>& done) {
  std::map<pid_t, int> running;  // pid -> seed
  std::vector<std::string> results;
  std::string error;
  int next = seeds.first;
  const auto start = [&](int seed) {
    const std::string result = dir + "/seed_" + std::to_string(seed) + ".json", log = dir + "/seed_" + std::to_string(seed) + ".log";
    std::vector<std::string> words = arguments;
    for (const std::string& w : {std::string("--seeds"), std::to_string(seed), std::string("--json"), result, std::string("--quiet")})
      words.push_back(w);
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(program.c_str()));
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) throw std::runtime_error("cannot start " + program + " for seed " + std::to_string(seed) + ": " + std::strerror(rc));
    running[pid] = seed;
  };
  while (next <= seeds.last || !running.empty()) {
    while (error.empty() && next <= seeds.last && static_cast<int>(running.size()) < processes) start(next++);
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("waiting for the seeds' processes: ") + std::strerror(errno));
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const int seed = it->second;
    running.erase(it);
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    if (code != 0 && code != flight_failed_code && error.empty()) {
      const std::string last = LastLine(dir + "/seed_" + std::to_string(seed) + ".log");
      error = "seed " + std::to_string(seed) + " ended with exit code " + std::to_string(code) + (last.empty() ? "" : ": " + last);
    }
    if (done) done(seed, code);
  }
  if (!error.empty()) throw std::runtime_error(error);
  for (int seed = seeds.first; seed <= seeds.last; ++seed) results.push_back(dir + "/seed_" + std::to_string(seed) + ".json");
  return results;
}

SeedRange SlurmArray::TaskSeeds(int task) const {
  const int first = seeds.first + task * seeds_per_task;
  return {first, std::min(seeds.last, first + seeds_per_task - 1)};
}

std::string SlurmArray::ResultFile(int task) const { return dir + "/task_" + std::to_string(task) + ".json"; }
std::string SlurmArray::LogFile(int task) const { return dir + "/task_" + std::to_string(task) + ".log"; }

std::string SlurmArray::Script(const std::string& program, const std::vector<std::string>& arguments, const std::string& working_dir) const {
  std::string s = "#!/bin/bash\n";
  s += "# uav-avoid-bench as a Slurm job array: task K flies seeds " + std::to_string(seeds.first) + " + K x " +
       std::to_string(seeds_per_task) + " on (at most " + std::to_string(seeds_per_task) + "), up to seed " +
       std::to_string(seeds.last) + ".\n";
  s += "#SBATCH --job-name=uav-avoid-bench\n";
  s += "#SBATCH --array=0-" + std::to_string(tasks() - 1) + "\n";
  s += "#SBATCH --cpus-per-task=" + std::to_string(cpus_per_task) + "\n";
  s += "#SBATCH --chdir=" + working_dir + "\n";
  s += "#SBATCH --output=" + dir + "/task_%a.log\n";
  s += "set -eu\n";
  s += "first=$(( " + std::to_string(seeds.first) + " + SLURM_ARRAY_TASK_ID * " + std::to_string(seeds_per_task) + " ))\n";
  s += "last=$(( first + " + std::to_string(seeds_per_task - 1) + " ))\n";
  s += "if [ \"$last\" -gt " + std::to_string(seeds.last) + " ]; then last=" + std::to_string(seeds.last) + "; fi\n";
  std::vector<std::string> words{program};
  words.insert(words.end(), arguments.begin(), arguments.end());
  s += "exec " + ShellQuoted(words) + " --seeds \"$first-$last\" --json " + ShellQuoted({dir}) +
       "/task_\"$SLURM_ARRAY_TASK_ID\".json --quiet\n";
  return s;
}

std::string SubmitSlurmArray(const SlurmArray& array, const std::string& program, const std::vector<std::string>& arguments,
                             const std::vector<std::string>& sbatch_options, bool wait) {
  std::filesystem::create_directories(array.dir);
  const std::string script = array.dir + "/job.sh";
  WriteFileAtomically(script, array.Script(program, arguments, std::filesystem::current_path().string()));
  std::vector<std::string> command{"sbatch", "--parsable"};
  if (wait) command.push_back("--wait");
  command.insert(command.end(), sbatch_options.begin(), sbatch_options.end());
  command.push_back(script);
  const std::string line = ShellQuoted(command) + " 2>&1";
  FILE* pipe = popen(line.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run sbatch: " + std::string(std::strerror(errno)));
  std::string output;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  std::string job = output.substr(0, output.find_first_of(";\n"));
  // With --wait sbatch's exit code is the array's (non-zero when a flight failed): the job id it
  // printed first tells a submission from a refusal.
  const bool submitted = !job.empty() && job.find_first_not_of("0123456789") == std::string::npos;
  if (!submitted) {
    while (!output.empty() && output.back() == '\n') output.pop_back();
    throw std::runtime_error("sbatch refused the job array" + (output.empty() ? std::string(" (exit status ") + std::to_string(status) + ")"
                                                                              : ": " + output));
  }
  return job;
}

std::vector<std::string> MissingTasks(const SlurmArray& array) {
  std::vector<std::string> missing;
  for (int k = 0; k < array.tasks(); ++k) {
    const SeedRange s = array.TaskSeeds(k);
    // A task writes its file after every flight: one cut short leaves fewer flights than seeds.
    std::size_t flown = 0;
    if (std::filesystem::exists(array.ResultFile(k))) {
      try {
        const nlohmann::json j = nlohmann::json::parse(ReadTextFile(array.ResultFile(k), "task results"));
        if (j.contains("flights") && j["flights"].is_array()) flown = j["flights"].size();
      } catch (const std::exception&) {
        flown = 0;
      }
    }
    if (flown == static_cast<std::size_t>(s.count())) continue;
    const std::string last = LastLine(array.LogFile(k));
    missing.push_back("task " + std::to_string(k) + " (seeds " + std::to_string(s.first) + "-" + std::to_string(s.last) + ", " +
                      std::to_string(flown) + " flown): " + (last.empty() ? "no log" : last));
  }
  return missing;
}

}  // namespace uav::simflight
