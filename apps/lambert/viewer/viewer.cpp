#include "viewer/viewer.h"

// The window and its loop: each frame takes the solve thread's latest snapshot, runs the script
// (viewer/script_player.h), takes the user's input (the camera, viewer/view_camera.h; a click picks
// a light, viewer/picking.h), sends edited lights to the solve thread, draws the scene and the
// panel (viewer/panel.h), and takes screenshots; then the figures for --json.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include "lambert/core/timer.h"
#include "lambert/io/png.h"
#include "viewer/baked_renderer.h"
#include "viewer/panel.h"
#include "viewer/picking.h"
#include "viewer/script_player.h"
#include "viewer/viewer_state.h"

namespace lambert::viewer {
namespace {

// The framebuffer's pixels, top row first, as the PNG writer wants them.
Status saveScreenshot(const std::string& path, int width, int height) {
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  std::vector<std::uint8_t> flipped(pixels.size());
  const std::size_t row = static_cast<std::size_t>(width) * 3;
  for (int y = 0; y < height; ++y)
    std::copy_n(pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(height - 1 - y) * row), row,
                flipped.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * row));
  return writePng(path, width, height, flipped);
}

std::string glfwMessage;
void onGlfwError(int, const char* description) { glfwMessage = description; }

// Figures over a span of frames.
struct FrameFigures {
  long long frames = 0;
  double seconds = 0, cpuSeconds = 0, uploadSeconds = 0;
};

}  // namespace

Status runViewer(const ViewerOptions& options, Stats& stats) {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit())
    return Error{"no display: GLFW could not start (" + glfwMessage + "); run it in a desktop session, or headless under xvfb-run"};
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, options.msaaSamples);
  GLFWwindow* window = glfwCreateWindow(options.width, options.height, ("lambert — " + options.scene.name).c_str(), nullptr, nullptr);
  if (!window) {
    glfwTerminate();
    return Error{"cannot open an OpenGL 3.3 core window (" + glfwMessage + ")"};
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(options.vsync ? 1 : 0);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the user's directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");

  Status result = Ok{};
  {
    Result<std::unique_ptr<MeshRenderer>> renderer = MeshRenderer::create();
    Result<std::unique_ptr<BakedRenderer>> bakedRenderer = Error{"no OpenGL programs"};
    if (renderer) bakedRenderer = BakedRenderer::create(options.scene);
    if (!renderer) {
      result = renderer.error();
    } else if (!bakedRenderer) {
      result = bakedRenderer.error();
    } else {
      ViewerState state;
      state.camera.camera = options.scene.camera;
      state.display = options.display;
      state.animation.base = options.scene.lights;
      state.animation.setAt = steadyClockSeconds();
      state.sphereCentre = options.sphereCentre;
      state.lightmapsAvailable = options.radiosity.meshing == MeshStrategy::Hierarchical;
      if (!state.lightmapsAvailable) state.display.lightmaps = false;
      const Bounds bounds = sceneBounds(options.scene);
      const double diagonal = length(bounds.hi - bounds.lo);

      BakeSettings bake = options.bake;
      bake.lightmaps = state.display.lightmaps;
      bake.probes = state.display.probes;
      SolveWorker worker(options.scene, options.radiosity, options.budget, state.display.flat, bake);
      std::shared_ptr<const LightmapFrame> lightmaps;
      std::shared_ptr<const ProbeFrame> probes;
      // What the last frame showed (swapped): script waits end on what is on screen.
      std::shared_ptr<const LightmapFrame> lightmapsOnScreen;
      std::shared_ptr<const ProbeFrame> probesOnScreen;
      // From a change of the lights to the lightmaps (probes) baked for them on screen.
      double lightsChangedAt = -1;
      bool lightmapsAwaited = false, probesAwaited = false;
      struct Latency {
        long long count = 0;
        double sum = 0, max = 0;
        void add(double seconds) { count += 1, sum += seconds, max = std::max(max, seconds); }
      } lightmapLatency, probeLatency;
      double lightmapUploadSeconds = 0;
      std::shared_ptr<const Snapshot> shown = previewSnapshot(options.scene);
      ScriptPlayer player;
      player.script = options.script ? &*options.script : nullptr;
      LightAnimation sentAnimation = state.animation;

      FrameFigures all, playing, lightmapped;
      Timer clock;
      double lastTime = clock.seconds();
      bool firstSolutionShown = false;
      double firstSolutionSeconds = 0, convergedSeconds = 0;
      while (!glfwWindowShouldClose(window)) {
        const double frameStart = clock.seconds();
        const double dt = frameStart - lastTime;
        lastTime = frameStart;
        glfwPollEvents();
        Timer cpu;

        if (std::string error = worker.error(); !error.empty()) {
          result = Error{error};
          break;
        }
        if (std::shared_ptr<const Snapshot> latest = worker.latest(); latest && latest != shown) {
          shown = latest;
          if (!firstSolutionShown) firstSolutionShown = true, firstSolutionSeconds = clock.seconds();
        }
        if (state.display.autoExposure && !shown->preview) state.display.exposure = shown->autoExposureStops;
        const std::vector<Light> currentLights = state.animation.lightsAt(steadyClockSeconds());
        const bool upToDate = !shown->preview && shown->lights == currentLights;
        lightmaps = worker.latestLightmaps();
        probes = worker.latestProbes();
        const bool lightmapsUpToDate = lightmapsOnScreen && lightmapsOnScreen->lights == currentLights;
        const bool probesUpToDate = probesOnScreen && probesOnScreen->lights == currentLights;
        if (upToDate && shown->settled && convergedSeconds == 0) convergedSeconds = clock.seconds();

        // The script: run commands until one waits.
        Screenshot screenshot;  // asked for by the script in this frame
        if (player.active()) {
          using W = ScriptPlayer::Waiting;
          if (player.waiting == W::Frames && player.framesLeft <= 0) player.waiting = W::None;
          if (player.waiting == W::Solution && !shown->preview) player.waiting = W::None;
          if (player.waiting == W::Converged && upToDate && shown->settled) player.waiting = W::None;
          if (player.waiting == W::Lightmaps && lightmapsUpToDate) player.waiting = W::None;
          if (player.waiting == W::Probes && probesUpToDate) player.waiting = W::None;
          if (player.waiting != W::None && player.waiting != W::Frames && player.waitTimer.seconds() > player.timeout) {
            const char* what = player.waiting == W::Solution    ? "no solution"
                               : player.waiting == W::Converged ? "not converged"
                               : player.waiting == W::Lightmaps ? "no lightmaps for these lights"
                                                                : "no probes for these lights";
            result = Error{player.where() + ": " + what + " within " + std::to_string(player.timeout) + " s"};
            break;
          }
          while (player.waiting == W::None && screenshot.path.empty() && player.next < player.script->lines.size()) {
            player.current = player.next++;
            if (Status ok = applyCommand(player.script->lines[player.current].step, state, player, screenshot); !ok) {
              result = Error{player.where() + ": " + ok.error().message};
              break;
            }
          }
          if (!result) break;
          if (player.finished() && screenshot.path.empty()) break;
        }

        // Input the panel does not take: orbit/turn, pan, dolly, fly, pick a light.
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        ImGuiIO& io = ImGui::GetIO();
        int fbWidth = 0, fbHeight = 0;
        glfwGetFramebufferSize(window, &fbWidth, &fbHeight);
        fbWidth = std::max(fbWidth, 1), fbHeight = std::max(fbHeight, 1);
        const double aspect = static_cast<double>(fbWidth) / fbHeight;
        const Eigen::Matrix4f viewProjection = state.camera.projection(aspect, bounds.lo, bounds.hi) * state.camera.view();
        int winWidth = 0, winHeight = 0;
        glfwGetWindowSize(window, &winWidth, &winHeight);
        if (!io.WantCaptureMouse) {
          // ImGui's mouse state, which keeps a click shorter than a frame.
          const double scale = kPi / std::max(winHeight, 1);
          const bool moved = io.MouseDragMaxDistanceSqr[0] > 9 || io.MouseDragMaxDistanceSqr[1] > 9 || io.MouseDragMaxDistanceSqr[2] > 9;
          if (io.MouseDown[0] && moved) state.camera.turn(-io.MouseDelta.x * scale, -io.MouseDelta.y * scale);
          if ((io.MouseDown[1] || io.MouseDown[2]) && moved) state.camera.pan(io.MouseDelta.x / std::max(winHeight, 1), io.MouseDelta.y / std::max(winHeight, 1));
          if (ImGui::IsMouseReleased(0) && io.MouseDragMaxDistanceSqr[0] <= 9)
            state.selectedLight = pickLight(state.animation.base, viewProjection, io.MousePos.x, io.MousePos.y, winWidth, winHeight);
          if (io.MouseWheel != 0) state.camera.dolly(std::pow(0.9, io.MouseWheel));
        }
        const bool screenshotKey = std::exchange(state.screenshotRequested, false);
        if (!io.WantCaptureKeyboard) {
          const double speed = diagonal * 0.4 * dt * (glfwGetKey(window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ? 4 : 1);
          const Vec3 f = state.camera.forward(), r = state.camera.right(), u = normalize(state.camera.camera.up);
          const std::pair<int, Vec3> keys[] = {{GLFW_KEY_W, f}, {GLFW_KEY_S, -f}, {GLFW_KEY_D, r}, {GLFW_KEY_A, -r}, {GLFW_KEY_E, u}, {GLFW_KEY_Q, -u}};
          for (const auto& [key, direction] : keys)
            if (glfwGetKey(window, key) == GLFW_PRESS) state.camera.move(direction * speed);
          if (state.display.probes) {
            // The probe sphere: arrows move it over the ground (right and forward as the camera
            // looks), Page Up and Page Down along the up axis.
            const Vec3 ahead = normalize(f - u * dot(f, u));
            const std::pair<int, Vec3> sphereKeys[] = {{GLFW_KEY_RIGHT, r}, {GLFW_KEY_LEFT, -r}, {GLFW_KEY_UP, ahead}, {GLFW_KEY_DOWN, -ahead},
                                                       {GLFW_KEY_PAGE_UP, u}, {GLFW_KEY_PAGE_DOWN, -u}};
            for (const auto& [key, direction] : sphereKeys)
              if (glfwGetKey(window, key) == GLFW_PRESS) state.sphereCentre += direction * (speed * 0.5);
          }
          if (ImGui::IsKeyPressed(GLFW_KEY_F12)) state.screenshotRequested = true;
          if (ImGui::IsKeyPressed(GLFW_KEY_SPACE) && !state.animation.base.empty()) setPlaying(state.animation, !state.animation.playing);
        }

        // Edited lights and play/pause go to the radiosity thread, which re-injects and re-solves
        // warm, and while playing moves the lights itself at its own rate.
        if (!(state.animation == sentAnimation)) {
          worker.setAnimation(state.animation);
          sentAnimation = state.animation;
          lightsChangedAt = clock.seconds();
          lightmapsAwaited = probesAwaited = true;
        }
        worker.setFlat(state.display.flat);
        worker.setBaking(state.display.lightmaps, state.display.probes);

        // The 3-D view; screenshots take it before the panel is drawn over it.
        glViewport(0, 0, fbWidth, fbHeight);
        glClearColor(0, 0, 0, 1);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        DisplaySettings display = state.display;
        const bool capture = (!screenshot.path.empty() && !screenshot.withPanels) || screenshotKey;
        display.lightMarkers = !capture;
        Timer upload;
        renderer.value()->upload(*shown);
        const double uploadSeconds = upload.seconds();
        const Eigen::Vector3f eye = toFloat(state.camera.camera.eye);
        const bool drawLightmaps = display.lightmaps && lightmaps;
        if (drawLightmaps) {
          Timer lightmapUpload;
          bakedRenderer.value()->upload(*lightmaps);
          lightmapUploadSeconds = std::max(lightmapUploadSeconds, lightmapUpload.seconds());
          bakedRenderer.value()->drawLightmapped(*lightmaps, viewProjection, display);
        } else {
          DisplaySettings meshDisplay = display;
          meshDisplay.lightMarkers = false;  // drawn last, over the sphere too
          renderer.value()->draw(*shown, viewProjection, eye, meshDisplay, options.scene.metresPerUnit, state.selectedLight, diagonal * 0.004);
        }
        std::optional<ShRgb> sphereSh;
        if (display.probes && probes) {
          sphereSh = probes->volume.irradianceShAt(state.sphereCentre);
          if (sphereSh)
            bakedRenderer.value()->drawSphere(*sphereSh, state.sphereCentre, options.sphereRadius, options.sphereAlbedo, viewProjection, display);
        }
        if (display.lightMarkers) renderer.value()->drawLightMarkers(shown->lights, viewProjection, state.selectedLight, diagonal * 0.004);
        // F12 and `screenshot` take the 3-D view alone; `screenshot-window` the panels too.
        auto save = [&](const std::string& path) {
          if (Status saved = saveScreenshot(path, fbWidth, fbHeight); !saved)
            result = Error{(player.active() ? player.where() + ": " : "") + saved.error().message};
          else if (screenshotKey)
            std::fprintf(stderr, "lambert view: wrote %s\n", path.c_str());
        };
        if (capture) save(screenshot.path.empty() ? "lambert-screenshot.png" : screenshot.path);
        if (!result) break;

        drawPanel(state, *shown, worker, options, lightmaps.get(), probes.get(), sphereSh.has_value());
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if (screenshot.withPanels) save(screenshot.path);
        if (!result) break;
        const double cpuSeconds = cpu.seconds();
        glfwSwapBuffers(window);
        // On screen once swapped: a light change's lightmaps and probes.
        lightmapsOnScreen = drawLightmaps ? lightmaps : nullptr;
        probesOnScreen = sphereSh ? probes : nullptr;
        // (The lights as they are now: a script may have changed them since the frame began.)
        if (lightmapsAwaited || probesAwaited) {
          const std::vector<Light> drawnFor = state.animation.lightsAt(steadyClockSeconds());
          if (lightmapsAwaited && drawLightmaps && lightmaps->lights == drawnFor)
            lightmapLatency.add(clock.seconds() - lightsChangedAt), lightmapsAwaited = false;
          if (probesAwaited && sphereSh && probes->lights == drawnFor) probeLatency.add(clock.seconds() - lightsChangedAt), probesAwaited = false;
        }

        for (FrameFigures* f : {&all, state.animation.playing ? &playing : nullptr, drawLightmaps ? &lightmapped : nullptr}) {
          if (!f) continue;
          f->frames += 1;
          f->seconds += clock.seconds() - frameStart;
          f->cpuSeconds += cpuSeconds;
          f->uploadSeconds += uploadSeconds;
        }
        if (player.active() && player.waiting == ScriptPlayer::Waiting::Frames) player.framesLeft -= 1;
        if (player.finished()) break;
      }

      WorkerFigures worker_;
      Stats engineStats = worker.finish(worker_);
      stats.append(engineStats);
      stats.add("frames", "frames drawn", static_cast<std::int64_t>(all.frames));
      stats.add("frames_per_second", "frames per second", all.seconds > 0 ? all.frames / all.seconds : 0.0, "/s");
      stats.add("frame_cpu_ms_mean", "viewer's own time per frame (input, upload, draw calls, panel)",
                all.frames ? 1e3 * all.cpuSeconds / all.frames : 0.0, "ms");
      stats.add("upload_ms_mean", "snapshot upload per frame", all.frames ? 1e3 * all.uploadSeconds / all.frames : 0.0, "ms");
      if (lightmapped.frames > 0) {
        stats.add("lightmap_frames", "frames drawn with lightmaps", static_cast<std::int64_t>(lightmapped.frames));
        stats.add("lightmap_frame_ms_mean", "frame time with lightmaps (mean)", 1e3 * lightmapped.seconds / lightmapped.frames, "ms");
        stats.add("lightmap_frame_cpu_ms_mean", "viewer's own time per frame with lightmaps", 1e3 * lightmapped.cpuSeconds / lightmapped.frames, "ms");
      }
      if (playing.frames > 0) {
        stats.add("playing_frames", "frames while the lights moved", static_cast<std::int64_t>(playing.frames));
        stats.add("playing_frames_per_second", "frames per second while the lights moved", playing.frames / playing.seconds, "/s");
        stats.add("playing_light_updates_per_second", "radiosity updates per second while the lights moved",
                  worker_.lightUpdates / playing.seconds, "/s");
      }
      stats.add("updates", "radiosity updates", static_cast<std::int64_t>(worker_.updates));
      stats.add("update_solve_ms_mean", "radiosity update: inject + solve (mean)",
                worker_.updates ? 1e3 * worker_.solveSeconds / worker_.updates : 0.0, "ms");
      stats.add("update_snapshot_ms_mean", "radiosity update: vertex values, shadows, draw arrays (mean)",
                worker_.updates ? 1e3 * worker_.snapshotSeconds / worker_.updates : 0.0, "ms");
      stats.add("update_ms_max", "radiosity update (max)", 1e3 * worker_.maxUpdateSeconds, "ms");
      stats.add("light_updates", "radiosity updates for moved lights", static_cast<std::int64_t>(worker_.lightUpdates));
      stats.add("light_update_ms_mean", "radiosity update for moved lights (mean)",
                worker_.lightUpdates ? 1e3 * worker_.lightUpdateSeconds / worker_.lightUpdates : 0.0, "ms");
      stats.add("first_solution_seconds", "first solution on screen after", firstSolutionSeconds, "s");
      if (worker_.lightmapBakes > 0) {
        stats.add("lightmap_bakes", "lightmap bakes", static_cast<std::int64_t>(worker_.lightmapBakes));
        stats.add("lightmap_bake_ms_mean", "lightmap bake (mean)", 1e3 * worker_.lightmapSeconds / worker_.lightmapBakes, "ms");
        stats.add("lightmap_upload_ms_max", "lightmap texture upload (max)", 1e3 * lightmapUploadSeconds, "ms");
      }
      if (lightmapLatency.count > 0) {
        stats.add("lightmap_light_moves", "light changes whose lightmaps reached the screen", static_cast<std::int64_t>(lightmapLatency.count));
        stats.add("lightmap_move_to_screen_ms_mean", "from a light change to its lightmaps on screen (mean)",
                  1e3 * lightmapLatency.sum / lightmapLatency.count, "ms");
        stats.add("lightmap_move_to_screen_ms_max", "from a light change to its lightmaps on screen (max)", 1e3 * lightmapLatency.max, "ms");
      }
      if (worker_.probeBakes > 0) {
        stats.add("probe_bakes", "probe volume bakes", static_cast<std::int64_t>(worker_.probeBakes));
        stats.add("probe_bake_ms_mean", "probe volume bake (mean)", 1e3 * worker_.probeSeconds / worker_.probeBakes, "ms");
      }
      if (probeLatency.count > 0)
        stats.add("probe_move_to_screen_ms_mean", "from a light change to its probes on screen (mean)", 1e3 * probeLatency.sum / probeLatency.count, "ms");
      stats.add("converged_seconds", "converged on screen after", convergedSeconds, "s");
    }
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  return result;
}

}  // namespace lambert::viewer
