// The smallest program against liblambert: build the engine, solve, read vertex radiance.
#include <cstdio>

#include "lambert/lambert.h"

int main() {
  lambert::RadiosityOptions options;  // the defaults: hierarchical radiosity, as `lambert solve` runs it
  auto engine = lambert::Radiosity::create(lambert::cornellBox(), options);
  if (!engine) return std::fprintf(stderr, "%s\n", engine.error().message.c_str()), 1;
  if (auto solved = (*engine)->solve(); !solved) return std::fprintf(stderr, "%s\n", solved.error().message.c_str()), 1;
  const lambert::SolutionView& solution = (*engine)->solution();
  std::vector<lambert::Rgb> radiance = solution.vertexRadiance();  // L = B/π, W/(m²·sr)
  lambert::Rgb mean;
  for (const lambert::Rgb& l : radiance) mean += l / static_cast<double>(radiance.size());
  std::printf("%zu vertices, mean radiance %.4f %.4f %.4f W/(m2 sr)\n", radiance.size(), mean.r, mean.g, mean.b);
}
