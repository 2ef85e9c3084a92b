// Root-pair classification with exact predicates, in 2D and 3D.
#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <catch2/catch.hpp>

#include <map>

#include "generators.h"
#include "hrbench/hrbench.h"
#include "visibility/culling.h"

using namespace hrbench;

static Segment S(double ax, double ay, double bx, double by) {
    return {Vec2(ax, ay), Vec2(bx, by)};
}

TEST_CASE("Root pairs are culled, touching or interacting as docs/conventions.md defines",
          "[culling][2d]") {
    SECTION("facing plates interact") {
        CHECK(ClassifyPair(S(0, 0, 1, 0), S(1, 1, 0, 1)) == PairRelation::Interacting);
    }
    SECTION("collinear plates are culled") {
        CHECK(ClassifyPair(S(0, 0, 1, 0), S(2, 0, 3, 0)) == PairRelation::Culled);
    }
    SECTION("plates facing away from each other are culled") {
        CHECK(ClassifyPair(S(1, 0, 0, 0), S(0, 1, 1, 1)) == PairRelation::Culled);
    }
    SECTION("a plate wholly behind the other's line is culled even if it faces it") {
        CHECK(ClassifyPair(S(0, 0, 1, 0), S(1, -1, 0, -2)) == PairRelation::Culled);
    }
    SECTION("a plate lying partly in front interacts") {
        CHECK(ClassifyPair(S(0, 0, 1, 0), S(2, -1, 2, 1)) == PairRelation::Interacting);
    }
    SECTION("plates meeting at a corner touch") {
        CHECK(ClassifyPair(S(0, 0, 1, 0), S(0, 1, 0, 0)) == PairRelation::Touching);
    }
    SECTION("crossing plates touch") {
        CHECK(ClassifyPair(S(-1, 0, 1, 0), S(0, -1, 0, 1)) == PairRelation::Touching);
    }
    SECTION("the decision is exact for a point a rounding error off the line") {
        double y = 1e-300;
        CHECK(ClassifyPair(S(0, 0, 1, 0), S(1, y, 0, y)) == PairRelation::Interacting);
    }
}

TEST_CASE("3D root pairs are culled when coplanar or back-facing, and touching is found",
          "[culling][3d]") {
    Polygon floor = Polygon::Quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
    SECTION("facing plates interact") {
        const Patches<Polygon> s = MakeScene("parallel3d", {}).Get<Polygon>();
        CHECK(ClassifyPair(s[0].shape, s[1].shape) == PairRelation::Interacting);
    }
    SECTION("coplanar plates are culled") {
        Polygon next = Polygon::Quad({2, 0, 0}, {3, 0, 0}, {3, 1, 0}, {2, 1, 0});
        CHECK(ClassifyPair(floor, next) == PairRelation::Culled);
    }
    SECTION("plates facing away from each other are culled") {
        Polygon above = Polygon::Quad({0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1});  // faces +z
        CHECK(ClassifyPair(floor, above) == PairRelation::Culled);
    }
    SECTION("a plate behind the other's plane is culled") {
        Polygon below = Polygon::Quad({0, 1, -1}, {1, 1, -1}, {1, 0, -1}, {0, 0, -1});
        CHECK(ClassifyPair(floor, below) == PairRelation::Culled);
    }
    SECTION("perpendicular plates touch without a gap") {
        const Patches<Polygon> s = MakeScene("perpendicular3d", {{"gap", 0}}).Get<Polygon>();
        CHECK(ClassifyPair(s[0].shape, s[1].shape) == PairRelation::Touching);
        const Patches<Polygon> g = MakeScene("perpendicular3d", {{"gap", 0.1}}).Get<Polygon>();
        CHECK(ClassifyPair(g[0].shape, g[1].shape) == PairRelation::Interacting);
    }
}

// ---------------------------------------------------------------------------------------
// The whole scene: whether a patch can stand between two others, and meshes facing away

namespace {

const std::string kData = HRBENCH_TEST_DATA;

Scene Segments(const Patches<Segment> &patches) { return {"file", {}, "", patches}; }

}  // namespace

TEST_CASE("A scene can occlude when some patch has others strictly on both sides",
          "[culling][occlusion]") {
    // Convex rooms, plates facing each other, arrays: every patch sees all others from one
    // side, so no segment between two of them can cross a third.
    for (const char *family : {"parallel", "room", "enclosure", "array", "perpendicular", "angled",
                               "parallel3d", "array3d", "perpendicular3d"}) {
        INFO(family);
        CHECK_FALSE(CanOcclude(MakeScene(family, {})));
    }
    CHECK_FALSE(CanOcclude(MakeScene("enclosure", {{"n", 7}})));
    CHECK_FALSE(CanOcclude(MakeScene("array", {{"k", 5}})));  // collinear plates: in the line
    // A blocker between plates, a box in a room, the Cornell box's blocks.
    for (const char *family : {"occluded", "occluded3d", "cornell"}) {
        INFO(family);
        CHECK(CanOcclude(MakeScene(family, {})));
    }
    CHECK(CanOcclude(LoadScene(kData + "/room_box.json")));
    CHECK(CanOcclude(LoadMesh(kData + "/room_box.obj")));
    // Two patches cannot occlude, even crossing: there is no third to block.
    CHECK_FALSE(CanOcclude(Segments({{S(-1, 0, 1, 0), {}}, {S(0, -1, 0, 1), {}}})));

    // Exact: a third plate in the floor's line does not make it separate, one a rounding
    // error below the line does.
    Segment floor = S(0, 0, 1, 0), ceiling = S(1, 1, 0, 1);
    CHECK_FALSE(CanOcclude(Segments({{floor, {}}, {ceiling, {}}, {S(2, 0, 3, 0), {}}})));
    CHECK(CanOcclude(Segments({{floor, {}}, {ceiling, {}}, {S(2, -1e-300, 3, 0), {}}})));
    // A patch both of whose sides others face: the plate between two facing plates.
    CHECK(CanOcclude(Segments({{floor, {}}, {ceiling, {}}, {S(0.4, 0.5, 0.6, 0.5), {}}})));
    // ... but not one off to the side, whatever it faces: the plates lie on one side of it.
    CHECK_FALSE(CanOcclude(Segments({{floor, {}}, {ceiling, {}}, {S(2, 0, 2, 1), {}}})));
}

TEST_CASE("A mesh whose faces mostly have every other face behind them draws a hint",
          "[culling][mesh]") {
    CHECK(FacingAwayHint(LoadMesh(kData + "/room_box.obj")).empty());
    // Every face reversed: the room's six walls (16 of the 17.5 units of area) have all
    // else behind them; the box's faces now face each other.
    // Judged per connected part: the room's walls are one, the box another.
    CHECK(FacingAwayHint(LoadMesh(kData + "/room_box_flipped.obj")) ==
          "faces holding 100% of the area of one of the mesh's 2 connected parts (6 of its 6 "
          "faces) have every other face behind them and exchange no light; faces are "
          "counter-clockwise seen from their front (docs/3d.md): a room seen from inside, or a "
          "face of a part, may be the wrong way round");
    // Two facing quads, the second reversed: half the area faces away, all of its part,
    // and no light is exchanged (0 links).
    std::string facing = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                         "f 1 2 3 4\nf 5 6 7 8\n";
    CHECK_THAT(FacingAwayHint(ParseMesh(facing, MeshFormat::Obj, "facing.obj", {})),
               Catch::StartsWith("faces holding 100% of the area of one of the mesh's 2 connected "
                                 "parts (1 of its 1 faces)"));
    std::string fixed = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                        "f 1 2 3 4\nf 5 8 7 6\n";
    CHECK(FacingAwayHint(ParseMesh(fixed, MeshFormat::Obj, "facing.obj", {})).empty());
    // The published Cornell boxes: blocks seen from outside in a room seen from inside.
    for (const char *file : {"/meshes/CornellBox-Original.obj", "/meshes/cornell_box.obj"}) {
        INFO(file);
        CHECK(FacingAwayHint(LoadMesh(kData + file, kDefaultMaxInputBytes, {true, 1})).empty());
    }
    // A convex object seen from outside, alone: rightly hinted, nothing lights anything.
    std::string tetra = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                        "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    CHECK_THAT(FacingAwayHint(ParseMesh(tetra, MeshFormat::Obj, "tetra.obj", {})),
               Catch::StartsWith("faces holding 100% of the mesh's area (4 of 4 faces)"));
    // A flat mesh: every face has the others in its plane, none behind; no hint.
    CHECK(FacingAwayHint(ParseMesh("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n"
                                   "f 1 2 5 4\nf 2 3 6 5\n",
                                   MeshFormat::Obj, "tiles.obj", {}))
              .empty());
    // Only meshes: a scene file or a family is written in hrbench's own convention.
    CHECK(FacingAwayHint(Segments({{S(1, 0, 0, 0), {}}, {S(0, 1, 1, 1), {}}})).empty());
}

// Every corner of every other face, tested one by one, in scene order: the scan alone.
// Returns whether a face has corners strictly on both sides of its plane, the number of
// faces with every other corner behind or in their plane (some behind), and their area.
static std::tuple<bool, std::vector<bool>> EveryCorner(const Patches<Polygon> &patches) {
    using Point = CGAL::Epick::Point_3;
    auto side = [](const Polygon &p, const Vec3 &v) {
        auto point = [](const Vec3 &x) { return Point(x.x(), x.y(), x.z()); };
        return int(CGAL::orientation(point(p.v[0]), point(p.v[1]), point(p.v[2]), point(v)));
    };
    bool separates = false;
    std::vector<bool> out(patches.size());
    for (size_t r = 0; r < patches.size(); ++r) {
        bool front = false, back = false;
        for (size_t k = 0; k < patches.size(); ++k)
            for (int c = 0; k != r && c < patches[k].shape.n; ++c) {
                int s = side(patches[r].shape, patches[k].shape.v[size_t(c)]);
                front |= s > 0, back |= s < 0;
            }
        separates |= front && back;
        out[r] = back && !front;
    }
    return {separates, out};
}

// Whether some connected part (faces sharing a corner, transitively) has more than half
// its area in faces that face out: the hint's rule, by brute force.
static bool SomePartFacesOut(const Patches<Polygon> &patches, const std::vector<bool> &out) {
    std::vector<size_t> part(patches.size());
    for (size_t r = 0; r < part.size(); ++r)
        part[r] = r;
    auto shares = [&](size_t a, size_t b) {
        for (int i = 0; i < patches[a].shape.n; ++i)
            for (int j = 0; j < patches[b].shape.n; ++j)
                if (patches[a].shape.v[size_t(i)] == patches[b].shape.v[size_t(j)])
                    return true;
        return false;
    };
    for (bool merged = true; merged;) {
        merged = false;
        for (size_t a = 0; a < part.size(); ++a)
            for (size_t b = 0; b < part.size(); ++b)
                if (part[a] != part[b] && shares(a, b)) {
                    size_t from = std::max(part[a], part[b]), to = std::min(part[a], part[b]);
                    for (size_t &p : part)
                        p = p == from ? to : p;
                    merged = true;
                }
    }
    std::map<size_t, std::pair<double, double>> areas;  // part -> (area, area facing out)
    for (size_t r = 0; r < patches.size(); ++r) {
        areas[part[r]].first += patches[r].shape.Area();
        areas[part[r]].second += out[r] ? patches[r].shape.Area() : 0;
    }
    for (const auto &[p, a] : areas)
        if (2 * a.second > a.first)
            return true;
    return false;
}

TEST_CASE("The scene-wide side tests, far corners first, agree with every corner tested",
          "[culling][mesh]") {
    auto asMesh = [](const Patches<Polygon> &patches, bool flip) {
        std::string obj;
        for (const auto &p : patches)
            for (int c = 0; c < p.shape.n; ++c)
                obj += "v " + std::to_string(p.shape.v[size_t(c)].x()) + " " +
                       std::to_string(p.shape.v[size_t(c)].y()) + " " +
                       std::to_string(p.shape.v[size_t(c)].z()) + "\n";
        for (size_t k = 0, v = 1; k < patches.size(); ++k) {
            std::vector<size_t> face;
            for (int c = 0; c < patches[k].shape.n; ++c)
                face.push_back(v++);
            if (flip)
                std::reverse(face.begin(), face.end());
            obj += "f";
            for (size_t f : face)
                obj += " " + std::to_string(f);
            obj += "\n";
        }
        return ParseMesh(obj, MeshFormat::Obj, "scene.obj", {});
    };
    std::vector<Scene> scenes;
    // Soups: the far corners often belong to the face tested, which then leaves them out.
    for (int seed = 1; seed <= 4; ++seed)
        scenes.push_back(asMesh(
            MakeScene("random3d", {{"n", 40}, {"seed", seed}, {"size", 3}}).Get<Polygon>(), false));
    // A closed sphere seen from inside, and from outside (each face hinted).
    for (bool flip : {false, true})
        scenes.push_back(asMesh(MakeScene("sphere", {{"n", 3}}).Get<Polygon>(), flip));
    // The outward sphere beside a lone triangle, whose corners are the far ones toward +x.
    Patches<Polygon> lone = MakeScene("sphere", {{"n", 2}}).Get<Polygon>();
    lone.push_back({Polygon::Triangle(Vec3(3, 0, 0), Vec3(3, 1, 0), Vec3(3, 0, 1)), {}});
    scenes.push_back(asMesh(lone, true));
    for (size_t s = 0; s < scenes.size(); ++s) {
        INFO("scene " << s);
        const Patches<Polygon> &patches = scenes[s].Get<Polygon>();
        auto [separates, out] = EveryCorner(patches);
        CHECK(CanOcclude(scenes[s]) == separates);
        std::string hint = FacingAwayHint(scenes[s]);
        CHECK(hint.empty() == !SomePartFacesOut(patches, out));
    }
}
