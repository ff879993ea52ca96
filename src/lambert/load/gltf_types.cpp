#include "lambert/load/gltf_types.h"

#include <cstdint>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace lambert {
namespace {

enum class Kind { Object, Array, Index, Integer, Number, Boolean, String, Numbers3, Numbers4, Numbers16 };

// What the glTF 2.0 schema says each property lambert reads holds. A path's "*" is every element
// of an array or every member of an object; a property that is absent is not checked (the reader
// decides what a missing one means).
struct Rule {
  std::string_view path;
  Kind kind;
};

constexpr Rule kRules[] = {
    {"/asset", Kind::Object}, {"/asset/version", Kind::String},
    {"/scene", Kind::Index}, {"/scenes", Kind::Array}, {"/scenes/*", Kind::Object},
    {"/scenes/*/nodes", Kind::Array}, {"/scenes/*/nodes/*", Kind::Index},
    {"/nodes", Kind::Array}, {"/nodes/*", Kind::Object}, {"/nodes/*/name", Kind::String},
    {"/nodes/*/mesh", Kind::Index}, {"/nodes/*/camera", Kind::Index},
    {"/nodes/*/children", Kind::Array}, {"/nodes/*/children/*", Kind::Index},
    {"/nodes/*/matrix", Kind::Numbers16}, {"/nodes/*/translation", Kind::Numbers3},
    {"/nodes/*/rotation", Kind::Numbers4}, {"/nodes/*/scale", Kind::Numbers3},
    {"/nodes/*/extensions/KHR_lights_punctual/light", Kind::Index},
    {"/meshes", Kind::Array}, {"/meshes/*", Kind::Object}, {"/meshes/*/name", Kind::String},
    {"/meshes/*/primitives", Kind::Array}, {"/meshes/*/primitives/*", Kind::Object},
    {"/meshes/*/primitives/*/attributes", Kind::Object}, {"/meshes/*/primitives/*/attributes/*", Kind::Index},
    {"/meshes/*/primitives/*/indices", Kind::Index}, {"/meshes/*/primitives/*/material", Kind::Index},
    {"/meshes/*/primitives/*/mode", Kind::Integer},
    {"/accessors", Kind::Array}, {"/accessors/*", Kind::Object}, {"/accessors/*/bufferView", Kind::Index},
    {"/accessors/*/byteOffset", Kind::Index}, {"/accessors/*/componentType", Kind::Integer},
    {"/accessors/*/normalized", Kind::Boolean}, {"/accessors/*/count", Kind::Index}, {"/accessors/*/type", Kind::String},
    {"/bufferViews", Kind::Array}, {"/bufferViews/*", Kind::Object}, {"/bufferViews/*/buffer", Kind::Index},
    {"/bufferViews/*/byteOffset", Kind::Index}, {"/bufferViews/*/byteLength", Kind::Index},
    {"/bufferViews/*/byteStride", Kind::Index},
    {"/buffers", Kind::Array}, {"/buffers/*", Kind::Object}, {"/buffers/*/uri", Kind::String},
    {"/buffers/*/byteLength", Kind::Index},
    {"/materials", Kind::Array}, {"/materials/*", Kind::Object}, {"/materials/*/name", Kind::String},
    {"/materials/*/pbrMetallicRoughness", Kind::Object},
    {"/materials/*/pbrMetallicRoughness/baseColorFactor", Kind::Numbers4},
    {"/materials/*/pbrMetallicRoughness/baseColorTexture", Kind::Object},
    {"/materials/*/pbrMetallicRoughness/baseColorTexture/index", Kind::Index},
    {"/materials/*/pbrMetallicRoughness/baseColorTexture/texCoord", Kind::Index},
    {"/materials/*/emissiveFactor", Kind::Numbers3},
    {"/materials/*/extensions/KHR_materials_emissive_strength/emissiveStrength", Kind::Number},
    {"/textures", Kind::Array}, {"/textures/*", Kind::Object}, {"/textures/*/source", Kind::Index},
    {"/textures/*/sampler", Kind::Index},
    {"/samplers", Kind::Array}, {"/samplers/*", Kind::Object}, {"/samplers/*/wrapS", Kind::Integer},
    {"/samplers/*/wrapT", Kind::Integer},
    {"/images", Kind::Array}, {"/images/*", Kind::Object}, {"/images/*/uri", Kind::String},
    {"/images/*/bufferView", Kind::Index},
    {"/cameras", Kind::Array}, {"/cameras/*", Kind::Object}, {"/cameras/*/type", Kind::String},
    {"/cameras/*/perspective", Kind::Object}, {"/cameras/*/perspective/yfov", Kind::Number},
    {"/cameras/*/perspective/aspectRatio", Kind::Number}, {"/cameras/*/perspective/znear", Kind::Number},
    {"/cameras/*/perspective/zfar", Kind::Number},
    {"/extensions/KHR_lights_punctual/lights", Kind::Array}, {"/extensions/KHR_lights_punctual/lights/*", Kind::Object},
    {"/extensions/KHR_lights_punctual/lights/*/name", Kind::String},
    {"/extensions/KHR_lights_punctual/lights/*/type", Kind::String},
    {"/extensions/KHR_lights_punctual/lights/*/color", Kind::Numbers3},
    {"/extensions/KHR_lights_punctual/lights/*/intensity", Kind::Number},
    {"/extensions/KHR_lights_punctual/lights/*/range", Kind::Number},
    {"/extensions/KHR_lights_punctual/lights/*/spot/innerConeAngle", Kind::Number},
    {"/extensions/KHR_lights_punctual/lights/*/spot/outerConeAngle", Kind::Number},
};

// A whole number written as one: tinygltf skips a 2.0 where an integer belongs, so it is refused here.
bool isIndex(const nlohmann::json& v) { return v.is_number_unsigned() || (v.is_number_integer() && v.get<std::int64_t>() >= 0); }

bool numbers(const nlohmann::json& v, std::size_t count) {
  if (!v.is_array() || v.size() != count) return false;
  for (const nlohmann::json& x : v)
    if (!x.is_number()) return false;
  return true;
}

bool matches(const nlohmann::json& v, Kind kind) {
  switch (kind) {
    case Kind::Object: return v.is_object();
    case Kind::Array: return v.is_array();
    case Kind::Index: return isIndex(v);
    case Kind::Integer: return v.is_number_integer();
    case Kind::Number: return v.is_number();
    case Kind::Boolean: return v.is_boolean();
    case Kind::String: return v.is_string();
    case Kind::Numbers3: return numbers(v, 3);
    case Kind::Numbers4: return numbers(v, 4);
    case Kind::Numbers16: return numbers(v, 16);
  }
  return false;
}

const char* expected(Kind kind) {
  switch (kind) {
    case Kind::Object: return "an object";
    case Kind::Array: return "an array";
    case Kind::Index: return "an index (a whole number, 0 or more, without a decimal point)";
    case Kind::Integer: return "a whole number (without a decimal point)";
    case Kind::Number: return "a number";
    case Kind::Boolean: return "true or false";
    case Kind::String: return "a string";
    case Kind::Numbers3: return "an array of 3 numbers";
    case Kind::Numbers4: return "an array of 4 numbers";
    case Kind::Numbers16: return "an array of 16 numbers";
  }
  return "";
}

// What is there, for the message: a short value as JSON, else its type.
std::string found(const nlohmann::json& v) {
  std::string text = v.dump();
  if (text.size() <= 24) return text;
  if (v.is_array()) return "an array of " + std::to_string(v.size());
  if (v.is_object()) return "an object";
  return text.substr(0, 21) + "...";
}

// A JSON pointer's escaping (RFC 6901) for a member name.
std::string escaped(const std::string& name) {
  std::string out;
  for (char c : name) out += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
  return out;
}

// Checks the rule's path from `at` (the value at `where`), segment by segment.
Status check(const nlohmann::json& at, const std::string& where, std::string_view rest, const Rule& rule,
             const std::string& file) {
  if (rest.empty()) {
    if (matches(at, rule.kind)) return Ok{};
    return Error{file + ": " + where + ": " + expected(rule.kind) + " is expected here, not " + found(at)};
  }
  rest.remove_prefix(1);  // the '/'
  const std::size_t end = rest.find('/');
  const std::string segment(rest.substr(0, end));
  rest = end == std::string_view::npos ? std::string_view{} : rest.substr(end);
  if (segment == "*") {
    if (at.is_array()) {
      for (std::size_t i = 0; i < at.size(); ++i)
        if (Status s = check(at[i], where + "/" + std::to_string(i), rest, rule, file); !s) return s;
    } else if (at.is_object()) {
      for (const auto& [name, value] : at.items())
        if (Status s = check(value, where + "/" + escaped(name), rest, rule, file); !s) return s;
    }
    return Ok{};  // a container of the wrong type is its own rule's finding
  }
  if (!at.is_object() || !at.contains(segment)) return Ok{};
  return check(at[segment], where + "/" + segment, rest, rule, file);
}

}  // namespace

Status checkGltfTypes(const nlohmann::json& document, const std::string& file) {
  if (!document.is_object()) return Error{file + ": a glTF file is a JSON object, not " + found(document)};
  // The rules run in order, containers before what they hold, so the first finding is the
  // outermost thing that is wrong.
  for (const Rule& rule : kRules)
    if (Status s = check(document, "", rule.path, rule, file); !s) return s;
  return Ok{};
}

}  // namespace lambert
