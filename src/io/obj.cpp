// OBJ files: the reader and the writer (with the MTL library beside it).
#include <algorithm>
#include <array>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <set>
#include <unordered_map>
#include <vector>

#include "../util/output.h"
#include "formats.h"
#include "mtl.h"
#include "numbers.h"
#include "text_reader.h"
#include "util/format.h"

namespace hrbench::meshio {

namespace {

// The number of lines of _text_ that start with _prefix_: room to reserve for the
// vertices and faces before reading them, so that a large mesh is not copied as it grows.
size_t LinesStartingWith(std::string_view text, std::string_view prefix) {
    size_t count = text.substr(0, prefix.size()) == prefix;
    std::string line = "\n" + std::string(prefix);
    for (size_t at = text.find(line); at != std::string_view::npos; at = text.find(line, at + 1))
        ++count;
    return count;
}

// Reads an OBJ file: v, f, usemtl and mtllib statements; vt and vn counted for the
// references of faces; vp, o, g and s ignored.
class ObjReader {
  public:
    ObjReader(std::string_view text, const std::string &source, const LibraryReader &readLibrary,
              const MeshOptions &options)
        : lines_(text, "mesh file '" + source + "'"), source_(source), readLibrary_(readLibrary),
          options_(options) {
        vertices_.reserve(LinesStartingWith(text, "v "));
        patches_.Reserve(LinesStartingWith(text, "f "));
    }

    MeshPatches Read() {
        while (lines_.Next())
            ReadStatement();
        if (numFaces_ == 0)
            lines_.FailAtEnd(lines_.Number() == 0 ? "the file is empty" : "the file has no faces");
        return std::move(patches_);
    }

  private:
    // Reads the statement on the current line, by its keyword.
    void ReadStatement() {
        Words words(lines_.Line());
        std::string_view keyword;
        words.Next(keyword);
        if (keyword == "v")
            ReadVertex(words);
        else if (keyword == "f")
            ReadFace(words);
        else if (keyword == "vt")
            ++numTextures_;
        else if (keyword == "vn")
            ++numNormals_;
        else if (keyword == "usemtl")
            UseMaterial(words);
        else if (keyword == "mtllib")
            ReadLibraries(words);
        else if (keyword != "vp" && keyword != "o" && keyword != "g" && keyword != "s")
            lines_.Fail("unsupported statement " + Quoted(keyword) +
                        " (hrbench reads v, f, usemtl and mtllib, and ignores vt, vn, vp, o, g "
                        "and s)");
    }

    // Reads `v x y z [w]`; the weight is checked, not used.
    void ReadVertex(Words &words) {
        size_t n = words.Left();
        if (n != 3 && n != 4)
            lines_.Fail("a vertex needs 3 coordinates and an optional weight, this line has " +
                        std::to_string(n) + " values");
        vertices_.push_back(ReadPoint(lines_, words, options_.scale));
        std::string_view weight;
        if (words.Next(weight))
            Finite(lines_, weight, "weight");
    }

    // Reads `f c1 c2 c3 ...` with the current material.
    void ReadFace(Words &words) {
        size_t number = ++numFaces_;
        std::string face = "face " + std::to_string(number);
        size_t n = words.Left();
        CheckCornerCount(lines_, face, n, options_.triangulate);
        corners_.resize(n);
        std::string_view word;
        for (Vec3 &corner : corners_) {
            words.Next(word);
            corner = vertices_[ReadCorner(word, face)];
        }
        AddFace(lines_, number, face, corners_, current_, options_.triangulate, patches_);
    }

    // Reads a corner of _face_, `i`, `i/t`, `i/t/n` or `i//n`, and returns the index of
    // its vertex; t and n must refer to texture coordinates and normals defined so far.
    size_t ReadCorner(std::string_view word, const std::string &face) {
        std::array<std::string_view, 3> parts;
        size_t count = 0;
        for (std::string_view rest = word;; ++count) {
            size_t slash = rest.find('/');
            if (count < parts.size())
                parts[count] = rest.substr(0, slash);
            if (slash == std::string_view::npos)
                break;
            rest.remove_prefix(slash + 1);
        }
        bool wellFormed = count < 3 && !parts[0].empty() && (count != 1 || !parts[1].empty()) &&
                          (count != 2 || !parts[2].empty());
        size_t vertex = wellFormed ? Resolve(parts[0], vertices_.size(), "vertex", face) : 0;
        if (wellFormed && count >= 1 && !parts[1].empty())
            wellFormed = Resolve(parts[1], numTextures_, "texture coordinate", face) != kBad;
        if (wellFormed && count == 2)
            wellFormed = Resolve(parts[2], numNormals_, "normal", face) != kBad;
        if (!wellFormed || vertex == kBad)
            lines_.Fail(face + ": " + Quoted(word) +
                        " is not a corner: i, i/t, i/t/n or i//n with integers counting from 1 "
                        "(or back from -1)");
        return vertex;
    }

    // The index that _ref_ (1-based, or negative: back from the last of the _defined_
    // elements so far) resolves to; kBad when _ref_ is not a non-zero integer.
    size_t Resolve(std::string_view ref, size_t defined, const char *kind,
                   const std::string &face) const {
        bool negative = ref[0] == '-';
        std::string_view digits = negative ? ref.substr(1) : ref;
        if (!AllDigits(digits) || digits.find_first_not_of('0') == std::string_view::npos)
            return kBad;
        uint64_t magnitude = 0;
        bool fits = std::from_chars(digits.data(), digits.data() + digits.size(), magnitude).ec ==
                        std::errc() &&
                    magnitude <= defined;
        if (!fits)
            lines_.Fail(face + " refers to " + kind + " " + Shown(ref) + " of " +
                        std::to_string(defined) + " defined so far");
        return negative ? defined - magnitude : magnitude - 1;
    }

    // Reads `usemtl NAME`: the material of the libraries read so far, or the defaults,
    // with a warning the first time a name is not found, unless a missing library (warned
    // about) may be what defines it.
    void UseMaterial(Words &words) {
        if (words.Left() != 1)
            lines_.Fail("usemtl needs one material name (one word)");
        std::string_view name;
        words.Next(name);
        auto it = materials_.find(name);
        current_ = it != materials_.end() ? it->second.material : kDefaultMaterial;
        if (it == materials_.end() && readLibrary_ && !libraryMissing_ &&
            undefinedNames_.insert(std::string(name)).second)
            patches_.warnings.push_back(lines_.Warning(
                "material " + Quoted(name) + " is not defined by the material libraries read " +
                "so far: its faces get the default reflectance " + DefaultSurface()));
    }

    static std::string DefaultSurface() {
        return FormatDouble(kMeshDefaultReflectance) + " and emission " +
               FormatDouble(kMeshDefaultEmission);
    }

    // Reads `mtllib FILE...`: each library once; a library that cannot be read ends the
    // run with this line named, one that does not exist is a warning.
    void ReadLibraries(Words &words) {
        if (words.Left() == 0)
            lines_.Fail("mtllib needs at least one file name");
        std::string_view name;
        while (words.Next(name)) {
            std::string file(name);
            if (!readLibrary_ || !librariesRead_.insert(file).second)
                continue;
            std::optional<std::string> text;
            std::string library = "material library '" + Directory(source_) + file + "'";
            try {
                text = readLibrary_(file);
            } catch (const InputError &e) {
                lines_.Fail(e.what());
            }
            if (!text) {
                libraryMissing_ = true;
                patches_.warnings.push_back(
                    lines_.Warning(library +
                                   " does not exist: the faces of its materials get "
                                   "the default reflectance " +
                                   DefaultSurface()));
                continue;
            }
            ReadMaterials(*text, library, materials_);
        }
    }

    static constexpr size_t kBad = size_t(-1);

    Lines lines_;
    std::string source_;
    const LibraryReader &readLibrary_;
    MeshOptions options_;
    std::vector<Vec3> vertices_;
    std::vector<Vec3> corners_;  // of the face being read
    size_t numFaces_ = 0;
    size_t numTextures_ = 0;
    size_t numNormals_ = 0;
    std::set<std::string> librariesRead_;
    bool libraryMissing_ = false;           // a library named does not exist
    std::set<std::string> undefinedNames_;  // usemtl names warned about
    Materials materials_;
    Material current_ = kDefaultMaterial;
    MeshPatches patches_;
};

// The `Kd` values of _m_: its display colour where their mean is its reflectance (as
// the reader takes it), else its reflectance as grey; both read back as _m_'s reflectance.
Rgb KdOf(const Material &m) {
    if (m.colour && MtlMean(*m.colour) == m.reflectance)
        return *m.colour;
    return {m.reflectance, m.reflectance, m.reflectance};
}

// A hash of a corner consistent with ==: -0 and 0 hash alike (adding +0.0 makes both 0).
struct CornerHash {
    size_t operator()(const std::array<double, 3> &xyz) const {
        uint64_t h = 0;
        for (double c : xyz) {
            uint64_t bits;
            c += 0.0;
            std::memcpy(&bits, &c, sizeof bits);
            h = (h ^ bits) * 0x100000001b3ull;  // FNV-1a's prime, one step per coordinate
            h ^= h >> 29;
        }
        return size_t(h);
    }
};

std::string RgbText(const Rgb &rgb) {
    return FormatDouble(rgb[0]) + " " + FormatDouble(rgb[1]) + " " + FormatDouble(rgb[2]);
}

}  // namespace

MeshPatches ReadObj(std::string_view text, const std::string &source,
                    const LibraryReader &readLibrary, const MeshOptions &options) {
    return ObjReader(text, source, readLibrary, options).Read();
}

// Writes _scene_ as OBJ at _path_ and its materials as the MTL library beside it
// (docs/scene-format.md#obj-and-mtl): corners shared where equal, faces in scene order
// with their corners in order, one material per distinct surface.
void SaveObj(const Scene &scene, const std::string &path) {
    // The library goes beside the file written, which a symbolic link _path_ names
    // elsewhere: mtllib is read relative to the OBJ's real folder.
    const std::string target = OutputTarget(path, "mesh file");
    std::string library = MaterialLibraryPath(target);
    std::string libraryName = library.substr(library.find_last_of('/') + 1);
    // OBJ has no escapes: a blank splits the name, '#' starts a comment, a line break
    // ends the statement, and each would silently lose the materials when read back.
    if (std::any_of(libraryName.begin(), libraryName.end(),
                    [](unsigned char c) { return c == ' ' || c == '#' || c < 0x20 || c == 0x7f; }))
        throw InputError("cannot name material library '" + libraryName +
                         "' in an OBJ file: an mtllib name is one word without '#' or "
                         "control characters; choose another --out name");
    const Patches<Polygon> &patches = scene.Get<Polygon>();
    // Corners equal under == share an index, numbered in order of first use.
    std::unordered_map<std::array<double, 3>, size_t, CornerHash> vertexIndex;
    std::string vertices, faces, mtl;
    std::vector<Material> materials;  // distinct, in order of first use
    size_t current = size_t(-1);
    for (size_t k = 0; k < patches.size(); ++k) {
        const Material &m = patches[k].material;
        if (m.reflectance > kMeshMaxReflectance)
            throw InputError("patch " + std::to_string(k) + " has reflectance " +
                             FormatDouble(m.reflectance) + ", above " +
                             FormatDouble(kMeshMaxReflectance) +
                             ", the most an MTL Kd gives when read back (docs/3d.md)");
        auto same = [&](const Material &o) {
            return o.reflectance == m.reflectance && o.emission == m.emission &&
                   o.colour == m.colour;
        };
        size_t material =
            size_t(std::find_if(materials.begin(), materials.end(), same) - materials.begin());
        if (material == materials.size()) {
            materials.push_back(m);
            mtl += "newmtl m" + std::to_string(material) + "\nKd " + RgbText(KdOf(m)) + "\nKe " +
                   RgbText({m.emission, m.emission, m.emission}) + "\n";
        }
        if (material != current)
            faces += "usemtl m" + std::to_string(material) + "\n";
        current = material;
        faces += "f";
        const Polygon &p = patches[k].shape;
        for (int c = 0; c < p.n; ++c) {
            std::array<double, 3> xyz = {p.v[c].x(), p.v[c].y(), p.v[c].z()};
            auto [it, added] = vertexIndex.try_emplace(xyz, vertexIndex.size() + 1);
            if (added)
                vertices += "v " + FormatDouble(xyz[0]) + " " + FormatDouble(xyz[1]) + " " +
                            FormatDouble(xyz[2]) + "\n";
            faces += " " + std::to_string(it->second);
        }
        faces += "\n";
    }
    std::string header = "# hrbench scene '" + scene.family + "', " +
                         std::to_string(patches.size()) +
                         " patches: faces counter-clockwise seen from the front\n";
    // Both staged, then the library renamed before the mesh that names it.
    WriteOutputFiles(
        {{library, "material library",
          "# Materials of " + target.substr(target.find_last_of('/') + 1) +
              ": reflectance = mean(Kd), emission = mean(Ke)\n" + mtl},
         {path, "mesh file", header + "mtllib " + libraryName + "\n" + vertices + faces}});
}

}  // namespace hrbench::meshio
