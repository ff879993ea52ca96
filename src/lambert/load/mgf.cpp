#include "lambert/load/mgf.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <type_traits>

#include "lambert/core/cie_colour.h"
#include "lambert/core/transform.h"
#include "lambert/core/warning.h"
#include "lambert/light/lights.h"
#include "lambert/load/gltf.h"
#include "lambert/load/mgf_source.h"
#include "lambert/load/photometry_file.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using mgf::Line;
using mgf::SourceFile;

// ---------------------------------------------------------------------------------------------
// Colour: CIE XYZ, kept at unit luminance (Y = 1) since an MGF colour is a chromaticity only
// (core/cie_colour.h).

struct Colour {
  Xyz xyz;             // equal-energy white, MGF's default colour
  std::string origin;  // "file:line: entity" that set it, for a repair's warning
};

// ---------------------------------------------------------------------------------------------
// Transforms: p' = A·p + t (rigid with uniform scale, possibly mirrored; core/transform.h).

// MGF's z-up to lambert's y-up: (x, y, z) → (x, z, −y), a rotation of −90° about x.
Transform zUpToYUp() {
  Transform r;
  r.m = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1};  // the columns: where x, y and z go
  return r;
}

// An xf argument list: a fixed part, then one array dimension per -a (its step applied 0..N−1
// times).
struct XfSpec {
  struct Part {
    Transform step;
    int count = 0;  // 0: fixed (applied once); N ≥ 1: an array dimension of N instances
  };
  std::vector<Part> parts;
  bool hasArray() const {
    return std::any_of(parts.begin(), parts.end(), [](const Part& p) { return p.count > 0; });
  }
};

struct ParseError {
  std::string message;
};

// ---------------------------------------------------------------------------------------------
// Contexts.

struct VertexContext {
  Vec3 position;
  Vec3 normal;  // (0, 0, 0): none
};

struct MaterialContext {
  double rd = 0;  // photometric diffuse reflectance
  Colour rdColour;
  double ed = 0;  // diffuse emittance, lm/m²
  Colour edColour;
  int sides = 2;
  int version = 0;  // bumped on every change: geometry takes the material as it is then
};

class Reader {
 public:
  Reader(const MgfOptions& options, const fs::path& top) : options_(options) { defaultObject_ = top.stem().string(); }

  Scene read(const fs::path& top) {
    std::optional<SourceFile> file = mgf::loadSource(top, top.string());
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
    if (numFaces == 0) throw ParseError{top.string() + ": no faces (lambert needs surfaces: f, sph, cyl, cone, ring, torus, prism); a library of materials and colours, as MGF's Materials/*.mgf are, is included (i) by a scene that has them"};
    if (dropped.total() > 0) warning(top.string() + ": " + dropped.describe());
    if (scene.surfaces.empty()) throw ParseError{top.string() + ": every face is degenerate (" + dropped.describe() + ")"};
    scene.lights = lights_;
    scene.camera = cameraViewingScene(scene);
    // The file's own frame: z up, in metres; every point read went through zUpToYUp.
    const Transform toScene = zUpToYUp();
    for (int axis = 0; axis < 3; ++axis) scene.fileFrame.axes[axis] = {toScene.m[axis * 4], toScene.m[axis * 4 + 1], toScene.m[axis * 4 + 2]};
    scene.fileFrame.offset = {toScene.m[12], toScene.m[13], toScene.m[14]};
    scene.fileFrame.up = {0, 0, 1};
    return scene;
  }

 private:
  const MgfOptions& options_;
  std::string defaultObject_;
  std::vector<fs::path> active_;  // the include chain, for cycles

  std::map<std::string, VertexContext> vertices_;
  std::string currentVertex_;  // "" when none
  std::map<std::string, Colour> colours_;
  Colour unnamedColour_;
  std::string currentColour_;  // "": the unnamed one
  std::map<std::string, MaterialContext> namedMaterials_;
  MaterialContext unnamedMaterial_;
  std::string currentMaterial_;  // "": the unnamed one
  int unnamedResets_ = 0;

  std::vector<Transform> xf_{zUpToYUp()};  // the total transform of each open context
  std::vector<std::string> objects_;
  std::set<std::string> warnedKinds_;
  std::set<std::string> repairedColours_;  // the origins of colours repaired (and reported) once
  std::map<std::string, Rgb> boundedAlbedos_;  // "place|albedo" → boundedAlbedo's result, reported once

  std::vector<Material> materials_;
  std::vector<Rgb> emission_;
  std::map<std::string, int> materialIndex_;  // "name#version" → index into materials_
  std::vector<PolygonMesh> meshes_;
  std::map<std::string, std::size_t> meshIndex_;
  std::vector<Light> lights_;
  std::map<std::string, std::shared_ptr<const Photometry>> photometries_;  // each IES file read once

  // --- the current line, for messages ---
  const SourceFile* file_ = nullptr;
  const Line* line_ = nullptr;

  std::string where() const { return file_->path + ":" + std::to_string(line_->number); }
  [[noreturn]] void fail(const std::string& what) const { throw ParseError{where() + ": " + what}; }
  const std::string& keyword() const { return line_->words[0]; }
  std::size_t numArgs() const { return line_->words.size() - 1; }
  const std::string& arg(std::size_t i) const { return line_->words[i + 1]; }

  // How the specification writes an entity, for the message that refuses a malformed one.
  static std::string usage(const std::string& k) {
    static const std::map<std::string, std::string> forms = {
        {"p", "p x y z"}, {"n", "n dx dy dz"}, {"cxy", "cxy x y"}, {"cspec", "cspec λmin λmax v1 v2 ..."}, {"cct", "cct kelvin"},
        {"cmix", "cmix w1 colour1 w2 colour2 ..."}, {"rd", "rd ρ"}, {"ed", "ed ε (lm/m²)"}, {"td", "td τ"}, {"rs", "rs ρ α"},
        {"ts", "ts τ α"}, {"ir", "ir n k"}, {"sides", "sides 1|2"}, {"f", "f v1 v2 v3 ..."}, {"sph", "sph centre radius"},
        {"cyl", "cyl v1 radius v2"}, {"cone", "cone v1 r1 v2 r2"}, {"ring", "ring centre rmin rmax"}, {"torus", "torus centre rmin rmax"},
        {"prism", "prism v1 v2 v3 ... length"}, {"i", "i file [xf arguments]"},
        {"ies", "ies file [-m multiplier] [xf arguments]"}};
    auto it = forms.find(k);
    return it == forms.end() ? std::string() : "; write it as '" + it->second + "'";
  }
  void expectArgs(std::size_t n) const {
    if (numArgs() != n)
      fail(keyword() + " takes " + std::to_string(n) + (n == 1 ? " argument" : " arguments") + ", not " + std::to_string(numArgs()) + usage(keyword()));
  }
  void expectAtLeast(std::size_t n) const {
    if (numArgs() < n) fail(keyword() + " takes at least " + std::to_string(n) + " arguments, not " + std::to_string(numArgs()) + usage(keyword()));
  }

  double number(const std::string& word) const {
    double value = 0;
    const char* begin = word.data();
    const char* end = begin + word.size();
    if (begin != end && *begin == '+') ++begin;
    auto [ptr, ec] = std::from_chars(begin, end, value);
    if (ec == std::errc::result_out_of_range) fail(keyword() + ": '" + word + "' is not a finite number (beyond double's range)" + usage(keyword()));
    if (ec != std::errc() || ptr != end) fail(keyword() + ": expected a number, got '" + word + "'" + usage(keyword()));
    if (!std::isfinite(value)) fail(keyword() + ": '" + word + "' is not a finite number" + usage(keyword()));
    return value;
  }
  int integer(const std::string& word) const {
    const double value = number(word);
    if (value != std::floor(value) || std::fabs(value) > 1e6) fail(keyword() + ": expected a whole number, got '" + word + "'");
    return static_cast<int>(value);
  }

  void warnOnce(const std::string& kind, const std::string& message) {
    if (warnedKinds_.insert(kind).second) warning(where() + ": " + message + " (further ones are not reported)");
  }

  // --- execution ---

  void runFile(const SourceFile& file) {
    const std::size_t depth = xf_.size();
    run(file, 0, file.lines.size(), depth);
    if (xf_.size() != depth) {  // a transformation applies to its own file only: it ends there
      const std::size_t open = xf_.size() - depth;
      warning(file.path + ":" + std::to_string(file.lines.empty() ? 0 : file.lines.back().number) + ": unbalanced xf: " +
              std::to_string(open) + (open == 1 ? " transformation is" : " transformations are") + " not ended; ended at the end of the file");
      xf_.resize(depth);
    }
  }

  void run(const SourceFile& file, std::size_t begin, std::size_t end, std::size_t fileDepth) {
    for (std::size_t i = begin; i < end; ++i) {
      file_ = &file;
      line_ = &file.lines[i];
      const std::string& k = keyword();
      if (k == "xf") {
        if (numArgs() == 0) {
          if (xf_.size() <= fileDepth) {
            warning(where() + ": xf: an end with no transformation to end; ignored");
          } else {
            xf_.pop_back();
          }
          continue;
        }
        const XfSpec spec = parseXf(1);
        if (!spec.hasArray()) {
          xf_.push_back(xf_.back() * instance(spec, {}));
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

  // The line of the xf that ends the array opened at `open`, or `end` when none does.
  std::size_t matchingXfEnd(const SourceFile& file, std::size_t open, std::size_t end) const {
    int depth = 0;
    for (std::size_t j = open; j < end; ++j) {
      const Line& l = file.lines[j];
      if (l.words[0] != "xf") continue;
      depth += l.words.size() > 1 ? 1 : -1;
      if (depth == 0) return j;
    }
    warning(where() + ": unbalanced xf: no xf ends this array (-a) in its file; it ends at the end of the file");
    return end;
  }

  // Runs body once per array instance of spec (the only one when it has no -a), each inside its
  // transformation context.
  void forEachInstance(const XfSpec& spec, const std::function<void()>& body) {
    std::vector<int> counts, index;
    for (const XfSpec::Part& p : spec.parts)
      if (p.count > 0) counts.push_back(p.count);
    index.assign(counts.size(), 0);
    const Transform outer = xf_.back();
    const std::size_t depth = xf_.size();
    while (true) {
      xf_.push_back(outer * instance(spec, index));
      body();
      xf_.resize(depth);
      std::size_t d = 0;
      while (d < counts.size() && ++index[d] == counts[d]) index[d++] = 0;
      if (d == counts.size()) break;
    }
  }

  static Transform instance(const XfSpec& spec, const std::vector<int>& index) {
    Transform total;
    std::size_t dimension = 0;
    for (const XfSpec::Part& p : spec.parts)
      total = (p.count == 0 ? p.step : p.step.power(index[dimension++])) * total;
    return total;
  }

  // The transform arguments from word `first` (1-based word index) to the end of the line.
  XfSpec parseXf(std::size_t first) const {
    XfSpec spec;
    spec.parts.push_back({});
    int repeat = 1;  // -i N: the arguments up to the next -i or -a are applied N times
    Transform repeated;
    auto closeRepeat = [&] {
      spec.parts.back().step = repeated.power(repeat) * spec.parts.back().step;
      repeated = Transform{};
      repeat = 1;
    };
    const std::vector<std::string>& w = line_->words;
    for (std::size_t i = first; i < w.size(); ++i) {
      const std::string& flag = w[i];
      auto need = [&](std::size_t n) {
        if (i + n >= w.size()) fail("xf: " + flag + " needs " + std::to_string(n) + (n == 1 ? " value" : " values") + (n == 3 ? " (-t dx dy dz)" : ""));
      };
      if (flag == "-t") {
        need(3);
        repeated = Transform::translation({number(w[i + 1]), number(w[i + 2]), number(w[i + 3])}) * repeated;
        i += 3;
      } else if (flag == "-rx" || flag == "-ry" || flag == "-rz") {
        need(1);
        repeated = Transform::rotation(flag[2] - 'x', number(w[++i])) * repeated;
      } else if (flag == "-s") {
        need(1);
        const double f = number(w[++i]);
        if (f == 0) fail("xf: -s 0 would collapse everything to a point; give a nonzero scale factor");
        repeated = Transform::scaling(f) * repeated;
      } else if (flag == "-mx" || flag == "-my" || flag == "-mz") {
        repeated = Transform::mirror(flag[2] - 'x') * repeated;
      } else if (flag == "-i" || flag == "-a") {
        need(1);
        const int n = integer(w[++i]);
        if (n < (flag == "-i" ? 0 : 1)) fail("xf: " + flag + " " + w[i] + " is not a valid count (" + flag + (flag == "-i" ? " takes 0 or more" : " takes 1 or more") + ")");
        closeRepeat();
        if (flag == "-i") {
          repeat = n;
        } else {
          spec.parts.push_back({Transform{}, n});
        }
      } else {
        fail("xf: unknown transformation argument '" + flag + "' (MGF's are -t dx dy dz, -rx/-ry/-rz degrees, -s f, -mx/-my/-mz, -i N, -a N)");
      }
    }
    closeRepeat();
    return spec;
  }

  void include(const SourceFile& from) {
    expectAtLeast(1);
    fs::path canonical;
    Result<SourceFile> file = mgf::openInclude(from, arg(0), options_.includeRoot, active_, canonical);
    if (!file) fail(file.error().message);
    const XfSpec spec = parseXf(2);
    const SourceFile* savedFile = file_;
    const Line* savedLine = line_;
    active_.push_back(canonical);
    forEachInstance(spec, [&] { runFile(*file); });
    active_.pop_back();
    file_ = savedFile;
    line_ = savedLine;
  }

  // MGF 2.0 "ies pathname [-m multiplier] [transform]": an IES luminaire at the origin of the
  // current frame, aimed down its −z (the photometric nadir), its 0–180° plane along x and its
  // 90–270° plane along y (MGF's notes on IES files), placed by the enclosing and its own
  // transforms (its own applied as an xf around it, arrays included); the file relative to the
  // including one. Its candela values times the multiplier, in white.
  void luminaire() {
    expectAtLeast(1);
    const std::string& name = arg(0);
    double multiplier = 1;
    std::size_t xfFrom = 2;
    if (numArgs() >= 2 && arg(1) == "-m") {
      if (numArgs() < 3) fail("ies: -m needs a multiplier; write it as 'ies file [-m multiplier] [transform]'");
      multiplier = number(arg(2));
      if (!(multiplier > 0)) fail("ies: the multiplier must be positive, got '" + arg(2) + "'");
      xfFrom = 4;
    }
    const fs::path target = (file_->directory / name).lexically_normal();
    auto cached = photometries_.find(target.string());
    if (cached == photometries_.end()) {
      Result<Photometry> read = readPhotometry(target.string());
      if (!read) fail("ies '" + name + "': " + read.error().message);
      cached = photometries_.emplace(target.string(), std::make_shared<const Photometry>(std::move(*read))).first;
    }
    const XfSpec spec = parseXf(xfFrom);
    forEachInstance(spec, [&] {
      const Transform& xf = xf_.back();
      Light light;
      light.kind = LightKind::Luminaire;
      light.name = name + " " + std::to_string(lights_.size());
      light.photometry = cached->second;
      light.position = xf.point({0, 0, 0});
      const auto direction = [&](const Vec3& v) { return normalize(xf.point(v) - light.position); };
      // Aimed down the transformed −z with C = 0 along the transformed x: the spin about that aim
      // which brings the frame's C0 there (light/lights.h, luminaireFrame).
      setLuminaireFrame(light, direction({0, 0, -1}), direction({1, 0, 0}));
      if (xf.mirrors())
        warnOnce("ies-mirror", "ies: a mirroring transform would run the luminaire's C planes the other way; it is placed unmirrored");
      light.intensity = Rgb::gray(multiplier);
      lights_.push_back(std::move(light));
    });
  }

  // --- contexts ---

  VertexContext& vertex(const std::string& name) {
    auto it = vertices_.find(name);
    if (it == vertices_.end()) fail(keyword() + ": undefined vertex '" + name + "'; define it before it is used (v " + name + " =, then p x y z)");
    return it->second;
  }
  Colour& currentColour() { return currentColour_.empty() ? unnamedColour_ : colours_.at(currentColour_); }
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
      if (!table.count(name)) fail(keyword() + ": undefined " + what + " '" + name + "'; define it before it is used (" + keyword() + " " + name + " = ...), or include the library that does");
    } else {
      if (arg(1) != "=" || numArgs() > 3) fail(keyword() + ": expected '" + keyword() + " name', '" + keyword() + " name =' or '" + keyword() + " name = template'");
      T value = fresh;
      if (numArgs() == 3) {
        auto it = table.find(arg(2));
        if (it == table.end()) fail(keyword() + ": undefined " + what + " '" + arg(2) + "' (the template); define it before it is used, or include the library that does");
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
      if (numArgs() == 0) fail("v needs a vertex name (v name =, then p x y z)");
      context(vertices_, currentVertex_, VertexContext{}, "vertex");
    } else if (k == "p" || k == "n") {
      expectArgs(3);
      if (currentVertex_.empty()) fail(k + " outside a vertex context; begin one with 'v name =' above it");
      const Vec3 value{number(arg(0)), number(arg(1)), number(arg(2))};
      (k == "p" ? vertices_[currentVertex_].position : vertices_[currentVertex_].normal) = value;
    } else if (k == "c") {
      if (!context(colours_, currentColour_, Colour{}, "colour")) {
        currentColour_.clear();
        unnamedColour_ = Colour{};  // the unnamed colour is reset to its default
      }
    } else if (k == "cxy") {
      expectArgs(2);
      const double x = number(arg(0)), y = number(arg(1));
      // XYZ up to a factor; (x, y) outside x ≥ 0, y > 0, x + y ≤ 1 is repaired where it is used.
      setColour(Xyz{x, y, 1 - x - y});
    } else if (k == "cspec") {
      expectAtLeast(4);
      const double lo = number(arg(0)), hi = number(arg(1));
      if (!(lo > 0 && hi > lo)) fail("cspec: the wavelength range must be 0 < λmin < λmax (nm)" + usage(k));
      std::vector<double> values;
      for (std::size_t i = 2; i < numArgs(); ++i) values.push_back(number(arg(i)));
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
      if (!(kelvin >= 100))
        fail("cct " + arg(0) + ": a black body below 100 K gives no visible light; give the colour temperature in kelvin (2856 for an incandescent lamp, 6504 for daylight)");
      setColour(integrateSpectrum([&](double lambda) { return planck(lambda, kelvin); }));
    } else if (k == "cmix") {
      if (numArgs() < 2 || numArgs() % 2 != 0) fail("cmix takes pairs of weight and colour name" + usage(k));
      Xyz sum{0, 0, 0};
      for (std::size_t i = 0; i < numArgs(); i += 2) {
        const double w = number(arg(i));  // negative ones too: the sum is checked where it is used
        auto it = colours_.find(arg(i + 1));
        if (it == colours_.end()) fail("cmix: undefined colour '" + arg(i + 1) + "'; define it before it is used (c " + arg(i + 1) + " =, then cxy, cspec, cct or cmix)");
        sum.x += w * it->second.xyz.x;
        sum.y += w * it->second.xyz.y;
        sum.z += w * it->second.xyz.z;
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
      // Above 1 is lowered where a face uses it (boundedAlbedo warns); a negative one is no typo
      // that can be guessed.
      if (rd < 0) fail("rd " + arg(0) + ": a reflectance must not be negative; give one between 0 and 1 (rd 0 for black)");
      currentMaterial().rd = rd;
      currentMaterial().rdColour = currentColour();
      materialChanged();
    } else if (k == "ed") {
      expectArgs(1);
      const double ed = number(arg(0));
      if (ed < 0) fail("ed " + arg(0) + ": an emittance must not be negative; give it in lm/m² (ed 0 for none)");
      currentMaterial().ed = ed;
      currentMaterial().edColour = currentColour();
      materialChanged();
    } else if (k == "sides") {
      expectArgs(1);
      const int sides = integer(arg(0));
      if (sides != 1 && sides != 2) fail("sides " + arg(0) + ": must be 1 (one-sided) or 2 (two-sided)");
      currentMaterial().sides = sides;
      materialChanged();
    } else if (k == "td" || k == "rs" || k == "ts" || k == "ir") {
      expectArgs(k == "td" ? 1 : 2);
      for (std::size_t i = 0; i < numArgs(); ++i) number(arg(i));
      const char* what = k == "td" ? "diffuse transmittance" : k == "rs" ? "specular reflectance" : k == "ts" ? "specular transmittance" : "index of refraction";
      warnOnce(k, k + " (" + what + ") is ignored: lambert's surfaces are opaque and diffuse");
    } else if (k == "o") {
      if (numArgs() >= 1) {
        std::string name = arg(0);
        for (std::size_t i = 1; i < numArgs(); ++i) name += " " + arg(i);
        if (numArgs() > 1) warning(where() + ": o takes one name, not " + std::to_string(numArgs()) + " words; read as '" + name + "'");
        objects_.push_back(name);
      } else {
        if (objects_.empty()) {
          warning(where() + ": o: an end with no object to end; ignored");
        } else {
          objects_.pop_back();
        }
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
    } else if (k == "ies") {
      luminaire();
    } else if (k == "fh") {
      warnOnce(k, "fh (face with holes) is not supported yet; skipped");
    } else {
      warnOnce(k, "unknown entity '" + k + "' skipped");
    }
  }

  // A colour with luminance is kept at unit luminance (cmix's weights are luminances); one without
  // is kept as it is, scaled to a largest component of 1, and repaired where it is used.
  void setColour(const Xyz& xyz) {
    std::string entity = keyword();
    for (std::size_t i = 0; i < numArgs() && entity.size() < 40; ++i) entity += " " + arg(i);
    if (entity.size() >= 40) entity += " ...";
    const std::string origin = where() + ": " + entity;
    const double scale = xyz.y > 0 ? xyz.y : std::fmax(std::fabs(xyz.x), std::fmax(std::fabs(xyz.y), std::fabs(xyz.z)));
    if (scale > 0)
      currentColour() = Colour{{xyz.x / scale, xyz.y / scale, xyz.z / scale}, origin};
    else
      currentColour() = Colour{{0, 0, 0}, origin};
  }

  // The colour a material's rd or ed takes, a real one; a repair is reported once per colour
  // definition, where it matters (a nonzero rd or ed).
  Xyz usedColour(const Colour& colour, double amount, const std::string& use) {
    std::string repair;
    Xyz real = realColour(colour.xyz, repair);
    if (!repair.empty() && amount > 0 && repairedColours_.insert(colour.origin).second)
      warning(colour.origin + ": " + repair + " (first used by " + use + " at " + where() + ")");
    return real;
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
    const Xyz rdColour = usedColour(m.rdColour, m.rd, "rd of material '" + name + "'");
    const Xyz edColour = usedColour(m.edColour, m.ed, "ed of material '" + name + "'");
    // A file included several times redefines its materials each time: one warning per line.
    const Rgb albedo = m.rd * chromaticityToRgb(rdColour);
    const std::string place = where() + ": material '" + name + "': rd";
    char albedoKey[128];
    std::snprintf(albedoKey, sizeof albedoKey, "|%a|%a|%a", albedo.r, albedo.g, albedo.b);
    auto bounded = boundedAlbedos_.find(place + albedoKey);
    if (bounded == boundedAlbedos_.end()) bounded = boundedAlbedos_.emplace(place + albedoKey, boundedAlbedo(albedo, place)).first;
    material.albedo = bounded->second;
    material.twoSided = m.sides == 2;
    const int index = static_cast<int>(materials_.size());
    materials_.push_back(material);
    emission_.push_back(m.ed / (kPi * kLumensPerWatt) * chromaticityToRgb(edColour));
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
    const Transform& xf = xf_.back();
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

  // A primitive with no area: nothing to draw, as a degenerate face is dropped.
  void skip(const std::string& why) { warnOnce("no-area " + keyword(), keyword() + ": " + why + ", no area; skipped"); }

  static Vec3 unitCircle(const Vec3& t, const Vec3& b, int j, int n) {
    const double phi = 2 * kPi * j / n;
    return std::cos(phi) * t + std::sin(phi) * b;
  }

  void sphere(const Vec3& centre, double radius) {
    if (radius == 0) return skip("a sphere of radius 0");
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
    if ((r1 < 0 && r2 > 0) || (r1 > 0 && r2 < 0))
      fail(keyword() + ": the radii must not have different signs (both positive: facing out; both negative: facing in); give them the same sign");
    if (r1 == 0 && r2 == 0) return skip("both radii 0");
    const Vec3 axis = v2 - v1;
    if (lengthSquared(axis) == 0) return skip("its two ends are the same point (a ring is that)");
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
    if (lengthSquared(c.normal) == 0) fail(keyword() + ": the centre vertex '" + arg(0) + "' has no normal, so which way it faces is unknown; give the vertex one (n dx dy dz)");
    return normalize(c.normal);
  }

  void ring(const VertexContext& c, double rmin, double rmax) {
    if (rmin < 0 || rmax < 0) fail("ring: the radii must not be negative (a ring faces along its centre's normal; reverse the normal to turn it)");
    if (rmin == rmax) return skip("equal radii");
    if (rmin > rmax) {
      warning(where() + ": ring: the radii are in the wrong order (rmin " + arg(1) + " > rmax " + arg(2) + "); swapped");
      std::swap(rmin, rmax);
    }
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
    if ((rmin < 0 && rmax > 0) || (rmin > 0 && rmax < 0))
      fail("torus: the radii must not have different signs (both positive: facing out; both negative: facing in); give them the same sign");
    if (std::fabs(rmax) == std::fabs(rmin)) return skip("equal radii (a tube of no thickness)");
    if (std::fabs(rmax) < std::fabs(rmin)) {
      warning(where() + ": torus: the radii are in the wrong order (|rmin| " + arg(1) + " > |rmax| " + arg(2) + "); swapped");
      std::swap(rmin, rmax);
    }
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
    if (length == 0) return skip("length 0");
    const Vec3 area = polygonAreaVector(base);
    if (lengthSquared(area) == 0) return skip("its base face has no area");
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
