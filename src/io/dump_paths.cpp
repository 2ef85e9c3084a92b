#include "io/dump_paths.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "hrbench/geometry/polygon.h"
#include "hrbench/geometry/segment.h"
#include "hrbench/geometry/subdivision.h"
#include "hrbench/util/error.h"
#include "util/args.h"
#include "util/format.h"

namespace hrbench {

namespace {

std::vector<Vec2> CornersOf(const Segment &s) { return {s.a, s.b}; }
std::vector<Vec3> CornersOf(const Polygon &p) { return {p.v.begin(), p.v.begin() + p.n}; }

double Diameter(const Segment &s) { return (s.b - s.a).norm(); }
double Diameter(const Polygon &p) { return p.Diameter(); }

// Whether _p_ lies on _s_ within _tol_ (a distance).
bool Contains(const Segment &s, const Vec2 &p, double tol) {
    Vec2 u = (s.b - s.a).normalized(), w = p - s.a;
    double along = w.dot(u), across = std::abs(w.x() * u.y() - w.y() * u.x());
    return across <= tol && along >= -tol && along <= (s.b - s.a).norm() + tol;
}

// Whether _p_ lies in the convex polygon _q_ (in its plane) within _tol_ (a distance).
bool Contains(const Polygon &q, const Vec3 &p, double tol) {
    Vec3 normal = q.Normal();
    if (std::abs((p - q.v[0]).dot(normal)) > tol)
        return false;
    for (int k = 0; k < q.n; ++k) {
        Vec3 inward = normal.cross(q.v[(k + 1) % q.n] - q.v[k]).normalized();
        if ((p - q.v[k]).dot(inward) < -tol)
            return false;
    }
    return true;
}

template <typename Shape>
bool ContainsAll(const Shape &shape, const std::vector<typename Shape::Vec> &points, double tol) {
    return std::all_of(points.begin(), points.end(),
                       [&](const auto &p) { return Contains(shape, p, tol); });
}

// Whether _shape_'s corners are _points_ within _tol_, in any cyclic order, either way.
template <typename Shape>
bool SameCorners(const Shape &shape, const std::vector<typename Shape::Vec> &points, double tol) {
    auto corners = CornersOf(shape);
    int n = int(corners.size());
    if (n != int(points.size()))
        return false;
    for (int shift = 0; shift < n; ++shift)
        for (int way : {1, -1}) {
            bool all = true;
            for (int k = 0; k < n && all; ++k)
                all = (points[k] - corners[((shift + way * k) % n + n) % n]).norm() <= tol;
            if (all)
                return true;
        }
    return false;
}

// Reads dump lines and converts their corner tokens for the patches of one shape.
template <typename Shape>
class Converter {
  public:
    using Vec = typename Shape::Vec;

    Converter(const Patches<Shape> &patches, Subdivision mode, double tolerance,
              const std::string &source)
        : patches_(patches), mode_(mode), tolerance_(tolerance), source_(source) {}

    void Run(std::istream &in, std::ostream &out) {
        std::string line;
        while (std::getline(in, line)) {
            ++line_;
            size_t first = line.find_first_not_of(" \t");
            if (first == std::string::npos || line[first] == '#') {
                out << line << '\n';
                continue;
            }
            out << ConvertLine(line) << '\n';
        }
    }

  private:
    [[noreturn]] void Fail(const std::string &what) const {
        throw InputError(source_ + ":" + std::to_string(line_) + ": " + what);
    }

    // _line_ with each word holding '@' replaced by its path (after a `KEY=` prefix).
    std::string ConvertLine(const std::string &line) const {
        std::string result;
        size_t at = 0;
        while (at < line.size()) {
            size_t start = line.find_first_not_of(" \t\r", at);
            result += line.substr(at, std::min(start, line.size()) - at);
            if (start == std::string::npos)
                break;
            size_t end = std::min(line.find_first_of(" \t\r", start), line.size());
            std::string word = line.substr(start, end - start);
            size_t mark = word.find('@');
            if (mark != std::string::npos) {
                size_t equals = word.rfind('=', mark);
                size_t from = equals == std::string::npos ? 0 : equals + 1;
                word = word.substr(0, from) + PathOf(word.substr(from));
            }
            result += word;
            at = end;
        }
        return result;
    }

    // The path of the element named by _token_, `[ROOT]@C;C;...`.
    std::string PathOf(const std::string &token) const {
        size_t mark = token.find('@');
        std::vector<Vec> points = Points(token, token.substr(mark + 1));
        std::vector<size_t> roots;
        if (mark > 0) {
            uint64_t root = ParseRoot(token, token.substr(0, mark));
            roots.push_back(size_t(root));
        } else {
            for (size_t r = 0; r < patches_.size(); ++r)
                if (ContainsAll(patches_[r].shape, points, Tolerance(r)))
                    roots.push_back(r);
            if (roots.empty())
                Fail("element '" + token + "' lies in no root patch within the tolerance " +
                     FormatDouble(tolerance_) + " of its diameter");
        }
        std::optional<std::string> found;
        for (size_t r : roots) {
            std::optional<std::string> path = Descend(token, r, points);
            if (path && found)
                Fail("element '" + token + "' matches elements of two root patches, " + *found +
                     " and " + *path + ": give its root, ROOT@...");
            if (path)
                found = path;
        }
        if (!found)
            Fail("element '" + token + "' matches no element of root patch" +
                 (roots.size() == 1 ? " " + std::to_string(roots[0]) : "es it lies in") +
                 " under the subdivision within the tolerance " + FormatDouble(tolerance_) +
                 " of its diameter");
        return *found;
    }

    double Tolerance(size_t root) const { return tolerance_ * Diameter(patches_[root].shape); }

    // The path in root _root_ of the element with corners _points_, down the one child
    // that holds them at each level; nothing when no element of the tree has them.
    std::optional<std::string> Descend(const std::string &token, size_t root,
                                       const std::vector<Vec> &points) const {
        double tol = Tolerance(root);
        Shape shape = patches_[root].shape;
        if (!ContainsAll(shape, points, tol))
            return std::nullopt;
        std::string digits;
        std::array<Shape, 4> children;
        for (int depth = 0;; ++depth) {
            if (SameCorners(shape, points, tol))
                return std::to_string(root) + (digits.empty() ? "" : "/" + digits);
            if (depth == kSafetyDepth)
                return std::nullopt;
            int n = shape.Subdivide(mode_, children), holder = -1;
            for (int c = 0; c < n; ++c) {
                if (!ContainsAll(children[c], points, tol))
                    continue;
                if (holder >= 0)
                    Fail("element '" + token + "' lies in two children of " + std::to_string(root) +
                         (digits.empty() ? "" : "/" + digits) +
                         " within the tolerance: give a smaller --tolerance");
                holder = c;
            }
            if (holder < 0)
                return std::nullopt;
            digits += char('0' + holder);
            shape = children[holder];
        }
    }

    uint64_t ParseRoot(const std::string &token, const std::string &text) const {
        bool digits =
            std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
        if (!digits || text.size() > 18 || std::stoull(text) >= patches_.size())
            Fail("element '" + token + "': '" + text + "' before '@' is not a root patch of " +
                 "the scene (0 to " + std::to_string(patches_.size() - 1) + ")");
        return std::stoull(text);
    }

    // The corners of _text_, "x,y[,z];x,y[,z];...".
    std::vector<Vec> Points(const std::string &token, const std::string &text) const {
        constexpr int d = Shape::kDimension;
        std::vector<Vec> points;
        size_t begin = 0;
        for (;;) {
            size_t end = std::min(text.find(';', begin), text.size());
            std::string corner = text.substr(begin, end - begin);
            Vec p;
            size_t from = 0;
            for (int c = 0; c < d; ++c) {
                size_t comma = std::min(corner.find(',', from), corner.size());
                if ((comma == corner.size()) != (c == d - 1))
                    Fail("bad element '" + token + "': a corner needs " + std::to_string(d) +
                         " coordinates separated by ',', got '" + corner + "'");
                try {
                    p[c] = ParseDouble(corner.substr(from, comma - from), "coordinate");
                } catch (const InputError &e) {
                    Fail("bad element '" + token + "': " + e.what());
                }
                from = comma + 1;
            }
            points.push_back(p);
            if (end == text.size())
                break;
            begin = end + 1;
        }
        size_t n = points.size();
        if (d == 2 ? n != 2 : n != 3 && n != 4)
            Fail("bad element '" + token + "': " + (d == 2 ? "2" : "3 or 4") +
                 " corners separated by ';' in a " + std::to_string(d) + "D scene, got " +
                 std::to_string(n));
        return points;
    }

    const Patches<Shape> &patches_;
    Subdivision mode_;
    double tolerance_;
    std::string source_;
    size_t line_ = 0;
};

}  // namespace

void ConvertDumpPaths(const Scene &scene, Subdivision subdivision, double tolerance,
                      std::istream &in, const std::string &source, std::ostream &out) {
    std::visit(
        [&](const auto &patches) {
            using Shape = std::decay_t<decltype(patches.front().shape)>;
            CheckSubdivision(subdivision, Shape::kDimension);
            Converter<Shape>(patches, subdivision, tolerance, source).Run(in, out);
        },
        scene.patches);
}

}  // namespace hrbench
