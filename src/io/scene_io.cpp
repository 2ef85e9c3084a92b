#include "hrbench/scene_io.h"

#include <algorithm>
#include <initializer_list>
#include <optional>
#include <set>
#include <vector>

#include <nlohmann/json.hpp>

#include "hrbench/util/error.h"
#include "util/output.h"

namespace hrbench {

using nlohmann::json;

static json ShapeToJson(const Segment &s) {
    return {{"a", {s.a.x(), s.a.y()}}, {"b", {s.b.x(), s.b.y()}}};
}

static json ShapeToJson(const Polygon &p) {
    json vertices = json::array();
    for (int k = 0; k < p.n; ++k)
        vertices.push_back({p.v[k].x(), p.v[k].y(), p.v[k].z()});
    return {{"vertices", vertices}};
}

std::string SceneToJson(const Scene &scene) {
    json doc;
    doc["format"] = "hrbench-scene";
    doc["schema_version"] = kSceneSchemaVersion;
    doc["dimension"] = scene.Dimension();
    doc["family"] = scene.family;
    doc["params"] = scene.params;
    json patches = json::array();
    std::visit(
        [&](const auto &list) {
            for (const auto &patch : list) {
                json p = ShapeToJson(patch.shape);
                p["reflectance"] = patch.material.reflectance;
                p["emission"] = patch.material.emission;
                if (patch.material.colour)
                    p["colour"] = *patch.material.colour;
                patches.push_back(p);
            }
        },
        scene.patches);
    doc["patches"] = patches;
    doc["scene_sha256"] = SceneSha256(scene);  // informative, as in the run record
    return doc.dump(2) + "\n";
}

namespace {

// Nesting deeper than this is refused while parsing: no scene needs more than 5 levels,
// and very deep documents would exhaust the stack when they are destroyed.
constexpr int kMaxJsonDepth = 32;

// Parses _text_, refusing malformed JSON, nesting deeper than kMaxJsonDepth and an
// object with a key given twice (the library would keep the last one silently).
json ParseStrict(const std::string &text, const std::string &source) {
    std::vector<std::set<std::string>> keys;  // the keys seen in each open object
    auto check = [&](int depth, json::parse_event_t event, json &parsed) {
        if (depth > kMaxJsonDepth)
            throw InputError(source + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                             " levels");
        if (event == json::parse_event_t::object_start)
            keys.emplace_back();
        else if (event == json::parse_event_t::object_end)
            keys.pop_back();
        else if (event == json::parse_event_t::key &&
                 !keys.back().insert(parsed.get<std::string>()).second)
            throw InputError(source + ": key \"" + parsed.get<std::string>() +
                             "\" appears twice in one object");
        return true;
    };
    try {
        return json::parse(text, check);
    } catch (const json::exception &e) {
        // Drop the library's "[json.exception.parse_error.101] " tag, keep its line and column.
        std::string what = e.what();
        size_t tag = what.find("] ");
        throw InputError(source + ": malformed JSON: " +
                         (tag == std::string::npos ? what : what.substr(tag + 2)));
    }
}

// Refuses a key of _object_ that is not in _known_ (a misspelt key would be ignored).
void CheckKeys(const json &object, std::initializer_list<const char *> known,
               const std::string &where) {
    for (const auto &item : object.items()) {
        const std::string &key = item.key();
        if (std::none_of(known.begin(), known.end(), [&](const char *k) { return key == k; }))
            throw InputError(where + " has an unknown key \"" + key + "\"");
    }
}

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

// The corners of a 3D patch: "vertices", an array of 3 or 4 points [x, y, z].
Polygon Corners(const json &patch, const std::string &where) {
    if (!patch.contains("vertices"))
        throw InputError(where + " has no \"vertices\"");
    const json &v = patch["vertices"];
    if (!v.is_array() || (v.size() != 3 && v.size() != 4))
        throw InputError(where + ".vertices must be an array of 3 or 4 points");
    Polygon polygon;
    polygon.n = int(v.size());
    for (size_t k = 0; k < v.size(); ++k) {
        std::string at = where + ".vertices[" + std::to_string(k) + "]";
        if (!v[k].is_array() || v[k].size() != 3)
            throw InputError(at + " must be an array of 3 numbers");
        polygon.v[k] = Vec3(Number(v[k][0], at + "[0]"), Number(v[k][1], at + "[1]"),
                            Number(v[k][2], at + "[2]"));
    }
    if (polygon.n == 3)
        polygon.v[3] = polygon.v[2];
    return polygon;
}

// A patch's optional display colour: "colour", an array [r, g, b] (ValidateScene checks
// the range).
std::optional<Rgb> Colour(const json &patch, const std::string &where) {
    if (!patch.contains("colour"))
        return std::nullopt;
    const json &c = patch["colour"];
    if (!c.is_array() || c.size() != 3)
        throw InputError(where + ".colour must be an array of 3 numbers [r, g, b]");
    Rgb rgb;
    for (size_t k = 0; k < 3; ++k)
        rgb[k] = Number(c[k], where + ".colour[" + std::to_string(k) + "]");
    return rgb;
}

}  // namespace

Scene SceneFromJson(const std::string &text, const std::string &source, bool reflectance) {
    json doc = ParseStrict(text, source);
    if (!doc.is_object())
        throw InputError(source + ": not an hrbench scene (the document is not an object)");
    // "scene_sha256" is informative, like "family" and "params": a run recomputes it.
    CheckKeys(
        doc,
        {"format", "schema_version", "dimension", "family", "params", "patches", "scene_sha256"},
        source + ":");
    if (!doc.contains("format") || doc["format"] != "hrbench-scene")
        throw InputError(source + ": not an hrbench scene (\"format\": \"hrbench-scene\" missing)");
    if (!doc.contains("schema_version") || !doc["schema_version"].is_number_integer())
        throw InputError(source + ": \"schema_version\" must be the integer " +
                         std::to_string(kSceneSchemaVersion));
    if (doc["schema_version"] != kSceneSchemaVersion)
        throw InputError(source + ": unsupported schema_version " + doc["schema_version"].dump() +
                         " (expected " + std::to_string(kSceneSchemaVersion) + ")");
    if (doc.contains("family") && !doc["family"].is_string())
        throw InputError(source + ": \"family\" must be a string");
    if (doc.contains("scene_sha256") && !doc["scene_sha256"].is_string())
        throw InputError(source + ": \"scene_sha256\" must be a string (64 hex digits)");
    if (doc.contains("params") && !doc["params"].is_object())
        throw InputError(source + ": \"params\" must be an object of numbers");

    Scene scene;
    scene.family = "file";
    if (doc.contains("dimension")) {
        const json &dimension = doc["dimension"];
        if (!dimension.is_number_integer() || (dimension != 2 && dimension != 3))
            throw InputError(source + ": \"dimension\" must be 2 or 3");
        if (dimension == 3)
            scene.patches = Patches<Polygon>();
    }
    if (doc.contains("params"))
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
        CheckKeys(p, {"a", "b", "vertices", "reflectance", "emission", "colour"}, where);
        Material material;
        if (p.contains("reflectance"))
            material.reflectance = Number(p["reflectance"], where + ".reflectance");
        if (p.contains("emission"))
            material.emission = Number(p["emission"], where + ".emission");
        material.colour = Colour(p, where);
        if (auto *polygons = std::get_if<Patches<Polygon>>(&scene.patches))
            polygons->push_back({Corners(p, where), material});
        else
            scene.Get<Segment>().push_back(
                {{Point(p, "a", where), Point(p, "b", where)}, material});
    }
    try {
        ValidateScene(scene, reflectance);
    } catch (const InputError &e) {
        throw InputError(source + ": " + e.what());
    }
    return scene;
}

Scene LoadScene(const std::string &path, size_t maxBytes, bool reflectance) {
    Scene scene = SceneFromJson(ReadInputFile(path, "scene file", maxBytes), path, reflectance);
    scene.file = path;
    return scene;
}

void SaveScene(const Scene &scene, const std::string &path) {
    WriteOutputFile(path, "scene file", SceneToJson(scene));
}

}  // namespace hrbench
