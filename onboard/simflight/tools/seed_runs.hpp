#pragma once
// Flying a range of seeds in several processes: on this machine (one process per seed, a few at
// once) or on a cluster as a Slurm job array (one task per range of seeds). Each process is the
// same program with the same flight options, its own --seeds and its own --json; the caller
// merges the files (uav-avoid-bench --merge). Plain functions, no knowledge of flights.
#include <functional>
#include <string>
#include <vector>

namespace uav::simflight {

struct SeedRange {
  int first = 0, last = 0;  // inclusive
  int count() const { return last - first + 1; }
};

// This program's own command line without the options that say how and where to run (each
// given as "--name VALUE" or "--name=VALUE", or a flag): what every process repeats.
std::vector<std::string> RepeatedArguments(int argc, char** argv, const std::vector<std::string>& options_with_value,
                                           const std::vector<std::string>& flags);

// The running program's executable (absolute).
std::string ThisExecutable();

// A line for /bin/sh: each word single-quoted where it needs it.
std::string ShellQuoted(const std::vector<std::string>& words);

// Runs `program arguments --seeds S --json DIR/seed_S.json --quiet` for every seed, at most
// `processes` at once, each one's stderr in DIR/seed_S.log. `done(seed, exit_code)` is called as
// each ends (in the order they end). Returns the result files in seed order. Throws
// std::runtime_error naming the seed and the last line of its log when a process could not run
// or ended with an exit code other than 0 or `flight_failed_code` (a flight that failed is a
// result, not an error).
std::vector<std::string> RunSeedsLocally(const std::string& program, const std::vector<std::string>& arguments, SeedRange seeds,
                                         int processes, const std::string& dir, int flight_failed_code,
                                         const std::function<void(int seed, int exit_code)>& done);

// A Slurm job array: task k flies seeds first + k * per_task .. (at most) last, writes
// DIR/task_k.json and logs to DIR/task_k.log. Each task asks for `cpus_per_task` CPUs.
struct SlurmArray {
  std::string dir;
  SeedRange seeds;
  int seeds_per_task = 10;
  int cpus_per_task = 2;
  int tasks() const { return (seeds.count() + seeds_per_task - 1) / seeds_per_task; }
  SeedRange TaskSeeds(int task) const;
  std::string ResultFile(int task) const;
  std::string LogFile(int task) const;
  // The batch script (#SBATCH lines, then the program run for the task's seeds).
  std::string Script(const std::string& program, const std::vector<std::string>& arguments, const std::string& working_dir) const;
};

// Writes DIR/job.sh and submits it with sbatch (`sbatch_options` added, e.g. --partition=long),
// waiting for the whole array to end when `wait`. Returns the job id. Throws std::runtime_error
// with sbatch's own message when it refuses.
std::string SubmitSlurmArray(const SlurmArray& array, const std::string& program, const std::vector<std::string>& arguments,
                             const std::vector<std::string>& sbatch_options, bool wait);

// The tasks of an array that did not fly all their seeds (no result file, or fewer flights in it),
// each as "task K (seeds A-B, N flown): LAST LOG LINE".
std::vector<std::string> MissingTasks(const SlurmArray& array);

}  // namespace uav::simflight
