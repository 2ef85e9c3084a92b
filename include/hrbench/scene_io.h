// Scene files: the documented JSON format (docs/scene-format.md).
#pragma once

#include <string>

#include "hrbench/scene.h"
#include "hrbench/util/input_file.h"

namespace hrbench {

constexpr int kSceneSchemaVersion = 1;

// Serialises _scene_ as a JSON document.
std::string SceneToJson(const Scene &scene);

// Parses a scene document; _source_ names it in error messages. Throws InputError
// with one line that says what is wrong and where.
// _reflectance_: check each patch's reflectance (ValidateScene).
Scene SceneFromJson(const std::string &text, const std::string &source, bool reflectance = true);

// Reads and parses the scene file at _path_, refusing files over _maxBytes_.
Scene LoadScene(const std::string &path, size_t maxBytes = kDefaultMaxInputBytes,
                bool reflectance = true);

// Writes _scene_ to _path_; throws InputError when the file cannot be written.
void SaveScene(const Scene &scene, const std::string &path);

}  // namespace hrbench
