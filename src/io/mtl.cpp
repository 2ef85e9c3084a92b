// MTL libraries: newmtl, Kd and Ke read, the other standard statements ignored.
#include "mtl.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "faces.h"
#include "hrbench/mesh_io.h"
#include "numbers.h"
#include "text_reader.h"

namespace hrbench::meshio {

// The value an MTL `Kd` or `Ke` stands for: the mean of r g b; three equal values (or
// one) give that value exactly, so that SaveMesh's grey values read back unchanged (their
// mean in floating point may differ in the last bit).
double MtlMean(const Rgb &rgb) {
    if (rgb[0] == rgb[1] && rgb[1] == rgb[2])
        return rgb[0];
    return (rgb[0] + rgb[1] + rgb[2]) / 3;
}

double CappedReflectance(double rho) { return std::min(std::max(rho, 0.0), kMeshMaxReflectance); }

namespace {

// _rgb_ with each component clamped to [0, 1], the range of a display colour.
Rgb DisplayRange(Rgb rgb) {
    for (double &c : rgb)
        c = std::min(std::max(c, 0.0), 1.0);
    return rgb;
}

// The standard MTL statements that say nothing about reflectance or emission.
bool IgnoredMtlStatement(std::string_view key) {
    static const std::set<std::string_view> kIgnored = {
        "Ka",   "Ks", "Ns", "Ni", "d",  "Tr",  "Tf",    "illum",  "bump", "disp",     "decal",
        "refl", "Pr", "Pm", "Ps", "Pc", "Pcr", "aniso", "anisor", "norm", "sharpness"};
    return kIgnored.count(key) > 0 || key.substr(0, 4) == "map_";
}

// Reads `newmtl NAME`: adds NAME, once, with the default surface.
DefinedMaterial &NewMaterial(const Lines &lines, Words &words, const std::string &library,
                             Materials &materials) {
    if (words.Left() != 1)
        lines.Fail("newmtl needs one material name (one word)");
    std::string_view name;
    words.Next(name);
    auto [it, added] = materials.try_emplace(
        std::string(name), DefinedMaterial{kDefaultMaterial, library, lines.Number()});
    if (!added) {
        const DefinedMaterial &first = it->second;
        std::string where = first.library == library ? "" : " in " + first.library + ",";
        lines.Fail("material " + Quoted(name) + " is defined twice (first" + where + " on line " +
                   std::to_string(first.line) + ")");
    }
    return it->second;
}

// Reads `Kd r g b` (reflectance: the mean, capped; display colour: r g b clamped to
// [0, 1]) or `Ke r g b` (emission) of _current_; one value stands for all three.
void ReadMtlColour(const Lines &lines, Words &words, std::string_view keyword,
                   DefinedMaterial *current) {
    std::string key(keyword);
    if (current == nullptr)
        lines.Fail(key + " before any newmtl");
    size_t n = words.Left();
    if (n != 1 && n != 3)
        lines.Fail(key + " needs r g b (or one value for all three), this line has " +
                   std::to_string(n) + " values");
    Rgb rgb;
    std::string_view word;
    for (size_t c = 0; c < n; ++c) {
        words.Next(word);
        rgb[c] = Finite(lines, word, key + " value");
    }
    if (n == 1)
        rgb[1] = rgb[2] = rgb[0];
    double mean = MtlMean(rgb);
    if (key == "Kd") {
        current->material.reflectance = CappedReflectance(mean);
        current->material.colour = DisplayRange(rgb);
        return;
    }
    if (!std::isfinite(mean))
        lines.Fail("Ke values overflow: their mean is not finite");
    if (mean < 0)
        lines.Fail("Ke gives a negative emission: the mean of its values is below 0");
    current->material.emission = mean;
}

}  // namespace

// Reads the MTL _text_ of _library_ ("material library 'PATH'") into _materials_.
void ReadMaterials(std::string_view text, const std::string &library, Materials &materials) {
    Lines lines(text, library);
    DefinedMaterial *current = nullptr;
    while (lines.Next()) {
        Words words(lines.Line());
        std::string_view key;
        words.Next(key);
        if (key == "newmtl")
            current = &NewMaterial(lines, words, library, materials);
        else if (key == "Kd" || key == "Ke")
            ReadMtlColour(lines, words, key, current);
        else if (!IgnoredMtlStatement(key))
            lines.Fail("unsupported statement " + Quoted(key) +
                       " (hrbench reads newmtl, Kd and Ke, and ignores the other standard "
                       "statements)");
    }
}

}  // namespace hrbench::meshio
