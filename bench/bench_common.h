#pragma once
// What every benchmark reports about where and how it ran, so its JSON can be compared with
// another run's (or explained by the load on a shared machine).
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include <cmath>
#include <ctime>
#include <fstream>
#include <string>

#include <CLI/CLI.hpp>

#include "lambert/core/error.h"
#include "lambert/load/scene_file.h"

namespace lambert::bench {

inline std::string cpuModel() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      auto colon = line.find(':');
      if (colon == std::string::npos) break;
      std::string model = line.substr(colon + 1);
      model.erase(0, model.find_first_not_of(" \t"));
      return model;
    }
  }
  return "unknown CPU";
}

inline std::string utcNow() {
  std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

inline std::string buildDescription() {
#ifdef NDEBUG
  std::string type = "Release";
#else
  std::string type = "Debug";
#endif
#if defined(__clang__)
  return type + ", " + __VERSION__;
#elif defined(__GNUC__)
  return type + ", GCC " + __VERSION__;
#else
  return type + ", " + __VERSION__;
#endif
}

// Seconds to the microsecond, so the JSON stays readable (x·10^k rounded, then divided, is the
// double nearest the decimal, which prints short).
inline double roundDigits(double value, int decimals) {
  double scale = std::pow(10.0, decimals);
  return std::round(value * scale) / scale;
}
inline double seconds(double s) { return roundDigits(s, 6); }

// CPU time of the whole process, all threads: against wall time it shows how many cores the
// run actually got (others' compiles share this machine).
inline double processCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

inline std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return one.empty() ? "unknown" : one + " " + five + " " + fifteen;
}

// The resident set now, from /proc/self/statm (pages).
inline double currentRssMib() {
  std::ifstream statm("/proc/self/statm");
  std::size_t size = 0, resident = 0;
  statm >> size >> resident;
  return roundDigits(static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0), 1);
}

// The process's peak resident set so far: getrusage's ru_maxrss (KiB on Linux), or the resident
// set now where that is higher (the kernel updates its high-water mark lazily, so it can trail).
inline double peakRssMib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return std::max(roundDigits(static_cast<double>(usage.ru_maxrss) / 1024.0, 1), currentRssMib());
}

// The command line parsed into the options `app` was given: --help prints the usage, and a bad
// option its error, each ending the process with CLI11's exit code.
inline void parseOrExit(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::exit(app.exit(e));
  }
}

// The generated building's size, as every benchmark over it takes it (lambert generate building's
// --rooms and --face-size).
inline void addBuildingOptions(CLI::App& app, int& rooms, double& faceSize) {
  app.add_option("--rooms", rooms, "Rooms of the generated building")->check(CLI::Range(1, 4096))->capture_default_str();
  app.add_option("--face-size", faceSize, "Largest face of the building, m")->check(CLI::Range(0.01, 100.0))->capture_default_str();
}

// The result, or its error after the benchmark's name on stderr and exit 1.
template <typename T>
T orExit(Result<T> result, const char* benchmark) {
  if (!result) {
    std::fprintf(stderr, "%s: %s\n", benchmark, result.error().message.c_str());
    std::exit(1);
  }
  return std::move(*result);
}

// lambert's --sides on a bench tool that reads a scene as the CLI does: "file" (each material as
// the file says), "one" or "two" (every material so).
inline void addSidesOption(CLI::App& app, std::string& sides) {
  app.add_option("--sides", sides, "file: each material's sides as the file says; one, two: every material so (lambert's --sides)")
      ->check(CLI::IsMember({"file", "one", "two"}))
      ->capture_default_str();
}
inline Result<Scene> loadSceneWithSides(const std::string& nameOrPath, const std::string& sides) {
  LoadOptions load;
  if (sides != "file") load.twoSided = sides == "two";
  return loadScene(nameOrPath, load);
}

}  // namespace lambert::bench
