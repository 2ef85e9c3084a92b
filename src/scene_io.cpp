#include "scene_io.h"

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "util/error.h"

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
                patches.push_back(p);
            }
        },
        scene.patches);
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
    if (doc.contains("dimension")) {
        const json &dimension = doc["dimension"];
        if (!dimension.is_number_integer() || (dimension != 2 && dimension != 3))
            throw InputError(source + ": \"dimension\" must be 2 or 3");
        if (dimension == 3)
            scene.patches = Patches<Polygon>();
    }
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
        Material material;
        if (p.contains("reflectance"))
            material.reflectance = Number(p["reflectance"], where + ".reflectance");
        if (p.contains("emission"))
            material.emission = Number(p["emission"], where + ".emission");
        if (auto *polygons = std::get_if<Patches<Polygon>>(&scene.patches))
            polygons->push_back({Corners(p, where), material});
        else
            scene.Get<Segment>().push_back(
                {{Point(p, "a", where), Point(p, "b", where)}, material});
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
    Scene scene = SceneFromJson(text.str(), path);
    scene.file = path;
    return scene;
}

void SaveScene(const Scene &scene, const std::string &path) {
    std::ofstream out(path, std::ios::binary);
    out << SceneToJson(scene);
    if (!out)
        throw InputError("cannot write scene file '" + path + "'");
}

}  // namespace hrbench
