// OFF files: the reader and the writer.
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/OFF.h>

#include "formats.h"
#include "mtl.h"
#include "numbers.h"
#include "text_reader.h"
#include "util/output.h"

namespace hrbench::meshio {

namespace {

// Reads an OFF or COFF file: the keyword, the counts, the vertex lines, the face lines.
class OffReader {
  public:
    OffReader(std::string_view text, const std::string &source, const MeshOptions &options)
        : lines_(text, "mesh file '" + source + "'"), options_(options) {}

    MeshPatches Read() {
        ReadHeader();
        ReadVertices();
        ReadFaces();
        if (lines_.Next())
            lines_.Fail("unexpected text after the last of the " + std::to_string(numFaces_) +
                        " faces");
        return std::move(patches_);
    }

  private:
    // Reads the keyword (OFF or COFF) and the counts, on its line or the next.
    void ReadHeader() {
        if (!lines_.Next())
            lines_.FailAtEnd(lines_.Number() == 0
                                 ? "the file is empty"
                                 : "no OFF header: the file holds only comments and blank lines");
        Words words(lines_.Line());
        std::string_view keyword, next;
        words.Next(keyword);
        CheckKeyword(keyword);
        if (Words(words).Next(next) && next == "BINARY")
            lines_.Fail("binary OFF files are not supported");
        coff_ = keyword == "COFF";
        if (words.Left() == 0) {
            if (!lines_.Next())
                lines_.FailAtEnd("truncated: the file ends before the counts of vertices, faces "
                                 "and edges");
            words = Words(lines_.Line());
        }
        ReadCounts(words);
    }

    // Refuses every keyword but OFF and COFF, the other variants of OFF by name.
    void CheckKeyword(std::string_view keyword) const {
        if (keyword == "OFF" || keyword == "COFF")
            return;
        if (keyword.size() > 3 && keyword.substr(keyword.size() - 3) == "OFF")
            lines_.Fail(Quoted(keyword) + " files are not supported (only OFF and COFF)");
        lines_.Fail("not an OFF file: it starts with " + Quoted(keyword) +
                    " instead of OFF or COFF");
    }

    // Reads `nv nf ne`, and refuses a vertex count that the rest of the file cannot hold
    // before anything is stored.
    void ReadCounts(Words &words) {
        size_t n = words.Left();
        if (n != 3)
            lines_.Fail("the counts line needs 3 numbers (vertices faces edges), not " +
                        std::to_string(n));
        std::string_view word;
        words.Next(word);
        numVertices_ = Count(lines_, word, "vertex count");
        words.Next(word);
        numFaces_ = Count(lines_, word, "face count");
        words.Next(word);
        Count(lines_, word, "edge count");  // checked, not used
        if (numFaces_ == 0)
            lines_.Fail("the header announces no faces");
        countsLine_ = lines_.Number();
        // Each vertex line takes at least 6 bytes, "0 0 0\n".
        if (numVertices_ > lines_.BytesLeft() / 6)
            lines_.Fail("truncated: announces " + std::to_string(numVertices_) +
                        " vertices but has only " + std::to_string(lines_.BytesLeft()) +
                        " bytes left");
    }

    // Reads the vertex lines, then refuses a face count that the rest cannot hold.
    void ReadVertices() {
        vertices_.reserve(numVertices_);  // ReadCounts saw that the file can hold them
        for (uint64_t k = 0; k < numVertices_; ++k) {
            if (!lines_.Next())
                lines_.FailAtEnd("truncated: the file ends after " + std::to_string(k) +
                                 " of the " + std::to_string(numVertices_) + " vertices");
            ReadVertex();
        }
        // Each face line takes at least 8 bytes, "3 0 1 2\n" (the last one 7).
        if (numFaces_ > (lines_.BytesLeft() + 1) / 8)
            lines_.FailAt(countsLine_, "truncated: announces " + std::to_string(numFaces_) +
                                           " faces but has only " +
                                           std::to_string(lines_.BytesLeft()) +
                                           " bytes left after the vertices");
        patches_.Reserve(numFaces_);
    }

    // Reads `x y z`, and in a COFF file an optional vertex colour (checked, not used).
    void ReadVertex() {
        Words words(lines_.Line());
        size_t n = words.Left();
        if (!coff_ && n != 3)
            lines_.Fail("a vertex needs 3 coordinates, this line has " + std::to_string(n) +
                        " values (vertex colours need the COFF keyword)");
        if (coff_ && n != 3 && n != 6 && n != 7)
            lines_.Fail("a COFF vertex needs 3 coordinates and optionally a colour of 3 or 4 "
                        "values, this line has " +
                        std::to_string(n) + " values");
        vertices_.push_back(ReadPoint(lines_, words, options_.scale));
        if (n > 3)
            ReadColour(lines_, words, n - 3, "vertex colour component");
    }

    // Reads the face lines; a missing one means the file is truncated.
    void ReadFaces() {
        for (uint64_t k = 0; k < numFaces_; ++k) {
            if (!lines_.Next())
                lines_.FailAtEnd("truncated: the file ends after " + std::to_string(k) +
                                 " of the " + std::to_string(numFaces_) + " faces");
            ReadFace(k + 1);
        }
    }

    // Reads `k i1 .. ik [colour]`: indices count from 0, the colour gives the reflectance.
    void ReadFace(uint64_t number) {
        std::string face = "face " + std::to_string(number);
        Words words(lines_.Line());
        std::string_view word;
        words.Next(word);
        uint64_t n = 0;
        if (!ParseCount(word, n))  // the message only where it is needed: a million faces
            Count(lines_, word, face + ": corner count");
        CheckCornerCount(lines_, face, n, options_.triangulate);
        if (words.Left() < n)
            lines_.Fail(face + " announces " + std::to_string(n) + " corners but lists only " +
                        std::to_string(words.Left()));
        corners_.resize(n);
        for (Vec3 &corner : corners_) {
            words.Next(word);
            uint64_t index = 0;
            if (!ParseCount(word, index))
                Count(lines_, word, face + ": vertex index");
            if (index >= vertices_.size())
                lines_.Fail(face + " refers to vertex " + std::to_string(index) + " of " +
                            std::to_string(vertices_.size()) + " (OFF vertices count from 0)");
            corner = vertices_[index];
        }
        size_t rest = words.Left();
        if (rest != 0 && rest != 3 && rest != 4)
            lines_.Fail(face + " has " + std::to_string(rest) +
                        " values after its corners; expected none or a colour of 3 or 4");
        Material material = kDefaultMaterial;
        if (rest > 0) {
            Colour colour = ReadColour(lines_, words, rest, face + ": colour component");
            material.reflectance = CappedReflectance(colour.mean);
            material.colour = colour.rgb;
        }
        AddFace(lines_, number, face, corners_, material, options_.triangulate, patches_);
    }

    Lines lines_;
    MeshOptions options_;
    bool coff_ = false;
    uint64_t numVertices_ = 0;
    uint64_t numFaces_ = 0;
    size_t countsLine_ = 0;
    std::vector<Vec3> vertices_;
    std::vector<Vec3> corners_;  // of the face being read
    MeshPatches patches_;
};

}  // namespace

MeshPatches ReadOff(std::string_view text, const std::string &source, const MeshOptions &options) {
    return OffReader(text, source, options).Read();
}

void SaveOff(const Scene &scene, const std::string &path) {
    using Point3 = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
    using PolygonIndices = std::vector<std::size_t>;
    std::vector<Point3> points;
    std::vector<PolygonIndices> polygons;
    for (const Patch<Polygon> &f : scene.Get<Polygon>()) {
        PolygonIndices indices;
        for (int k = 0; k < f.shape.n; ++k) {
            indices.push_back(points.size());
            points.emplace_back(f.shape.v[k].x(), f.shape.v[k].y(), f.shape.v[k].z());
        }
        polygons.push_back(indices);
    }
    OutputFile out(path, "mesh file");
    auto np = CGAL::parameters::stream_precision(17);
    CGAL::IO::write_OFF(out.Stream(), points, polygons, np);
    out.Commit();  // a failed write throws here, with its reason
}

}  // namespace hrbench::meshio
