// viewer_bench: `lambert view` on the Cornell box with its two spotlights turning, in a real
// window (Xvfb and Mesa's software OpenGL where there is no display), as JSON. The issue's
// targets, on a 2-core machine: at 5,000 patches and 1280×720, at least 30 frames drawn per
// second while the spots move, and the radiosity updated at least 60 times per second on its
// thread; the viewer's own time per frame is reported apart from the solve's.
//
// Then lightmap mode (`--lightmaps`) on the same scene with the hierarchical method:
// the frame time while the lightmapped faces are drawn, and, for a few aims of the warm spot,
// the time from the light's move to the lightmaps baked for it on screen (the radiosity thread
// re-solves warm and re-bakes; the lightmaps are drawn from float textures).
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include "bench_common.h"

namespace {

using Json = nlohmann::ordered_json;
using namespace lambert::bench;

struct Options {
  std::size_t patches = 5000;
  int width = 1280, height = 720;
  int frames = 300;
  int lightmapSize = 256;
  int lightMoves = 3;
};

// Runs a command and gives its exit code and stdout (stderr passes through).
std::pair<int, std::string> capture(const std::string& command) {
  std::string output;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {-1, output};
  std::array<char, 4096> buffer;
  while (std::size_t n = fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  bool quick = false;
  CLI::App app{"viewer_bench: frames and radiosity updates per second of `lambert view` while spotlights move, as JSON"};
  app.add_option("--patches", options.patches, "Patches of the Cornell box's uniform mesh")->capture_default_str();
  app.add_option("--width", options.width, "Window width")->capture_default_str();
  app.add_option("--height", options.height, "Window height")->capture_default_str();
  app.add_option("--frames", options.frames, "Frames drawn while the spots move")->capture_default_str();
  app.add_option("--lightmap-size", options.lightmapSize, "Lightmap mode: texels per side of the atlas")->capture_default_str();
  app.add_option("--light-moves", options.lightMoves, "Lightmap mode: moves of the spot timed to their lightmaps on screen")->capture_default_str();
  app.add_flag("--quick", quick, "1,000 patches, 60 frames, 128² lightmaps, 2 moves (a few seconds)");
  parseOrExit(app, argc, argv);
  if (quick) options.patches = 1000, options.frames = 60, options.lightmapSize = 128, options.lightMoves = 2;

  Json doc;
  doc["benchmark"] = "viewer";
  doc["machine"] = cpuModel() + " (" + std::to_string(std::thread::hardware_concurrency()) + " hardware threads)";
  doc["date"] = utcNow();
  doc["build"] = buildDescription();
  doc["load_average_at_start"] = loadAverage();
  doc["settings"] = {{"scene", "cornell-spots"}, {"patches", options.patches}, {"width", options.width}, {"height", options.height},
                     {"frames_while_moving", options.frames}, {"lightmap_size", options.lightmapSize}, {"light_moves", options.lightMoves}};

  // Without a display of its own, the viewer draws under Xvfb; with neither, say so and stop.
  const bool display = std::getenv("DISPLAY") != nullptr;
  const bool xvfb = std::system("command -v xvfb-run > /dev/null 2>&1") == 0;
  if (!display && !xvfb) {
    doc["skipped"] = "no display and no xvfb-run (Debian xvfb): the viewer needs an X server";
    std::printf("%s\n", doc.dump(2).c_str());
    return 0;
  }
  const std::filesystem::path script = std::filesystem::temp_directory_path() / ("lambert-viewer-bench-" + std::to_string(getpid()) + ".txt");
  std::ofstream(script) << "wait-converged 600\nplay\nframes " << options.frames << "\n";
  const std::string command = std::string(display ? "" : "xvfb-run -a -s '-screen 0 1920x1080x24' ") + LAMBERT_CLI_PATH +
                              " view --scene cornell-spots --patches " + std::to_string(options.patches) + " --width " +
                              std::to_string(options.width) + " --height " + std::to_string(options.height) + " --script " +
                              script.string() + " --json";
  std::fprintf(stderr, "viewer_bench: %s\n", command.c_str());
  auto [code, output] = capture(command);
  std::filesystem::remove(script);
  Json viewer = Json::parse(output, nullptr, false);
  if (code != 0 || viewer.is_discarded()) {
    std::fprintf(stderr, "viewer_bench: the viewer failed (exit %d):\n%s\n", code, output.c_str());
    return 1;
  }
  const double fps = viewer.value("playing_frames_per_second", 0.0), updates = viewer.value("playing_light_updates_per_second", 0.0);
  doc["display"] = display ? "DISPLAY" : "Xvfb (Mesa software OpenGL)";
  doc["frames_per_second_while_moving"] = roundDigits(fps, 2);
  doc["radiosity_updates_per_second_while_moving"] = roundDigits(updates, 2);
  doc["viewer_ms_per_frame"] = viewer.value("frame_cpu_ms_mean", 0.0);
  doc["update_solve_ms_mean"] = viewer.value("update_solve_ms_mean", 0.0);
  doc["update_snapshot_ms_mean"] = viewer.value("update_snapshot_ms_mean", 0.0);
  doc["viewer"] = viewer;

  // Lightmap mode: the first bake, frames, then the warm spot aimed at points across the floor,
  // each waited for until its lightmaps are on screen, then frames again.
  std::ofstream lightmapScript(script);
  lightmapScript << "exposure 0\nwait-lightmaps 600\nframes " << options.frames / 2 << "\n";
  const double aims[][2] = {{120, 120}, {420, 420}, {150, 420}, {400, 150}, {278, 280}};
  for (int k = 0; k < options.lightMoves; ++k)
    lightmapScript << "light 0 aim " << aims[k % 5][0] << " 0 " << aims[k % 5][1] << "\nwait-lightmaps 600\n";
  lightmapScript << "frames " << options.frames / 2 << "\n";
  lightmapScript.close();
  const std::string lightmapCommand = std::string(display ? "" : "xvfb-run -a -s '-screen 0 1920x1080x24' ") + LAMBERT_CLI_PATH +
                                      " view --scene cornell-spots --lightmaps --lightmap-size " + std::to_string(options.lightmapSize) +
                                      " --width " + std::to_string(options.width) + " --height " + std::to_string(options.height) +
                                      " --script " + script.string() + " --json";
  std::fprintf(stderr, "viewer_bench: %s\n", lightmapCommand.c_str());
  auto [lightmapCode, lightmapOutput] = capture(lightmapCommand);
  std::filesystem::remove(script);
  Json lightmapViewer = Json::parse(lightmapOutput, nullptr, false);
  if (lightmapCode != 0 || lightmapViewer.is_discarded()) {
    std::fprintf(stderr, "viewer_bench: the viewer failed in lightmap mode (exit %d):\n%s\n", lightmapCode, lightmapOutput.c_str());
    return 1;
  }
  doc["lightmaps"] = {
      {"method", "hierarchical"},
      {"frame_ms_mean", roundDigits(lightmapViewer.value("lightmap_frame_ms_mean", 0.0), 3)},
      {"viewer_ms_per_frame", roundDigits(lightmapViewer.value("lightmap_frame_cpu_ms_mean", 0.0), 3)},
      {"frames", lightmapViewer.value("lightmap_frames", 0)},
      {"bake_ms_mean", roundDigits(lightmapViewer.value("lightmap_bake_ms_mean", 0.0), 1)},
      {"bakes", lightmapViewer.value("lightmap_bakes", 0)},
      {"texture_upload_ms_max", roundDigits(lightmapViewer.value("lightmap_upload_ms_max", 0.0), 3)},
      {"light_move_to_screen_ms_mean", roundDigits(lightmapViewer.value("lightmap_move_to_screen_ms_mean", 0.0), 1)},
      {"light_move_to_screen_ms_max", roundDigits(lightmapViewer.value("lightmap_move_to_screen_ms_max", 0.0), 1)},
      {"light_moves_timed", lightmapViewer.value("lightmap_light_moves", 0)},
      {"elements", lightmapViewer.value("elements", 0)},
      {"viewer", lightmapViewer}};

  const bool targetSize = options.patches >= 5000 && options.width >= 1280 && options.height >= 720;
  doc["target"] = {{"frames_per_second_min", 30},
                   {"updates_per_second_min", 60},
                   {"met", targetSize ? Json(fps >= 30 && updates >= 60) : Json(nullptr)}};
  std::printf("%s\n", doc.dump(2).c_str());
  return 0;
}
