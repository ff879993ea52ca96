// lambert: radiosity for diffuse scenes. A thin front end: each subcommand lives in its own file.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "commands.h"
#include "options.h"
#include "lambert/core/interrupt.h"
#include "lambert/version.h"

int main(int argc, char** argv) {
  lambert::exitCleanlyOnInterrupt("lambert");  // first: every thread started later inherits its signal mask
  lambert::cli::keepWarnings();                 // for --json's "warnings"
  CLI::App app{"lambert — physically based radiosity for diffuse scenes"};
  // The library's version (the one linked in), as `lambert --version` prints it.
  app.set_version_flag("--version", std::string("lambert ") + lambert::version());
  app.require_subcommand(1);
  // Every command's results are the same to the bit whatever the thread count (a test checks it);
  // --threads only trades time for cores.
  app.fallthrough();
  int threads = 0;
  app.add_option("--threads", threads, "Threads to use (default: every core); results do not depend on it")->check(CLI::Range(1, 4096));
  using AddCommand = std::function<int()> (*)(CLI::App&);
  std::vector<std::pair<CLI::App*, std::function<int()>>> commands;
  for (AddCommand add : {lambert::cli::addRenderCommand, lambert::cli::addSolveCommand, lambert::cli::addAnimateCommand,
                         lambert::cli::addReferenceCommand, lambert::cli::addCompareCommand, lambert::cli::addScenesCommand,
                         lambert::cli::addInfoCommand, lambert::cli::addGenerateCommand,
                         lambert::cli::addViewCommand, lambert::cli::addReportCommand, lambert::cli::addDaylightCommand}) {
    std::function<int()> run = add(app);
    commands.emplace_back(app.get_subcommands({}).back(), std::move(run));
  }
  CLI11_PARSE(app, argc, argv);
  std::unique_ptr<tbb::global_control> threadLimit;
  if (threads > 0) threadLimit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
  for (auto& [command, run] : commands)
    if (command->parsed()) return run();
  return 2;
}
