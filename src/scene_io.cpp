#include "scene_io.h"

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "util/error.h"

namespace hrbench {

using nlohmann::json;

std::string SceneToJson(const Scene &scene) {
    json doc;
    doc["format"] = "hrbench-scene";
    doc["schema_version"] = kSceneSchemaVersion;
    doc["dimension"] = scene.dimension;
    doc["family"] = scene.family;
    doc["params"] = scene.params;
    json patches = json::array();
    for (const Segment &s : scene.segments)
        patches.push_back({{"a", {s.a.x(), s.a.y()}},
                           {"b", {s.b.x(), s.b.y()}},
                           {"reflectance", s.material.reflectance},
                           {"emission", s.material.emission}});
    doc["patches"] = patches;
    return doc.dump(2) + "\n";
}

namespace {

double Number(const json &value, const std::string &where) {
    if (!value.is_number())
        throw InputError(where + " must be a number");
    return value.get<double>();
}

Vec2 Point(const json &patch, const char *key, const std::string &where) {
    if (!patch.contains(key))
        throw InputError(where + " has no \"" + key + "\"");
    const json &p = patch[key];
    if (!p.is_array() || p.size() != 2)
        throw InputError(where + "." + key + " must be an array of 2 numbers");
    return Vec2(Number(p[0], where + "." + key + "[0]"), Number(p[1], where + "." + key + "[1]"));
}

}  // namespace

Scene SceneFromJson(const std::string &text, const std::string &source) {
    json doc;
    try {
        doc = json::parse(text);
    } catch (const json::exception &e) {
        // Drop the library's "[json.exception.parse_error.101] " tag, keep its line and column.
        std::string what = e.what();
        size_t tag = what.find("] ");
        throw InputError(source + ": malformed JSON: " +
                         (tag == std::string::npos ? what : what.substr(tag + 2)));
    }
    if (!doc.is_object() || doc.value("format", "") != "hrbench-scene")
        throw InputError(source + ": not an hrbench scene (\"format\": \"hrbench-scene\" missing)");
    if (doc.value("schema_version", 0) != kSceneSchemaVersion)
        throw InputError(source + ": unsupported schema_version (expected " +
                         std::to_string(kSceneSchemaVersion) + ")");

    Scene scene;
    scene.family = "file";
    scene.dimension = doc.value("dimension", 2);
    if (doc.contains("params") && doc["params"].is_object())
        for (const auto &[key, value] : doc["params"].items())
            scene.params[key] = Number(value, source + ": params." + key);
    if (!doc.contains("patches") || !doc["patches"].is_array())
        throw InputError(source + ": \"patches\" must be an array");
    const json &patches = doc["patches"];
    for (size_t k = 0; k < patches.size(); ++k) {
        std::string where = source + ": patches[" + std::to_string(k) + "]";
        const json &p = patches[k];
        if (!p.is_object())
            throw InputError(where + " must be an object");
        Segment s{Point(p, "a", where), Point(p, "b", where), {}};
        if (p.contains("reflectance"))
            s.material.reflectance = Number(p["reflectance"], where + ".reflectance");
        if (p.contains("emission"))
            s.material.emission = Number(p["emission"], where + ".emission");
        scene.segments.push_back(s);
    }
    try {
        ValidateScene(scene);
    } catch (const InputError &e) {
        throw InputError(source + ": " + e.what());
    }
    return scene;
}

Scene LoadScene(const std::string &path) {
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw InputError("cannot read scene file '" + path + "'");
    std::stringstream text;
    text << in.rdbuf();
    return SceneFromJson(text.str(), path);
}

void SaveScene(const Scene &scene, const std::string &path) {
    std::ofstream out(path, std::ios::binary);
    out << SceneToJson(scene);
    if (!out)
        throw InputError("cannot write scene file '" + path + "'");
}

}  // namespace hrbench
