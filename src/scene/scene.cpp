#include "hrbench/scene.h"

#include <charconv>
#include <cmath>

#include "hrbench/util/error.h"
#include "util/sha256.h"

namespace hrbench {

static void ValidateMaterial(const Material &m, const std::string &name, bool reflectance) {
    if (reflectance && !(m.reflectance >= 0 && m.reflectance < 1))
        throw InputError(name + " has reflectance outside [0, 1)");
    if (!(m.emission >= 0) || !std::isfinite(m.emission))
        throw InputError(name + " has emission that is negative or not finite");
    if (m.colour)
        for (double c : *m.colour)
            if (!(c >= 0 && c <= 1))
                throw InputError(name + " has a colour component outside [0, 1]");
}

void ValidateScene(const Scene &scene, bool reflectance) {
    std::visit(
        [&](const auto &patches) {
            if (patches.empty())
                throw InputError("scene has no patches");
            for (size_t k = 0; k < patches.size(); ++k) {
                std::string name = "patch " + std::to_string(k);
                std::string problem = patches[k].shape.Problem();
                if (!problem.empty())
                    throw InputError(name + " " + problem);
                ValidateMaterial(patches[k].material, name, reflectance);
            }
        },
        scene.patches);
}

// Appends _x_ in the digest's number format, printf's %.17g; adding +0.0 turns -0 into 0.
// to_chars with a precision is specified as that printf conversion, and is several times
// faster: a scene of a million triangles has nine million coordinates.
static void AppendCoordinate(std::string &text, double x) {
    char digits[32];
    char *end =
        std::to_chars(digits, digits + sizeof digits, x + 0.0, std::chars_format::general, 17).ptr;
    if (!text.empty() && text.back() != '\n')
        text += ' ';
    text.append(digits, end);
}

static void AppendCorners(std::string &text, const Segment &s) {
    for (const Vec2 &p : {s.a, s.b})
        for (int c = 0; c < 2; ++c)
            AppendCoordinate(text, p[c]);
}

static void AppendCorners(std::string &text, const Polygon &p) {
    for (int k = 0; k < p.n; ++k)
        for (int c = 0; c < 3; ++c)
            AppendCoordinate(text, p.v[k][c]);
}

// Calls _take_ with SceneGeometryText(_scene_) in pieces of whole lines, each about
// _piece_ bytes, so that a scene of a million triangles (180 MB of text) is digested
// without holding its text.
template <typename Take>
static void ForEachGeometryPiece(const Scene &scene, size_t piece, Take &&take) {
    std::string text;
    std::visit(
        [&](const auto &patches) {
            for (const auto &patch : patches) {
                AppendCorners(text, patch.shape);
                text += '\n';
                if (text.size() >= piece) {
                    take(text);
                    text.clear();
                }
            }
        },
        scene.patches);
    take(text);
}

std::string SceneGeometryText(const Scene &scene) {
    std::string text;
    ForEachGeometryPiece(scene, size_t(-1), [&](std::string &piece) { text.swap(piece); });
    return text;
}

std::string SceneSha256(const Scene &scene) {
    Sha256 sha;
    ForEachGeometryPiece(scene, size_t(1) << 20,
                         [&](const std::string &piece) { sha.Update(piece); });
    return sha.Hex();
}

}  // namespace hrbench
