#pragma once
// The types of the glTF 2.0 properties lambert reads, checked before tinygltf parses the file:
// tinygltf skips a property of the wrong type without a word (a node's "mesh": "quad" leaves the
// node empty), which turns a broken export into a silently missing object. This names the JSON
// path and what belongs there instead.
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "lambert/core/error.h"

namespace lambert {

// Ok, or "<file>: <JSON path>: <what is expected> here, not <what is there>" for the first
// property (in the glTF 2.0 schema's terms: index, integer, number, string, boolean, array of n
// numbers) that has the wrong type. Properties it does not know are left to the reader.
Status checkGltfTypes(const nlohmann::json& document, const std::string& file);

}  // namespace lambert
