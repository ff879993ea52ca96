// A spotlight swept across the Cornell box's back wall, as an interactive program moves a light:
// the mesh and form factors are made once, and each frame sets the light where it is now and
// re-solves warm from the previous frame within a fixed budget of shots. Prints each frame's
// mean radiance and solve time; exits 1 if a value is not finite or the lit patch of the back
// wall does not follow the spot.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "lambert/lambert.h"

namespace {

constexpr int kFrames = 5;
constexpr double kFirstAimX = 140, kAimStepX = 70;  // mm, across the back wall (x = 0 green, 556 red)
constexpr double kBackWallZ = 559.2, kAimY = 400;   // aimed above the tall block (its top is at 330)

// The area-weighted centre of the back wall's lit patch: its elements brighter than half the
// brightest. The spot's direct light dominates there, so this follows the spot's aim.
double litCentreX(const lambert::SolutionView& solution, std::size_t backWall) {
  const lambert::Mesh& mesh = solution.mesh();
  const std::vector<lambert::Rgb>& radiosity = solution.radiosity();
  double brightest = 0;
  for (std::size_t i = 0; i < mesh.numPatches(); ++i)
    if (mesh.patches[i].surface == backWall) brightest = std::max(brightest, radiosity[i].luminance());
  double weightedX = 0, area = 0;
  for (std::size_t i = 0; i < mesh.numPatches(); ++i)
    if (mesh.patches[i].surface == backWall && radiosity[i].luminance() > 0.5 * brightest) {
      weightedX += mesh.patches[i].area * mesh.patches[i].centroid.x;
      area += mesh.patches[i].area;
    }
  return area > 0 ? weightedX / area : std::nan("");
}

}  // namespace

int main() {
  // cornell-spots: the Cornell box with its ceiling light dark; one of its spots, moved to the
  // front below the ceiling, is the light that sweeps.
  lambert::Scene scene = lambert::cornellBoxWithSpots();
  lambert::Light spot = scene.lights.front();
  spot.position = {278, 520, 60};
  spot.angularVelocity = {};
  std::size_t backWall = scene.surfaces.size();
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s)
    if (scene.surfaces[s].name == "back wall") backWall = s;
  if (backWall == scene.surfaces.size()) return std::fprintf(stderr, "moving_light: scene '%s' has no back wall\n", scene.name.c_str()), 1;

  auto aimedAt = [&spot](int frame) {
    lambert::Light light = spot;
    const lambert::Vec3 target{kFirstAimX + kAimStepX * frame, kAimY, kBackWallZ};
    light.direction = lambert::normalize(target - spot.position);
    return light;
  };
  scene.lights = {aimedAt(0)};

  // Progressive shooting keeps the power it has not shot yet between frames, so a budget of
  // shots per frame gives an up-to-date direct light at once and the bounces over the frames.
  lambert::RadiosityOptions options;
  options.meshing = lambert::MeshStrategy::Uniform;  // shooting is for the flat methods
  options.uniform.targetPatches = 784;
  options.solver = lambert::SolverKind::Shooting;
  auto engine = lambert::Radiosity::create(scene, options);
  if (!engine) return std::fprintf(stderr, "moving_light: %s\n", engine.error().message.c_str()), 1;
  // Frame 0 is solved in full: the warm start the later frames build on, each within the budget.
  const lambert::SolveBudget budget{.maxShots = 300};
  double previousX = 0;
  for (int frame = 0; frame < kFrames; ++frame) {
    (*engine)->setLights({aimedAt(frame)});
    const auto start = std::chrono::steady_clock::now();
    auto report = (*engine)->solve(frame == 0 ? lambert::SolveBudget{} : budget);
    const double milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!report) return std::fprintf(stderr, "moving_light: frame %d: %s\n", frame, report.error().message.c_str()), 1;

    const lambert::SolutionView& solution = (*engine)->solution();
    const std::vector<lambert::Rgb> radiance = solution.vertexRadiance();  // L = B/π, W/(m²·sr)
    lambert::Rgb mean;
    for (const lambert::Rgb& l : radiance) {
      if (!std::isfinite(l.r) || !std::isfinite(l.g) || !std::isfinite(l.b))
        return std::fprintf(stderr, "moving_light: frame %d: a vertex radiance is not finite\n", frame), 1;
      mean += l / static_cast<double>(radiance.size());
    }
    const double x = litCentreX(solution, backWall);
    std::printf("frame %d: spot aimed at x = %.0f mm, lit centre x = %.0f mm, mean radiance %.4g %.4g %.4g W/(m2 sr), "
                "solve %.1f ms (%lld shots, unshot %.2g)\n",
                frame, kFirstAimX + kAimStepX * frame, x, mean.r, mean.g, mean.b, milliseconds, report->iterations,
                report->unshotFraction);
    if (!std::isfinite(x)) return std::fprintf(stderr, "moving_light: frame %d: no lit patch on the back wall\n", frame), 1;
    // The lit patch must move with the aim, by a good part of the step (the mesh is coarse).
    if (frame > 0 && x - previousX < kAimStepX / 3)
      return std::fprintf(stderr, "moving_light: frame %d: the lit centre moved from x = %.0f to %.0f mm, the spot by %.0f mm\n",
                          frame, previousX, x, kAimStepX),
             1;
    previousX = x;
  }
  return 0;
}
