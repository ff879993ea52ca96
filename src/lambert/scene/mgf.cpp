#include "lambert/scene/mgf.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <type_traits>

#include "lambert/core/warning.h"
#include "lambert/scene/gltf.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxIncludeDepth = 32;

// ---------------------------------------------------------------------------------------------
// Colour: CIE XYZ, kept at unit luminance (Y = 1) since an MGF colour is a chromaticity only.

struct Xyz {
  double x = 1, y = 1, z = 1;  // equal-energy white, MGF's default colour
};

// g(λ; μ, σ1, σ2): a Gaussian with a different width on each side of its peak (Wyman et al.).
double lobe(double lambdaNm, double mu, double sigmaBelow, double sigmaAbove) {
  const double t = (lambdaNm - mu) / (lambdaNm < mu ? sigmaBelow : sigmaAbove);
  return std::exp(-0.5 * t * t);
}

// CIE 1931 2° colour matching functions, the multi-lobe fit of Wyman, Sloan & Shirley 2013.
Xyz colourMatching(double lambdaNm) {
  return {1.056 * lobe(lambdaNm, 599.8, 37.9, 31.0) + 0.362 * lobe(lambdaNm, 442.0, 16.0, 26.7) -
              0.065 * lobe(lambdaNm, 501.1, 20.4, 26.2),
          0.821 * lobe(lambdaNm, 568.8, 46.9, 40.5) + 0.286 * lobe(lambdaNm, 530.9, 16.3, 31.1),
          1.217 * lobe(lambdaNm, 437.0, 11.8, 36.0) + 0.681 * lobe(lambdaNm, 459.0, 26.0, 13.8)};
}

// XYZ of a spectrum given as a function of wavelength (nm), integrated at 1 nm over the visible
// range 360–830 nm; unnormalised.
Xyz integrateSpectrum(const std::function<double(double)>& spectrum) {
  Xyz sum{0, 0, 0};
  for (double lambda = 360; lambda <= 830; lambda += 1) {
    const double s = spectrum(lambda);
    const Xyz cmf = colourMatching(lambda);
    sum.x += s * cmf.x;
    sum.y += s * cmf.y;
    sum.z += s * cmf.z;
  }
  return sum;
}

// Planck's spectral radiance at temperature T (K), up to a constant factor.
double planck(double lambdaNm, double kelvin) {
  constexpr double kC2 = 1.4387769e7;  // second radiation constant h·c/k in nm·K
  const double l = lambdaNm;
  return 1 / (l * l * l * l * l * (std::exp(kC2 / (l * kelvin)) - 1));
}

Rgb xyzToRec709(const Xyz& c) {
  return {3.2404542 * c.x - 1.5371385 * c.y - 0.4985314 * c.z,
          -0.9692660 * c.x + 1.8760108 * c.y + 0.0415560 * c.z,
          0.0556434 * c.x - 0.2040259 * c.y + 1.0572252 * c.z};
}

// A chromaticity as lambert RGB of Rec. 709 luminance 1, with MGF's white (E) at (1, 1, 1).
Rgb chromaticityToRgb(const Xyz& c) {
  const Rgb white = xyzToRec709(Xyz{});
  Rgb rgb = xyzToRec709(c);
  for (int k = 0; k < 3; ++k) rgb[k] = std::fmax(0.0, rgb[k] / white[k]);
  const double luminance = rgb.luminance();
  return luminance > 0 ? rgb / luminance : Rgb::gray(1);
}

// ---------------------------------------------------------------------------------------------
// Transforms: p' = A·p + t (rigid with uniform scale, possibly mirrored).

struct Affine {
  double a[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3 t;

  Vec3 point(const Vec3& p) const {
    return Vec3{a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z, a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z,
                a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z} +
           t;
  }
  // This, then `after`: after(this(p)).
  Affine then(const Affine& after) const {
    Affine r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r.a[i][j] = after.a[i][0] * a[0][j] + after.a[i][1] * a[1][j] + after.a[i][2] * a[2][j];
    r.t = after.point(t);
    return r;
  }
  Affine power(int n) const {
    Affine r;
    for (int i = 0; i < n; ++i) r = r.then(*this);
    return r;
  }
  // A mirroring transform turns a counter-clockwise polygon clockwise: faces are reversed.
  bool mirrors() const {
    const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                       a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    return det < 0;
  }
};

Affine translation(const Vec3& d) {
  Affine r;
  r.t = d;
  return r;
}
Affine rotation(int axis, double degrees) {
  const double rad = degrees * kPi / 180, c = std::cos(rad), s = std::sin(rad);
  Affine r;
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;  // the plane turned counter-clockwise
  r.a[i][i] = c;
  r.a[i][j] = -s;
  r.a[j][i] = s;
  r.a[j][j] = c;
  return r;
}
Affine scaling(double f) {
  Affine r;
  for (int i = 0; i < 3; ++i) r.a[i][i] = f;
  return r;
}
Affine mirror(int axis) {
  Affine r;
  r.a[axis][axis] = -1;
  return r;
}

// MGF's z-up to lambert's y-up: (x, y, z) → (x, z, −y), a rotation of −90° about x.
Affine zUpToYUp() {
  Affine r;
  r.a[1][1] = 0;
  r.a[1][2] = 1;
  r.a[2][1] = -1;
  r.a[2][2] = 0;
  return r;
}

// An xf argument list: a fixed part, then one array dimension per -a (its step applied 0..N−1
// times).
struct XfSpec {
  struct Part {
    Affine step;
    int count = 0;  // 0: fixed (applied once); N ≥ 1: an array dimension of N instances
  };
  std::vector<Part> parts;
  bool hasArray() const {
    return std::any_of(parts.begin(), parts.end(), [](const Part& p) { return p.count > 0; });
  }
};

// ---------------------------------------------------------------------------------------------
// Input: logical lines (continuations joined) as words, with the physical line they start on.

struct Line {
  std::vector<std::string> words;
  int number = 0;
};

struct SourceFile {
  std::string path;  // as named in messages
  fs::path directory;
  std::vector<Line> lines;
};

struct ParseError {
  std::string message;
};

std::vector<std::string> splitWords(const std::string& text) {
  std::vector<std::string> words;
  std::istringstream in(text);
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

std::optional<SourceFile> loadSource(const fs::path& path, const std::string& shownPath) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  SourceFile file;
  file.path = shownPath;
  file.directory = path.parent_path();
  std::string physical, logical;
  int number = 0, start = 0;
  while (std::getline(in, physical)) {
    ++number;
    if (!physical.empty() && physical.back() == '\r') physical.pop_back();
    if (logical.empty()) start = number;
    if (!physical.empty() && physical.back() == '\\') {
      physical.back() = ' ';  // an escaped newline counts as a space
      logical += physical;
      continue;
    }
    logical += physical;
    Line line{splitWords(logical), start};
    logical.clear();
    if (line.words.empty() || line.words[0][0] == '#') continue;
    file.lines.push_back(std::move(line));
  }
  if (!logical.empty()) {
    Line line{splitWords(logical), start};
    if (!line.words.empty() && line.words[0][0] != '#') file.lines.push_back(std::move(line));
  }
  return file;
}

// ---------------------------------------------------------------------------------------------
// Contexts.

struct VertexContext {
  Vec3 position;
  Vec3 normal;  // (0, 0, 0): none
};

struct MaterialContext {
  double rd = 0;  // photometric diffuse reflectance
  Xyz rdColour;
  double ed = 0;  // diffuse emittance, lm/m²
  Xyz edColour;
  int sides = 2;
  int version = 0;  // bumped on every change: geometry takes the material as it is then
};

class Reader {
 public:
  Reader(const MgfOptions& options, const fs::path& top) : options_(options) {
    root_ = fs::absolute(top).lexically_normal().parent_path();
    defaultObject_ = top.stem().string();
  }

  Scene read(const fs::path& top) {
    std::optional<SourceFile> file = loadSource(top, top.string());
    if (!file) throw ParseError{top.string() + ": cannot open MGF file"};
    active_.push_back(fs::weakly_canonical(top));
    runFile(*file);

    Scene scene;
    scene.name = defaultObject_;
    scene.metresPerUnit = 1;  // MGF is in metres
    scene.materials = materials_;
    DroppedFaces dropped;
    std::size_t numFaces = 0;
    for (const PolygonMesh& mesh : meshes_) {
      numFaces += mesh.faces.size();
      dropped.add(addSmoothRegions(scene, mesh, emission_, options_.regions));
    }
    if (numFaces == 0) throw ParseError{top.string() + ": no faces (lambert needs surfaces: f, sph, cyl, cone, ring, torus, prism)"};
    if (dropped.total() > 0) warning(top.string() + ": " + dropped.describe());
    if (scene.surfaces.empty()) throw ParseError{top.string() + ": every face is degenerate (" + dropped.describe() + ")"};
    scene.camera = cameraViewingScene(scene);
    // The file's own frame: z up, in metres; every point read went through zUpToYUp.
    const Affine toScene = zUpToYUp();
    for (int axis = 0; axis < 3; ++axis) scene.fileFrame.axes[axis] = {toScene.a[0][axis], toScene.a[1][axis], toScene.a[2][axis]};
    scene.fileFrame.offset = toScene.t;
    scene.fileFrame.up = {0, 0, 1};
    return scene;
  }

 private:
  const MgfOptions& options_;
  fs::path root_;
  std::string defaultObject_;
  std::vector<fs::path> active_;  // the include chain, for cycles

  std::map<std::string, VertexContext> vertices_;
  std::string currentVertex_;  // "" when none
  std::map<std::string, Xyz> colours_;
  Xyz unnamedColour_;
  std::string currentColour_;  // "": the unnamed one
  std::map<std::string, MaterialContext> namedMaterials_;
  MaterialContext unnamedMaterial_;
  std::string currentMaterial_;  // "": the unnamed one
  int unnamedResets_ = 0;

  std::vector<Affine> xf_{zUpToYUp()};  // the total transform of each open context
  std::vector<std::string> objects_;
  std::set<std::string> warnedKinds_;

  std::vector<Material> materials_;
  std::vector<Rgb> emission_;
  std::map<std::string, int> materialIndex_;  // "name#version" → index into materials_
  std::vector<PolygonMesh> meshes_;
  std::map<std::string, std::size_t> meshIndex_;

  // --- the current line, for messages ---
  const SourceFile* file_ = nullptr;
  const Line* line_ = nullptr;

  std::string where() const { return file_->path + ":" + std::to_string(line_->number); }
  [[noreturn]] void fail(const std::string& what) const { throw ParseError{where() + ": " + what}; }
  const std::string& keyword() const { return line_->words[0]; }
  std::size_t numArgs() const { return line_->words.size() - 1; }
  const std::string& arg(std::size_t i) const { return line_->words[i + 1]; }

  void expectArgs(std::size_t n) const {
    if (numArgs() != n)
      fail(keyword() + " takes " + std::to_string(n) + (n == 1 ? " argument" : " arguments") + ", not " + std::to_string(numArgs()));
  }
  void expectAtLeast(std::size_t n) const {
    if (numArgs() < n) fail(keyword() + " takes at least " + std::to_string(n) + " arguments, not " + std::to_string(numArgs()));
  }

  double number(const std::string& word) const {
    double value = 0;
    const char* begin = word.data();
    const char* end = begin + word.size();
    if (begin != end && *begin == '+') ++begin;
    auto [ptr, ec] = std::from_chars(begin, end, value);
    if (ec == std::errc::result_out_of_range) fail(keyword() + ": '" + word + "' is not a finite number");
    if (ec != std::errc() || ptr != end) fail(keyword() + ": expected a number, got '" + word + "'");
    if (!std::isfinite(value)) fail(keyword() + ": '" + word + "' is not a finite number");
    return value;
  }
  int integer(const std::string& word) const {
    const double value = number(word);
    if (value != std::floor(value) || std::fabs(value) > 1e6) fail(keyword() + ": expected an integer, got '" + word + "'");
    return static_cast<int>(value);
  }

  void warnOnce(const std::string& kind, const std::string& message) {
    if (warnedKinds_.insert(kind).second) warning(where() + ": " + message + " (further ones are not reported)");
  }

  // --- execution ---

  void runFile(const SourceFile& file) {
    const std::size_t depth = xf_.size();
    run(file, 0, file.lines.size(), depth);
    if (xf_.size() != depth) {
      file_ = &file;
      const std::size_t open = xf_.size() - depth;
      throw ParseError{file.path + ":" + std::to_string(file.lines.empty() ? 0 : file.lines.back().number) + ": unbalanced xf: " +
                       std::to_string(open) + (open == 1 ? " transformation is" : " transformations are") + " not ended"};
    }
  }

  void run(const SourceFile& file, std::size_t begin, std::size_t end, std::size_t fileDepth) {
    for (std::size_t i = begin; i < end; ++i) {
      file_ = &file;
      line_ = &file.lines[i];
      const std::string& k = keyword();
      if (k == "xf") {
        if (numArgs() == 0) {
          if (xf_.size() <= fileDepth) fail("unbalanced xf: an end with no transformation to end");
          xf_.pop_back();
          continue;
        }
        const XfSpec spec = parseXf(1);
        if (!spec.hasArray()) {
          xf_.push_back(instance(spec, {}).then(xf_.back()));
          continue;
        }
        const std::size_t close = matchingXfEnd(file, i, end);
        forEachInstance(spec, [&] { run(file, i + 1, close, xf_.size()); });
        i = close;  // its end is consumed with the array
      } else if (k == "i") {
        include(file);
      } else {
        entity();
      }
    }
  }

  std::size_t matchingXfEnd(const SourceFile& file, std::size_t open, std::size_t end) const {
    int depth = 0;
    for (std::size_t j = open; j < end; ++j) {
      const Line& l = file.lines[j];
      if (l.words[0] != "xf") continue;
      depth += l.words.size() > 1 ? 1 : -1;
      if (depth == 0) return j;
    }
    fail("unbalanced xf: an array (-a) with no xf to end it in this file");
  }

  // Runs body once per array instance of spec (the only one when it has no -a), each inside its
  // transformation context.
  void forEachInstance(const XfSpec& spec, const std::function<void()>& body) {
    std::vector<int> counts, index;
    for (const XfSpec::Part& p : spec.parts)
      if (p.count > 0) counts.push_back(p.count);
    index.assign(counts.size(), 0);
    const Affine outer = xf_.back();
    const std::size_t depth = xf_.size();
    while (true) {
      xf_.push_back(instance(spec, index).then(outer));
      body();
      xf_.resize(depth);
      std::size_t d = 0;
      while (d < counts.size() && ++index[d] == counts[d]) index[d++] = 0;
      if (d == counts.size()) break;
    }
  }

  static Affine instance(const XfSpec& spec, const std::vector<int>& index) {
    Affine total;
    std::size_t dimension = 0;
    for (const XfSpec::Part& p : spec.parts)
      total = total.then(p.count == 0 ? p.step : p.step.power(index[dimension++]));
    return total;
  }

  // The transform arguments from word `first` (1-based word index) to the end of the line.
  XfSpec parseXf(std::size_t first) const {
    XfSpec spec;
    spec.parts.push_back({});
    int repeat = 1;  // -i N: the arguments up to the next -i or -a are applied N times
    Affine repeated;
    auto closeRepeat = [&] {
      spec.parts.back().step = spec.parts.back().step.then(repeated.power(repeat));
      repeated = Affine{};
      repeat = 1;
    };
    const std::vector<std::string>& w = line_->words;
    for (std::size_t i = first; i < w.size(); ++i) {
      const std::string& flag = w[i];
      auto need = [&](std::size_t n) {
        if (i + n >= w.size()) fail("xf: " + flag + " needs " + std::to_string(n) + (n == 1 ? " value" : " values"));
      };
      if (flag == "-t") {
        need(3);
        repeated = repeated.then(translation({number(w[i + 1]), number(w[i + 2]), number(w[i + 3])}));
        i += 3;
      } else if (flag == "-rx" || flag == "-ry" || flag == "-rz") {
        need(1);
        repeated = repeated.then(rotation(flag[2] - 'x', number(w[++i])));
      } else if (flag == "-s") {
        need(1);
        const double f = number(w[++i]);
        if (f == 0) fail("xf: -s 0 would collapse everything to a point");
        repeated = repeated.then(scaling(f));
      } else if (flag == "-mx" || flag == "-my" || flag == "-mz") {
        repeated = repeated.then(mirror(flag[2] - 'x'));
      } else if (flag == "-i" || flag == "-a") {
        need(1);
        const int n = integer(w[++i]);
        if (n < (flag == "-i" ? 0 : 1)) fail("xf: " + flag + " " + w[i] + " is not a valid count");
        closeRepeat();
        if (flag == "-i") {
          repeat = n;
        } else {
          spec.parts.push_back({Affine{}, n});
        }
      } else {
        fail("xf: unknown transformation argument '" + flag + "'");
      }
    }
    closeRepeat();
    return spec;
  }

  void include(const SourceFile& from) {
    expectAtLeast(1);
    const std::string& name = arg(0);
    const fs::path target = (from.directory / name).lexically_normal();
    const fs::path relative = fs::absolute(target).lexically_normal().lexically_relative(root_);
    if (relative.empty() || *relative.begin() == "..")
      fail("include '" + name + "' is outside the top file's folder (" + root_.string() + ")");
    std::error_code ec;
    if (!fs::is_regular_file(target, ec)) fail("cannot open include '" + name + "'");
    const fs::path canonical = fs::weakly_canonical(target);
    if (std::find(active_.begin(), active_.end(), canonical) != active_.end()) fail("include cycle: '" + name + "' is already being read");
    if (static_cast<int>(active_.size()) > kMaxIncludeDepth)
      fail("includes nested deeper than " + std::to_string(kMaxIncludeDepth) + " levels");
    std::optional<SourceFile> file = loadSource(target, target.string());
    if (!file) fail("cannot open include '" + name + "'");
    const XfSpec spec = parseXf(2);
    const SourceFile* savedFile = file_;
    const Line* savedLine = line_;
    active_.push_back(canonical);
    forEachInstance(spec, [&] { runFile(*file); });
    active_.pop_back();
    file_ = savedFile;
    line_ = savedLine;
  }

  // --- contexts ---

  VertexContext& vertex(const std::string& name) {
    auto it = vertices_.find(name);
    if (it == vertices_.end()) fail(keyword() + ": undefined vertex '" + name + "'");
    return it->second;
  }
  Xyz& currentColour() { return currentColour_.empty() ? unnamedColour_ : colours_.at(currentColour_); }
  MaterialContext& currentMaterial() {
    return currentMaterial_.empty() ? unnamedMaterial_ : namedMaterials_.at(currentMaterial_);
  }
  void materialChanged() { ++currentMaterial().version; }

  // c / m / v: [name [= [template]]]. Returns false for the bare form.
  template <class T>
  bool context(std::map<std::string, T>& table, std::string& current, const T& fresh, const char* what) {
    if (numArgs() == 0) return false;
    const std::string& name = arg(0);
    if (numArgs() == 1) {
      if (!table.count(name)) fail(keyword() + ": undefined " + what + " '" + name + "'");
    } else {
      if (arg(1) != "=" || numArgs() > 3) fail(keyword() + ": expected '" + keyword() + " name', '" + keyword() + " name =' or '" + keyword() + " name = template'");
      T value = fresh;
      if (numArgs() == 3) {
        auto it = table.find(arg(2));
        if (it == table.end()) fail(keyword() + ": undefined " + what + " '" + arg(2) + "'");
        value = it->second;
      }
      // A redefinition is a new context: keep versions rising so earlier snapshots stay apart.
      if constexpr (std::is_same_v<T, MaterialContext>) {
        auto old = table.find(name);
        value.version = old == table.end() ? 0 : old->second.version + 1;
      }
      table[name] = value;
    }
    current = name;
    return true;
  }

  void entity() {
    const std::string& k = keyword();
    if (k == "v") {
      if (numArgs() == 0) fail("v needs a vertex name");
      context(vertices_, currentVertex_, VertexContext{}, "vertex");
    } else if (k == "p" || k == "n") {
      expectArgs(3);
      if (currentVertex_.empty()) fail(k + " outside a vertex context (v name =)");
      const Vec3 value{number(arg(0)), number(arg(1)), number(arg(2))};
      (k == "p" ? vertices_[currentVertex_].position : vertices_[currentVertex_].normal) = value;
    } else if (k == "c") {
      if (!context(colours_, currentColour_, Xyz{}, "colour")) {
        currentColour_.clear();
        unnamedColour_ = Xyz{};  // the unnamed colour is reset to its default
      }
    } else if (k == "cxy") {
      expectArgs(2);
      const double x = number(arg(0)), y = number(arg(1));
      if (!(x >= 0 && y > 0 && x + y <= 1)) fail("cxy: (" + arg(0) + ", " + arg(1) + ") is not a chromaticity (x ≥ 0, y > 0, x + y ≤ 1)");
      currentColour() = Xyz{x / y, 1, (1 - x - y) / y};
    } else if (k == "cspec") {
      expectAtLeast(4);
      const double lo = number(arg(0)), hi = number(arg(1));
      if (!(lo > 0 && hi > lo)) fail("cspec: the wavelength range must be 0 < λmin < λmax (nm)");
      std::vector<double> values;
      for (std::size_t i = 2; i < numArgs(); ++i) {
        values.push_back(number(arg(i)));
        if (values.back() < 0) fail("cspec: spectral values must not be negative");
      }
      const double step = (hi - lo) / static_cast<double>(values.size() - 1);
      const Xyz xyz = integrateSpectrum([&](double lambda) {
        if (lambda < lo || lambda > hi) return 0.0;  // zero outside the range given
        const double u = (lambda - lo) / step;
        const std::size_t j = std::min(static_cast<std::size_t>(u), values.size() - 2);
        return values[j] + (values[j + 1] - values[j]) * (u - static_cast<double>(j));
      });
      setColour(xyz);
    } else if (k == "cct") {
      expectArgs(1);
      const double kelvin = number(arg(0));
      if (!(kelvin >= 100)) fail("cct: " + arg(0) + " K is not a black-body temperature (at least 100 K)");
      setColour(integrateSpectrum([&](double lambda) { return planck(lambda, kelvin); }));
    } else if (k == "cmix") {
      if (numArgs() < 2 || numArgs() % 2 != 0) fail("cmix takes pairs of weight and colour name");
      Xyz sum{0, 0, 0};
      for (std::size_t i = 0; i < numArgs(); i += 2) {
        const double w = number(arg(i));
        if (w < 0) fail("cmix: weights must not be negative");
        auto it = colours_.find(arg(i + 1));
        if (it == colours_.end()) fail("cmix: undefined colour '" + arg(i + 1) + "'");
        sum.x += w * it->second.x;
        sum.y += w * it->second.y;
        sum.z += w * it->second.z;
      }
      setColour(sum);
    } else if (k == "m") {
      if (!context(namedMaterials_, currentMaterial_, MaterialContext{}, "material")) {
        currentMaterial_.clear();
        unnamedMaterial_ = MaterialContext{};
        unnamedMaterial_.version = ++unnamedResets_;
      }
    } else if (k == "rd") {
      expectArgs(1);
      const double rd = number(arg(0));
      if (rd < 0 || rd > 1) fail("rd " + arg(0) + ": a reflectance must be between 0 and 1");
      currentMaterial().rd = rd;
      currentMaterial().rdColour = currentColour();
      materialChanged();
    } else if (k == "ed") {
      expectArgs(1);
      const double ed = number(arg(0));
      if (ed < 0) fail("ed " + arg(0) + ": an emittance must not be negative");
      currentMaterial().ed = ed;
      currentMaterial().edColour = currentColour();
      materialChanged();
    } else if (k == "sides") {
      expectArgs(1);
      const int sides = integer(arg(0));
      if (sides != 1 && sides != 2) fail("sides " + arg(0) + ": must be 1 or 2");
      currentMaterial().sides = sides;
      materialChanged();
    } else if (k == "td" || k == "rs" || k == "ts" || k == "ir") {
      expectArgs(k == "td" ? 1 : 2);
      for (std::size_t i = 0; i < numArgs(); ++i) number(arg(i));
      const char* what = k == "td" ? "diffuse transmittance" : k == "rs" ? "specular reflectance" : k == "ts" ? "specular transmittance" : "index of refraction";
      warnOnce(k, k + " (" + what + ") is ignored: lambert's surfaces are opaque and diffuse");
    } else if (k == "o") {
      if (numArgs() > 1) fail("o takes one name (or none, to end the object)");
      if (numArgs() == 1) {
        objects_.push_back(arg(0));
      } else {
        if (objects_.empty()) fail("o: an end with no object to end");
        objects_.pop_back();
      }
    } else if (k == "f") {
      expectAtLeast(3);
      std::vector<Vec3> corners;
      for (std::size_t i = 0; i < numArgs(); ++i) corners.push_back(vertex(arg(i)).position);
      addFace(corners);
    } else if (k == "sph") {
      expectArgs(2);
      sphere(vertex(arg(0)).position, number(arg(1)));
    } else if (k == "cyl") {
      expectArgs(3);
      const double r = number(arg(1));
      cone(vertex(arg(0)).position, r, vertex(arg(2)).position, r);
    } else if (k == "cone") {
      expectArgs(4);
      cone(vertex(arg(0)).position, number(arg(1)), vertex(arg(2)).position, number(arg(3)));
    } else if (k == "ring") {
      expectArgs(3);
      const VertexContext& c = vertex(arg(0));
      ring(c, number(arg(1)), number(arg(2)));
    } else if (k == "torus") {
      expectArgs(3);
      const VertexContext& c = vertex(arg(0));
      torus(c, number(arg(1)), number(arg(2)));
    } else if (k == "prism") {
      expectAtLeast(4);
      std::vector<Vec3> base;
      for (std::size_t i = 0; i + 1 < numArgs(); ++i) base.push_back(vertex(arg(i)).position);
      prism(base, number(arg(numArgs() - 1)));
    } else if (k == "fh" || k == "ies") {
      warnOnce(k, k == "fh" ? std::string("fh (face with holes) is not supported yet; skipped") : std::string("ies (IES luminaire) is not supported; skipped"));
    } else {
      warnOnce(k, "unknown entity '" + k + "' skipped");
    }
  }

  void setColour(const Xyz& xyz) {
    if (!(xyz.y > 0)) fail(keyword() + ": the colour has no luminance");
    currentColour() = Xyz{xyz.x / xyz.y, 1, xyz.z / xyz.y};
  }

  // --- geometry ---

  int materialIndex() {
    const std::string name = currentMaterial_.empty() ? std::string("default") : currentMaterial_;
    const MaterialContext& m = currentMaterial();
    const std::string key = currentMaterial_ + "#" + std::to_string(m.version);  // "" + #: the unnamed one
    auto it = materialIndex_.find(key);
    if (it != materialIndex_.end()) return it->second;
    Material material;
    material.name = name;
    for (const Material& other : materials_)
      if (other.name == name) {
        material.name = name + " " + std::to_string(m.version);  // the same name, changed since
        break;
      }
    material.albedo = boundedAlbedo(m.rd * chromaticityToRgb(m.rdColour), where() + ": material '" + name + "': rd");
    material.twoSided = m.sides == 2;
    const int index = static_cast<int>(materials_.size());
    materials_.push_back(material);
    emission_.push_back(m.ed / (kPi * kLumensPerWatt) * chromaticityToRgb(m.edColour));
    materialIndex_[key] = index;
    return index;
  }

  PolygonMesh& mesh() {
    std::string name = defaultObject_;
    if (!objects_.empty()) {
      name = objects_[0];
      for (std::size_t i = 1; i < objects_.size(); ++i) name += "/" + objects_[i];
    }
    auto it = meshIndex_.find(name);
    if (it != meshIndex_.end()) return meshes_[it->second];
    meshIndex_[name] = meshes_.size();
    meshes_.push_back({});
    meshes_.back().name = name;
    return meshes_.back();
  }

  // One polygon in the file's (untransformed) coordinates, counter-clockwise from the front.
  void addFace(const std::vector<Vec3>& corners) {
    const Affine& xf = xf_.back();
    const int material = materialIndex();
    PolygonMesh& m = mesh();
    PolygonMesh::Face face;
    face.material = material;
    for (const Vec3& p : corners) {
      face.vertices.push_back(static_cast<std::uint32_t>(m.positions.size()));
      m.positions.push_back(xf.point(p));
    }
    if (xf.mirrors()) std::reverse(face.vertices.begin(), face.vertices.end());
    m.faces.push_back(std::move(face));
  }
  void addFace(std::vector<Vec3> corners, bool reversed) {
    if (reversed) std::reverse(corners.begin(), corners.end());
    addFace(corners);
  }

  int segments() const { return std::max(3, options_.divisions); }

  static Vec3 unitCircle(const Vec3& t, const Vec3& b, int j, int n) {
    const double phi = 2 * kPi * j / n;
    return std::cos(phi) * t + std::sin(phi) * b;
  }

  void sphere(const Vec3& centre, double radius) {
    if (radius == 0) fail("sph: the radius must not be zero");
    const double r = std::fabs(radius);
    const bool inward = radius < 0;
    const int around = segments(), down = std::max(2, around / 2);
    const Vec3 n{0, 0, 1}, t{1, 0, 0}, b{0, 1, 0};
    auto at = [&](int i, int j) {
      const double theta = kPi * i / down;  // 0 at the north pole
      return centre + r * (std::sin(theta) * unitCircle(t, b, j, around) + std::cos(theta) * n);
    };
    for (int i = 0; i < down; ++i)
      for (int j = 0; j < around; ++j) {
        if (i == 0) {
          addFace({centre + r * n, at(1, j), at(1, j + 1)}, inward);
        } else if (i == down - 1) {
          addFace({at(i, j), centre - r * n, at(i, j + 1)}, inward);
        } else {
          addFace({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)}, inward);
        }
      }
  }

  void cone(const Vec3& v1, double r1, const Vec3& v2, double r2) {
    if ((r1 < 0 && r2 > 0) || (r1 > 0 && r2 < 0)) fail(keyword() + ": the radii must not have different signs");
    if (r1 == 0 && r2 == 0) fail(keyword() + ": the radii must not both be zero");
    const Vec3 axis = v2 - v1;
    if (lengthSquared(axis) == 0) fail(keyword() + ": the two ends are the same point (a ring is that)");
    const bool inward = r1 < 0 || r2 < 0;
    const double a1 = std::fabs(r1), a2 = std::fabs(r2);
    Vec3 t, b;
    orthonormalBasis(normalize(axis), t, b);
    const int n = segments();
    for (int j = 0; j < n; ++j) {
      const Vec3 u0 = unitCircle(t, b, j, n), u1 = unitCircle(t, b, j + 1, n);
      if (a1 == 0) {
        addFace({v1, v2 + a2 * u1, v2 + a2 * u0}, inward);
      } else if (a2 == 0) {
        addFace({v1 + a1 * u0, v1 + a1 * u1, v2}, inward);
      } else {
        addFace({v1 + a1 * u0, v1 + a1 * u1, v2 + a2 * u1, v2 + a2 * u0}, inward);
      }
    }
  }

  Vec3 axisOf(const VertexContext& c) const {
    if (lengthSquared(c.normal) == 0) fail(keyword() + ": the centre vertex '" + arg(0) + "' has no normal (n dx dy dz)");
    return normalize(c.normal);
  }

  void ring(const VertexContext& c, double rmin, double rmax) {
    if (rmin < 0 || !(rmax > rmin)) fail("ring: the radii must satisfy 0 ≤ rmin < rmax");
    const Vec3 n = axisOf(c);
    Vec3 t, b;
    orthonormalBasis(n, t, b);
    const int k = segments();
    if (rmin == 0) {  // a disc: one convex polygon
      std::vector<Vec3> disc;
      for (int j = 0; j < k; ++j) disc.push_back(c.position + rmax * unitCircle(t, b, j, k));
      addFace(disc);
      return;
    }
    for (int j = 0; j < k; ++j) {
      const Vec3 u0 = unitCircle(t, b, j, k), u1 = unitCircle(t, b, j + 1, k);
      addFace({c.position + rmin * u0, c.position + rmax * u0, c.position + rmax * u1, c.position + rmin * u1});
    }
  }

  void torus(const VertexContext& c, double rmin, double rmax) {
    if ((rmin < 0 && rmax > 0) || (rmin > 0 && rmax < 0)) fail("torus: the radii must not have different signs");
    if (!(std::fabs(rmax) > std::fabs(rmin))) fail("torus: |rmax| must be greater than |rmin|");
    const bool inward = rmax < 0;
    const double major = (std::fabs(rmax) + std::fabs(rmin)) / 2, tube = (std::fabs(rmax) - std::fabs(rmin)) / 2;
    const Vec3 n = axisOf(c);
    Vec3 t, b;
    orthonormalBasis(n, t, b);
    const int k = segments();
    auto at = [&](int j, int i) {
      const Vec3 radial = unitCircle(t, b, j, k);
      const double psi = 2 * kPi * i / k;
      return c.position + (major + tube * std::cos(psi)) * radial + tube * std::sin(psi) * n;
    };
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) addFace({at(j, i), at(j + 1, i), at(j + 1, i + 1), at(j, i + 1)}, inward);
  }

  void prism(const std::vector<Vec3>& base, double length) {
    if (length == 0) fail("prism: the length must not be zero");
    const Vec3 area = polygonAreaVector(base);
    if (lengthSquared(area) == 0) fail("prism: the base face has no area");
    const Vec3 offset = normalize(area) * -length;  // away from the base face's front
    std::vector<Vec3> far;
    for (const Vec3& p : base) far.push_back(p + offset);
    addFace(base);
    addFace(far, true);
    const std::size_t n = base.size();
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = (i + 1) % n;
      addFace({base[i], far[i], far[j], base[j]});
    }
  }
};

}  // namespace

Result<Scene> readMgf(const std::string& path, const MgfOptions& options) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Error{path + ": no such MGF file"};
  try {
    Reader reader(options, path);
    return reader.read(path);
  } catch (const ParseError& e) {
    return Error{e.message};
  } catch (const std::exception& e) {  // a filesystem or allocation failure, never thrown out
    return Error{path + ": " + e.what()};
  }
}

}  // namespace lambert
