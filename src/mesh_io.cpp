#include "hrbench/mesh_io.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <string_view>
#include <utility>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/Polygon_2_algorithms.h>

#include "hrbench/util/error.h"
#include "hrbench/util/format.h"
#include "hrbench/util/output.h"

namespace hrbench {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using PolygonIndices = std::vector<std::size_t>;
using LibraryReader = std::function<std::optional<std::string>(const std::string &mtlName)>;

const Material kDefaultMaterial{kMeshDefaultReflectance, kMeshDefaultEmission};

MeshFormat FormatOf(const std::string &path) {
    size_t dot = path.find_last_of('.');
    std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == "off")
        return MeshFormat::Off;
    if (ext == "obj")
        return MeshFormat::Obj;
    throw InputError("mesh file '" + path + "' must end in .off or .obj");
}

std::string Directory(const std::string &path) {
    size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

// The value an MTL `Kd` or `Ke` stands for: the mean of r g b; three equal values (or
// one) give that value exactly, so that SaveMesh's grey values read back unchanged (their
// mean in floating point may differ in the last bit).
double MtlMean(const Rgb &rgb) {
    if (rgb[0] == rgb[1] && rgb[1] == rgb[2])
        return rgb[0];
    return (rgb[0] + rgb[1] + rgb[2]) / 3;
}

double CappedReflectance(double rho) { return std::min(std::max(rho, 0.0), kMeshMaxReflectance); }

// _rgb_ with each component clamped to [0, 1], the range of a display colour.
Rgb DisplayRange(Rgb rgb) {
    for (double &c : rgb)
        c = std::min(std::max(c, 0.0), 1.0);
    return rgb;
}

// ---------------------------------------------------------------------------------------
// Lines, words and numbers

// _word_ for a message: at most 40 bytes, every byte outside printable ASCII escaped, so
// that a message stays one short line whatever the file holds.
std::string Shown(std::string_view word) {
    constexpr size_t kMaxShown = 40;
    std::string out;
    for (unsigned char c : word.substr(0, kMaxShown)) {
        if (c >= 0x20 && c < 0x7f) {
            out += char(c);
        } else {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", unsigned(c));
            out += hex;
        }
    }
    return word.size() > kMaxShown ? out + "..." : out;
}

std::string Quoted(std::string_view word) { return "'" + Shown(word) + "'"; }

bool IsBlank(char c) { return c == ' ' || c == '\t'; }

// _value_ with 3 significant digits, for measures in messages.
std::string ThreeDigits(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value);
    return text;
}

// The statements of one file's text, line by line, numbered from 1; errors name the file
// and the line. A statement line is one that is neither blank nor only a comment.
class Lines {
  public:
    // _file_ names the file in messages: "mesh file 'PATH'".
    Lines(std::string_view text, std::string file) : text_(text), file_(std::move(file)) {
        // Skip a UTF-8 byte order mark, which some editors write before the first line.
        if (text_.substr(0, 3) == "\xEF\xBB\xBF")
            pos_ = 3;
    }

    // Moves to the next statement line, without its line ending and its `#` comment;
    // false at the end of the text.
    bool Next() {
        while (pos_ < text_.size()) {
            size_t end = std::min(text_.find('\n', pos_), text_.size());
            std::string_view line = text_.substr(pos_, end - pos_);
            pos_ = std::min(end + 1, text_.size());
            ++number_;
            if (!line.empty() && line.back() == '\r')
                line.remove_suffix(1);
            if (line.find('\r') != std::string_view::npos)
                Fail("carriage return inside a line (line endings must be \\n or \\r\\n)");
            line = line.substr(0, line.find('#'));
            if (!std::all_of(line.begin(), line.end(), IsBlank)) {
                line_ = line;
                return true;
            }
        }
        return false;
    }

    std::string_view Line() const { return line_; }
    size_t Number() const { return number_; }
    // The bytes after the current line.
    size_t BytesLeft() const { return text_.size() - pos_; }

    [[noreturn]] void Fail(const std::string &what) const { FailAt(number_, what); }
    [[noreturn]] void FailAt(size_t line, const std::string &what) const {
        throw InputError(At(line, what));
    }
    // A warning about the current line, worded as an error is.
    std::string Warning(const std::string &what) const { return At(number_, what); }
    std::string At(size_t line, const std::string &what) const {
        return file_ + ", line " + std::to_string(line) + ": " + what;
    }
    // Fails at the line after the last one (line 1 of an empty file): where a truncated
    // file ends. Call once Next() has returned false.
    [[noreturn]] void FailAtEnd(const std::string &what) const { FailAt(number_ + 1, what); }

  private:
    std::string_view text_;
    std::string file_;
    size_t pos_ = 0;
    size_t number_ = 0;
    std::string_view line_;
};

// The words of a line, separated by spaces and tabs.
class Words {
  public:
    explicit Words(std::string_view line) : rest_(line) {}

    // Reads the next word into _word_; false when none is left.
    bool Next(std::string_view &word) {
        // Plain loops: find_first_of with a set costs a memchr per character.
        size_t start = 0, size = rest_.size();
        while (start < size && IsBlank(rest_[start]))
            ++start;
        size_t end = start;
        while (end < size && !IsBlank(rest_[end]))
            ++end;
        word = rest_.substr(start, end - start);
        rest_.remove_prefix(end);
        return !word.empty();
    }

    // The number of words not read yet.
    size_t Left() const {
        Words copy = *this;
        std::string_view word;
        size_t n = 0;
        while (copy.Next(word))
            ++n;
        return n;
    }

  private:
    std::string_view rest_;
};

bool AllDigits(std::string_view word) {
    return !word.empty() &&
           std::all_of(word.begin(), word.end(), [](unsigned char c) { return std::isdigit(c); });
}

// Parses _word_ as a number into _value_; returns "" or why it is not a finite number.
// As everywhere in hrbench (util/args.h), a number beyond the doubles overflows and one
// that would lose precision as a subnormal (or 0) underflows.
std::string NumberProblem(std::string_view word, double &value) {
    std::string_view text = word;
    if (text.size() > 1 && text[0] == '+' && text[1] != '+' && text[1] != '-')
        text.remove_prefix(1);  // files and strtod take a leading '+', from_chars does not
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec == std::errc::invalid_argument || end != text.data() + text.size())
        return "is not a number";
    const char *overflows = "overflows double precision (largest 1.8e308)";
    const char *underflows = "underflows double precision (smallest normal 2.2e-308)";
    if (ec == std::errc::result_out_of_range) {
        // from_chars reports underflow and overflow alike; strtod tells them apart.
        return std::isinf(std::strtod(std::string(text).c_str(), nullptr)) ? overflows : underflows;
    }
    if (!std::isfinite(value))
        return "is not finite";
    return value == 0 || std::isnormal(value) ? "" : underflows;
}

// Reads _word_ as a finite number, or fails at the current line of _lines_ saying what
// (_what_) is wrong: "coordinate '1e400' overflows".
double Finite(const Lines &lines, std::string_view word, const std::string &what) {
    double value = 0;
    std::string problem = NumberProblem(word, value);
    if (!problem.empty())
        lines.Fail(what + " " + Quoted(word) + " " + problem);
    return value;
}

// Reads _word_ as a non-negative integer written in digits, or fails saying why not.
uint64_t Count(const Lines &lines, std::string_view word, const std::string &what) {
    uint64_t value = 0;
    if (AllDigits(word)) {
        if (std::from_chars(word.data(), word.data() + word.size(), value).ec == std::errc())
            return value;
        lines.Fail(what + " " + Quoted(word) + " is too large");
    }
    double number = 0;
    std::string problem = NumberProblem(word, number);
    if (problem.empty())
        problem = number < 0 ? "is negative" : "is not an integer";
    lines.Fail(what + " " + Quoted(word) + " " + problem);
}

// Reads the _count_ (3 or 4) components r g b [a] of a colour: integers in 0..255, or,
// when any is written otherwise (0.5, 1e-1), numbers in [0, 1]. Returns r, g, b and their
// mean, scaled to [0, 1].
struct Colour {
    Rgb rgb;
    double mean;
};
Colour ReadColour(const Lines &lines, Words &words, size_t count, const std::string &what) {
    std::array<std::string_view, 4> components;
    bool integers = true;
    for (size_t k = 0; k < count; ++k) {
        words.Next(components[k]);
        integers = integers && AllDigits(components[k]);
    }
    Rgb rgb{};
    double sum = 0;
    for (size_t k = 0; k < count; ++k) {
        std::string_view word = components[k];
        double value = 0;
        if (integers) {
            uint64_t byte = 256;
            std::from_chars(word.data(), word.data() + word.size(), byte);
            if (byte > 255)
                lines.Fail(what + " " + Quoted(word) + " is outside 0..255");
            value = double(byte);
        } else {
            value = Finite(lines, word, what);
            if (!(value >= 0 && value <= 1))
                lines.Fail(what + " " + Quoted(word) +
                           " is outside [0, 1] (a colour written with fractions is read in 0..1)");
        }
        if (k < 3) {  // the alpha is checked, not used
            rgb[k] = integers ? value / 255 : value;
            sum += value;
        }
    }
    return {rgb, integers ? sum / (3 * 255.0) : sum / 3};
}

// Reads the coordinates x y z of a vertex, each multiplied by _scale_.
Vec3 ReadPoint(const Lines &lines, Words &words, double scale) {
    std::array<double, 3> xyz;
    std::string_view word;
    for (double &c : xyz) {
        words.Next(word);
        c = Finite(lines, word, "coordinate") * scale;
        if (scale != 1 && (!std::isfinite(c) || (c != 0 && !std::isnormal(c))))
            lines.Fail("coordinate " + Quoted(word) + " times the scale " + FormatDouble(scale) +
                       (std::isfinite(c) ? " underflows double precision (smallest normal 2.2e-308)"
                                         : " overflows double precision (largest 1.8e308)"));
    }
    return Vec3(xyz[0], xyz[1], xyz[2]);
}

// ---------------------------------------------------------------------------------------
// Faces: patches as they are, or split into triangles (docs/3d.md, "Mesh input")

// The patches read from a mesh file, with the line and the number (from 1) of the face
// each comes from, for messages.
struct MeshPatches {
    Patches<Polygon> patches;
    std::vector<std::pair<size_t, size_t>> origins;  // line, face
    std::vector<std::string> warnings;               // Scene::warnings

    void Add(const Polygon &shape, const Material &material, size_t line, size_t face) {
        patches.push_back({shape, material});
        origins.emplace_back(line, face);
    }
};

// Corner indices of a triangle of a split face, counter-clockwise like the face.
using CornerTriangle = std::array<size_t, 3>;

// Largest number of corners of a face that is split by ear clipping (a non-convex one):
// the clipping takes up to n^3 steps.
constexpr size_t kMaxClippedCorners = 512;

// Why _quad_ (of a face that Polygon::Problem refuses) is not planar or not convex, with
// corners numbered from 1; "" when it is neither, but degenerate, not finite or too
// large. Same measures and tolerances as Polygon::Problem.
std::string QuadShapeProblem(const Polygon &quad) {
    double diameter = quad.Diameter();
    Vec3 areaVector = quad.AreaVector();
    double twiceArea = areaVector.norm();
    if (!std::isfinite(diameter) || !std::isfinite(twiceArea) ||
        !(twiceArea > 2e-12 * diameter * diameter))
        return "";
    Vec3 normal = areaVector / twiceArea;
    // The diagonals are perpendicular to the normal, so all four corners lie equally far
    // from the plane through their mean, on alternate sides.
    Vec3 centroid = 0.25 * (quad.v[0] + quad.v[1] + quad.v[2] + quad.v[3]);
    double distance = std::abs((quad.v[0] - centroid).dot(normal));
    for (int k = 1; k < 4; ++k)
        distance = std::max(distance, std::abs((quad.v[k] - centroid).dot(normal)));
    if (distance > kMeshPlanarityTolerance * diameter)
        return "is not planar: its corners lie " + ThreeDigits(distance) +
               " off their mean plane, " + ThreeDigits(distance / diameter) +
               " of the face's diameter " + ThreeDigits(diameter) + " (tolerance " +
               ThreeDigits(kMeshPlanarityTolerance) + " of the diameter)";
    for (int k = 0; k < 4; ++k) {
        const Vec3 &a = quad.v[k], &b = quad.v[(k + 1) % 4], &c = quad.v[(k + 2) % 4];
        if (!((b - a).cross(c - b).dot(normal) > 1e-12 * diameter * diameter))
            return "is not a convex quad: corner " + std::to_string((k + 1) % 4 + 1) +
                   " turns the wrong way or goes straight on";
    }
    return "";
}

// The corners of a face seen along its normal: each corner's two coordinates other than
// the one where the face's area vector is largest (ties: x before y before z), exactly
// as read, in the order that keeps the face counter-clockwise.
class ProjectedFace {
  public:
    using Point2 = Kernel::Point_2;

    ProjectedFace(const std::vector<Vec3> &corners, int dropped) {
        int u = (dropped + 1) % 3, w = (dropped + 2) % 3;
        for (const Vec3 &c : corners)
            points_.emplace_back(c[u], c[w]);
    }

    // Whether the projected polygon is simple (no two edges cross or touch, no corner
    // repeats), decided exactly; if so, it fixes the orientation.
    bool IsSimple() {
        const Kernel traits{};  // a named one: GCC warns that a temporary is uninitialized
        if (!CGAL::is_simple_2(points_.begin(), points_.end(), traits))
            return false;
        clockwise_ = CGAL::orientation_2(points_.begin(), points_.end(), traits) == CGAL::CLOCKWISE;
        return true;
    }

    // +1 when a, b, c turn left (counter-clockwise seen from the front), -1 when right,
    // 0 when collinear; exact.
    int Turn(size_t a, size_t b, size_t c) const {
        int turn = int(CGAL::orientation(points_[a], points_[b], points_[c]));
        return clockwise_ ? -turn : turn;
    }

    bool StrictlyConvex() const {
        size_t n = points_.size();
        for (size_t k = 0; k < n; ++k)
            if (Turn((k + n - 1) % n, k, (k + 1) % n) <= 0)
                return false;
        return true;
    }

    // Whether _b_ with its neighbours _a_ and _c_ among the _remaining_ corners is an ear:
    // it turns left, and no other remaining corner lies in or on the triangle a b c.
    bool IsEar(size_t a, size_t b, size_t c, const std::vector<size_t> &remaining) const {
        if (Turn(a, b, c) <= 0)
            return false;
        for (size_t x : remaining)
            if (x != a && x != b && x != c && Turn(a, b, x) >= 0 && Turn(b, c, x) >= 0 &&
                Turn(c, a, x) >= 0)
                return false;
        return true;
    }

  private:
    std::vector<Point2> points_;
    bool clockwise_ = false;
};

// Splits the face with _corners_ (named _face_ in messages) into triangles:
//  - a quad convex seen along its normal: along its shorter diagonal (ties: v1v3 only
//    when strictly shorter than v0v2), as a fan from the diagonal's first corner;
//  - a polygon of 5 or more corners that is strictly convex seen along its normal: a fan
//    from its first corner, (v0, vk, vk+1) for k = 1 .. n-2;
//  - any other simple polygon: ear clipping, walking the corners from the first; an ear
//    is cut off as (previous, current, next), and the walk goes back to the previous
//    corner, otherwise on to the next; the last three corners, in their order, make the
//    last triangle.
// Fails at the current line of _lines_ when the face is degenerate or not simple.
std::vector<CornerTriangle> Triangulate(const Lines &lines, const std::string &face,
                                        const std::vector<Vec3> &corners) {
    size_t n = corners.size();
    // Twice the area vector, relative to the first corner so that it does not depend on
    // where the face lies.
    Vec3 areaVector = Vec3::Zero();
    Vec3 low = corners[0], high = corners[0];
    for (size_t k = 0; k < n; ++k) {
        areaVector += (corners[k] - corners[0]).cross(corners[(k + 1) % n] - corners[0]);
        low = low.cwiseMin(corners[k]);
        high = high.cwiseMax(corners[k]);
    }
    double size = (high - low).norm();  // the bounding box's diagonal: O(n), unlike the diameter
    if (!areaVector.allFinite() || !std::isfinite(size))
        lines.Fail(face + " is too large for double precision (its size or area overflows)");
    if (!(areaVector.norm() > 2e-12 * size * size))
        lines.Fail(face + " is degenerate (its area is zero), so it cannot be triangulated");
    int dropped = 0;
    for (int axis = 1; axis < 3; ++axis)
        if (std::abs(areaVector[axis]) > std::abs(areaVector[dropped]))
            dropped = axis;
    ProjectedFace projected(corners, dropped);
    if (!projected.IsSimple())
        lines.Fail(face + " is not a simple polygon seen along its normal (two edges cross or "
                          "touch, or a corner repeats), so it cannot be triangulated");

    std::vector<CornerTriangle> triangles;
    if (projected.StrictlyConvex()) {
        if (n == 4) {
            bool v1v3 =
                (corners[3] - corners[1]).squaredNorm() < (corners[2] - corners[0]).squaredNorm();
            return v1v3 ? std::vector<CornerTriangle>{{1, 2, 3}, {1, 3, 0}}
                        : std::vector<CornerTriangle>{{0, 1, 2}, {0, 2, 3}};
        }
        for (size_t k = 1; k + 1 < n; ++k)
            triangles.push_back({0, k, k + 1});
        return triangles;
    }
    if (n > kMaxClippedCorners)
        lines.Fail(face + " is a non-convex polygon of " + std::to_string(n) +
                   " corners; at most " + std::to_string(kMaxClippedCorners) +
                   " can be triangulated");
    std::vector<size_t> ring(n);
    std::iota(ring.begin(), ring.end(), size_t(0));
    size_t at = 0, misses = 0;
    while (ring.size() > 3) {
        size_t r = ring.size();
        size_t a = ring[(at + r - 1) % r], b = ring[at], c = ring[(at + 1) % r];
        if (projected.IsEar(a, b, c, ring)) {
            triangles.push_back({a, b, c});
            ring.erase(ring.begin() + std::ptrdiff_t(at));
            at = (at + r - 2) % (r - 1);  // back to the previous corner
            misses = 0;
        } else {
            at = (at + 1) % r;
            // A simple polygon always has an ear: a full round without one cannot happen.
            if (++misses > r)
                lines.Fail(face + " cannot be triangulated (no ear found)");
        }
    }
    triangles.push_back({ring[0], ring[1], ring[2]});
    return triangles;
}

// Fails at the current line of _lines_ unless _face_ may have _n_ corners: at least 3,
// and at most 4 unless faces are triangulated.
void CheckCornerCount(const Lines &lines, const std::string &face, uint64_t n, bool triangulate) {
    if (n < 3)
        lines.Fail(face + " has " + std::to_string(n) + " corners (a face needs at least 3)");
    if (n > 4 && !triangulate)
        lines.Fail(face + " has " + std::to_string(n) +
                   " corners (triangles and quads are read as they are; --triangulate splits "
                   "polygons into triangles)");
}

// Appends face number _number_ (from 1; _face_ is "face N") with _corners_ (as
// CheckCornerCount allows) to
// _patches_ with _material_: as it is when it can be a patch (Polygon::Problem), split
// into triangles when _triangulate_ and it is a polygon of 5 or more corners or a quad
// that is not planar or not convex; otherwise fails at the current line of _lines_
// saying why.
void AddFace(const Lines &lines, size_t number, const std::string &face,
             const std::vector<Vec3> &corners, const Material &material, bool triangulate,
             MeshPatches &patches) {
    size_t n = corners.size();
    if (n <= 4) {
        Polygon polygon = n == 3 ? Polygon::Triangle(corners[0], corners[1], corners[2])
                                 : Polygon::Quad(corners[0], corners[1], corners[2], corners[3]);
        std::string problem = polygon.Problem();
        if (problem.empty())
            return patches.Add(polygon, material, lines.Number(), number);
        std::string shape = n == 4 ? QuadShapeProblem(polygon) : "";
        if (shape.empty())
            lines.Fail(face + " " + problem);
        if (!triangulate)
            lines.Fail(face + " " + shape + "; --triangulate splits it into triangles");
    }
    std::vector<CornerTriangle> triangles = Triangulate(lines, face, corners);
    for (size_t k = 0; k < triangles.size(); ++k) {
        const CornerTriangle &t = triangles[k];
        Polygon triangle = Polygon::Triangle(corners[t[0]], corners[t[1]], corners[t[2]]);
        std::string problem = triangle.Problem();
        if (!problem.empty())
            lines.Fail(face + ", triangle " + std::to_string(k + 1) + " of " +
                       std::to_string(triangles.size()) + " of its triangulation, " + problem);
        patches.Add(triangle, material, lines.Number(), number);
    }
}

// ---------------------------------------------------------------------------------------
// OFF

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
        uint64_t n = Count(lines_, word, face + ": corner count");
        CheckCornerCount(lines_, face, n, options_.triangulate);
        if (words.Left() < n)
            lines_.Fail(face + " announces " + std::to_string(n) + " corners but lists only " +
                        std::to_string(words.Left()));
        corners_.resize(n);
        for (Vec3 &corner : corners_) {
            words.Next(word);
            uint64_t index = Count(lines_, word, face + ": vertex index");
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

// ---------------------------------------------------------------------------------------
// MTL

// A material of an OBJ's libraries, with where it was defined, for duplicates.
struct DefinedMaterial {
    Material material;
    std::string library;  // "material library 'PATH'"
    size_t line;
};
using Materials = std::map<std::string, DefinedMaterial, std::less<>>;

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

// ---------------------------------------------------------------------------------------
// OBJ

// Reads an OBJ file: v, f, usemtl and mtllib statements; vt and vn counted for the
// references of faces; vp, o, g and s ignored.
class ObjReader {
  public:
    ObjReader(std::string_view text, const std::string &source, const LibraryReader &readLibrary,
              const MeshOptions &options)
        : lines_(text, "mesh file '" + source + "'"), source_(source), readLibrary_(readLibrary),
          options_(options) {}

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

}  // namespace

Scene ParseMesh(const std::string &text, MeshFormat format, const std::string &source,
                const LibraryReader &readMaterialLibrary, const MeshOptions &options) {
    if (!(options.scale > 0) || !std::isfinite(options.scale))
        throw InputError("the scale of mesh file '" + source +
                         "' must be a finite number greater than 0");
    MeshPatches read = format == MeshFormat::Off
                           ? OffReader(text, source, options).Read()
                           : ObjReader(text, source, readMaterialLibrary, options).Read();
    Scene scene;
    scene.family = "mesh";
    scene.file = source;
    if (options.scale != 1)
        scene.params["scale"] = options.scale;
    if (options.triangulate)
        scene.params["triangulate"] = 1;
    scene.patches = read.patches;
    scene.warnings = read.warnings;
    // The readers check each face where they read it; this keeps the scene contract
    // should ValidateScene come to check more, naming the face's line.
    try {
        ValidateScene(scene);
    } catch (const InputError &) {
        for (size_t k = 0; k < read.patches.size(); ++k) {
            Scene one;
            one.patches = Patches<Polygon>{read.patches[k]};
            try {
                ValidateScene(one);
            } catch (const InputError &e) {
                std::string what = e.what(), prefix = "patch 0 ";
                if (what.rfind(prefix, 0) == 0)
                    what.erase(0, prefix.size());
                auto [line, face] = read.origins[k];
                throw InputError("mesh file '" + source + "', line " + std::to_string(line) +
                                 ": face " + std::to_string(face) + " " + what);
            }
        }
        throw;
    }
    return scene;
}

Scene LoadMesh(const std::string &path, size_t maxInputBytes, const MeshOptions &options) {
    MeshFormat format = FormatOf(path);
    std::string text = ReadInputFile(path, "mesh file", maxInputBytes);
    auto readLibrary = [&](const std::string &name) -> std::optional<std::string> {
        std::string libraryPath = Directory(path) + name;
        std::error_code error;
        if (std::filesystem::status(libraryPath, error).type() ==
            std::filesystem::file_type::not_found)
            return std::nullopt;  // its faces get the defaults, with a warning (docs/3d.md)
        return ReadInputFile(libraryPath, "material library", maxInputBytes);
    };
    return ParseMesh(text, format, path, readLibrary, options);
}

std::string MaterialLibraryPath(const std::string &objPath) {
    return objPath.substr(0, objPath.find_last_of('.')) + ".mtl";
}

namespace {

// The `Kd` values of _m_: its display colour where their mean is its reflectance (as
// the reader takes it), else its reflectance as grey; both read back as _m_'s reflectance.
Rgb KdOf(const Material &m) {
    if (m.colour && MtlMean(*m.colour) == m.reflectance)
        return *m.colour;
    return {m.reflectance, m.reflectance, m.reflectance};
}

std::string RgbText(const Rgb &rgb) {
    return FormatDouble(rgb[0]) + " " + FormatDouble(rgb[1]) + " " + FormatDouble(rgb[2]);
}

// Writes _scene_ as OBJ at _path_ and its materials as the MTL library beside it
// (docs/scene-format.md#obj-and-mtl): corners shared where equal, faces in scene order
// with their corners in order, one material per distinct surface.
void SaveObj(const Scene &scene, const std::string &path) {
    std::string library = MaterialLibraryPath(path);
    std::string libraryName = library.substr(library.find_last_of('/') + 1);
    if (libraryName.find_first_of(" \t") != std::string::npos)
        throw InputError("cannot name material library '" + libraryName +
                         "' in an OBJ file: mtllib names are single words");
    const Patches<Polygon> &patches = scene.Get<Polygon>();
    std::map<std::array<double, 3>, size_t> vertexIndex;
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
    WriteOutputFile(library, "material library",
                    "# Materials of " + path.substr(path.find_last_of('/') + 1) +
                        ": reflectance = mean(Kd), emission = mean(Ke)\n" + mtl);
    WriteOutputFile(path, "mesh file", header + "mtllib " + libraryName + "\n" + vertices + faces);
}

}  // namespace

void SaveMesh(const Scene &scene, const std::string &path) {
    MeshFormat format = FormatOf(path);
    if (scene.Dimension() != 3)
        throw InputError("only 3D scenes can be written as meshes");
    if (format == MeshFormat::Obj)
        return SaveObj(scene, path);
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
    std::ofstream out(path, std::ios::binary);
    auto np = CGAL::parameters::stream_precision(17);
    bool ok = out && CGAL::IO::write_OFF(out, points, polygons, np);
    if (!ok || !out.flush())
        throw InputError("cannot write mesh file '" + path + "'");
}

}  // namespace hrbench
