#pragma once
// Running a command line from a test: its exit code and everything it printed.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace lambert::testing {

struct CommandResult {
  int exitCode = -1;
  std::string output;  // stdout and stderr together
};

inline CommandResult shell(const std::string& commandLine) {
  const std::string command = commandLine + " 2>&1";
  CommandResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  while (std::size_t n = fread(buffer.data(), 1, buffer.size(), pipe)) result.output.append(buffer.data(), n);
  int status = pclose(pipe);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

// The Khronos glTF-Validator (installed into .tools/ by scripts/install-deps.sh where npm is):
// why it cannot run here, or "" where it can. Needs LAMBERT_SOURCE_DIR.
inline std::string gltfValidatorSkipReason(const std::string& sourceDir) {
  if (std::system("node --version > /dev/null 2>&1") != 0) return "no node.js here to run the glTF-Validator";
  if (std::system(("test -f " + sourceDir + "/.tools/node_modules/gltf-validator/package.json").c_str()) != 0)
    return "no glTF-Validator in .tools/ (npm was not reachable when install-deps ran)";
  return "";
}

// tests/validate-glb.js over the files (space-separated paths): exit 0 when none has an issue.
inline CommandResult validateGlb(const std::string& sourceDir, const std::string& files) {
  return shell("node " + sourceDir + "/tests/validate-glb.js " + sourceDir + "/.tools/node_modules/gltf-validator " + files);
}

}  // namespace lambert::testing
