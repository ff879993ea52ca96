// Reads a light-probe file that `lambert solve --probes` wrote and prints the irradiance a surface
// with normal n receives at point p: the L2 spherical-harmonic irradiance of the eight probes
// around p, blended trilinearly over those of them that are valid (probes inside geometry are
// left out and the weights of the rest renormalised), clamped at zero. A point outside the grid
// takes the nearest place on it.
//
//   read_probes room.probes  px py pz  nx ny nz
//
// This program uses the file format alone (docs/lightmaps.md, "Light probes"), not lambert's
// library, as an engine's loader would: 64-byte little-endian header, one validity byte per probe
// padded to a multiple of 4, then 27 float32 per probe (9 coefficients, each r, g, b).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

namespace {

struct ProbeFile {
  double origin[3] = {};
  double spacing = 0;
  std::uint32_t dims[3] = {};
  std::vector<std::uint8_t> valid;
  std::vector<float> coefficients;  // 27 per probe
};

std::uint32_t u32(const std::uint8_t* p) {
  return p[0] | p[1] << 8 | p[2] << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}
double f64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int k = 0; k < 8; ++k) v |= static_cast<std::uint64_t>(p[k]) << (8 * k);
  double d;
  std::memcpy(&d, &v, sizeof d);
  return d;
}
float f32(const std::uint8_t* p) {
  const std::uint32_t v = u32(p);
  float f;
  std::memcpy(&f, &v, sizeof f);
  return f;
}

bool load(const char* path, ProbeFile& file) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "%s: cannot open\n", path);
    return false;
  }
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 64 || std::memcmp(bytes.data(), "LMBPROBE", 8) != 0 || u32(&bytes[8]) != 1 || u32(&bytes[12]) != 9) {
    std::fprintf(stderr, "%s: not a version 1 lambert probe file\n", path);
    return false;
  }
  for (int a = 0; a < 3; ++a) file.origin[a] = f64(&bytes[16 + 8 * a]);
  file.spacing = f64(&bytes[40]);
  std::uint64_t n = 1;
  for (int a = 0; a < 3; ++a) n *= file.dims[a] = u32(&bytes[48 + 4 * a]);
  const std::uint64_t flags = (n + 3) / 4 * 4;
  if (n == 0 || n > (1u << 24) || !(file.spacing > 0) || bytes.size() != 64 + flags + 27 * 4 * n) {
    std::fprintf(stderr, "%s: its size does not match its header\n", path);
    return false;
  }
  file.valid.assign(bytes.begin() + 64, bytes.begin() + 64 + static_cast<std::ptrdiff_t>(n));
  file.coefficients.resize(27 * n);
  for (std::uint64_t i = 0; i < 27 * n; ++i) file.coefficients[i] = f32(&bytes[64 + flags + 4 * i]);
  return true;
}

// E(n) = Σ_k c_k Y_k(n), the real SH basis in lambert's order (k = l² + l + m).
std::array<double, 3> irradiance(const float* c, double x, double y, double z) {
  const double basis[9] = {0.282095, 0.488603 * y, 0.488603 * z, 0.488603 * x, 1.092548 * x * y,
                           1.092548 * y * z, 0.315392 * (3 * z * z - 1), 1.092548 * x * z, 0.546274 * (x * x - y * y)};
  std::array<double, 3> e{};
  for (int k = 0; k < 9; ++k)
    for (int ch = 0; ch < 3; ++ch) e[ch] += c[3 * k + ch] * basis[k];
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 8) {
    std::fprintf(stderr, "usage: %s FILE.probes px py pz nx ny nz\n", argv[0]);
    return 2;
  }
  ProbeFile file;
  if (!load(argv[1], file)) return 1;
  double p[3], n[3];
  for (int a = 0; a < 3; ++a) p[a] = std::atof(argv[2 + a]), n[a] = std::atof(argv[5 + a]);
  const double norm = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(norm > 0)) {
    std::fprintf(stderr, "the normal must not be zero\n");
    return 2;
  }
  for (double& v : n) v /= norm;

  // The cell holding p (clamped onto the grid) and p's place in it.
  std::uint32_t lo[3];
  double t[3];
  for (int a = 0; a < 3; ++a) {
    const double g = std::fmin(std::fmax((p[a] - file.origin[a]) / file.spacing, 0.0), file.dims[a] - 1.0);
    lo[a] = std::min(static_cast<std::uint32_t>(g), file.dims[a] > 1 ? file.dims[a] - 2 : 0u);
    t[a] = file.dims[a] > 1 ? g - lo[a] : 0;
  }
  std::array<double, 3> sum{};
  double weights = 0;
  for (int corner = 0; corner < 8; ++corner) {
    std::uint32_t index[3];
    double w = 1;
    for (int a = 0; a < 3; ++a) {
      const int step = corner >> a & 1;
      if (step && file.dims[a] == 1) w = 0;
      index[a] = lo[a] + static_cast<std::uint32_t>(step);
      w *= step ? t[a] : 1 - t[a];
    }
    if (w <= 0) continue;
    const std::uint64_t probe = index[0] + static_cast<std::uint64_t>(file.dims[0]) * (index[1] + static_cast<std::uint64_t>(file.dims[1]) * index[2]);
    if (!file.valid[probe]) continue;
    const std::array<double, 3> e = irradiance(&file.coefficients[27 * probe], n[0], n[1], n[2]);
    for (int ch = 0; ch < 3; ++ch) sum[ch] += w * e[ch];
    weights += w;
  }
  if (weights <= 0) {
    std::printf("no valid probe around (%g, %g, %g): the point is inside geometry\n", p[0], p[1], p[2]);
    return 1;
  }
  // L2 irradiance rings below zero facing a dark region opposite a bright one: no light is negative.
  for (double& e : sum) e = std::fmax(e, 0.0);
  std::printf("irradiance %.6g %.6g %.6g W/m^2 (RGB) at (%g, %g, %g), normal (%g, %g, %g)\n", sum[0] / weights,
              sum[1] / weights, sum[2] / weights, p[0], p[1], p[2], n[0], n[1], n[2]);
  return 0;
}
