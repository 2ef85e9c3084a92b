// Form factors without occlusion (form_factor.h; the rules are stated in docs/solve.md):
// flatland by crossed strings, exactly; 3D by Lambert's contour formula at a point,
// integrated over the emitting polygon by an adaptive tensor Gauss-Legendre rule.
#include "solve/form_factor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace hrbench {

namespace {

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------
// Flatland

double Cross2(const Vec2 &p, const Vec2 &q) { return p.x() * q.y() - p.y() * q.x(); }

// Cuts _s_ down to its part strictly in front of (left of) the line of _other_; false
// when no part is. The clip point is computed from the end that is cut away, so an end
// lying on the line (the shared corner of two walls) is kept bit for bit.
bool ClipToFront(Segment &s, const Segment &other) {
    Vec2 dir = other.b - other.a;
    double da = Cross2(dir, s.a - other.a), db = Cross2(dir, s.b - other.a);
    if (!(da > 0) && !(db > 0))
        return false;
    if (!(da > 0))
        s.a = s.a + (s.b - s.a) * (da / (da - db));
    else if (!(db > 0))
        s.b = s.b + (s.a - s.b) * (db / (db - da));
    return true;
}

// ---------------------------------------------------------------------------------------
// 3D: Lambert's formula

// A convex polygon: a triangle or quad cut by at most three planes, each of which adds
// at most one corner.
struct Corners {
    std::array<Vec3, 8> v;
    int n = 0;
};

// Sutherland-Hodgman: the part of _in_ strictly in front of the plane through _origin_
// with normal _normal_. As in ClipToFront, a corner on the plane stays exact; repeated
// corners are dropped, so the result has no zero-length edge.
Corners ClipToFront(const Corners &in, const Vec3 &origin, const Vec3 &normal) {
    Corners out;
    auto push = [&out](const Vec3 &p) {
        if (out.n == 0 || p != out.v[out.n - 1])
            out.v[out.n++] = p;
    };
    for (int k = 0; k < in.n; ++k) {
        const Vec3 &a = in.v[k], &b = in.v[(k + 1) % in.n];
        double da = normal.dot(a - origin), db = normal.dot(b - origin);
        if (da > 0)
            push(a);
        if ((da > 0) != (db > 0))
            push(da > 0 ? Vec3(b + (a - b) * (db / (db - da)))
                        : Vec3(a + (b - a) * (da / (da - db))));
    }
    if (out.n > 1 && out.v[out.n - 1] == out.v[0])
        --out.n;
    if (out.n < 3)
        out.n = 0;
    return out;
}

Corners CornersOf(const Polygon &p) {
    Corners c;
    for (int k = 0; k < p.n; ++k)
        c.v[k] = p.v[k];
    c.n = p.n;
    return c;
}

// Lambert's formula for a differential area at _x_ (unit normal _normal_) and a convex
// polygon _w_ that lies in front of x's tangent plane and is counter-clockwise seen from
// x: (1/2pi) sum_k gamma_k normal . unit(R_{k+1} x R_k), R_k = w_k - x. (R_k x R_{k+1},
// the usual order, points away from x for a polygon that x sees counter-clockwise.) The
// angle gamma_k is atan2(|cross|, dot), accurate at every angle.
double Lambert(const Vec3 &x, const Vec3 &normal, const Corners &w) {
    double sum = 0;
    Vec3 r0 = w.v[w.n - 1] - x;
    for (int k = 0; k < w.n; ++k) {
        Vec3 r1 = w.v[k] - x;
        Vec3 c = r1.cross(r0);
        double sine = c.norm();
        if (sine > 0)
            sum += std::atan2(sine, r0.dot(r1)) * normal.dot(c) / sine;
        r0 = r1;
    }
    return sum / (2 * kPi);
}

// ---------------------------------------------------------------------------------------
// 3D: the emitter as pieces, each a map of the unit square

// x(s, t) = o + s a + t b + s t c for (s, t) in [0, 1]^2.
struct Piece {
    Vec3 o, a, b, c;
};

// Bilinear: v0 at (0,0), v1 at (1,0), v2 at (1,1), v3 at (0,1).
Piece QuadPiece(const Vec3 &v0, const Vec3 &v1, const Vec3 &v2, const Vec3 &v3) {
    return {v0, v1 - v0, v3 - v0, v2 - v1 - v3 + v0};
}

// Collapsed (Duffy): x = v0 + s (v1 - v0) + s t (v2 - v1), the side s = 0 collapsed to the
// apex v0; the three edges are sides of the square and the Jacobian, 2 A s, is a
// polynomial. A function of the direction from v0 alone is a function of t alone here.
Piece TrianglePiece(const Vec3 &apex, const Vec3 &v1, const Vec3 &v2) {
    return {apex, v1 - apex, Vec3::Zero(), v2 - v1};
}

// At most 18: two fans of at most 7 triangles (one per edge of a heptagon: a quad cut by
// three planes) around a contact, and 4 for the rest (a hexagon).
struct Pieces {
    std::array<Piece, 18> piece;
    int n = 0;
    void Add(const Piece &p) { piece[n++] = p; }
};

// A convex polygon without singular points: bilinear if a quad, else a fan of triangles.
void AddPlain(const Corners &p, Pieces &out) {
    if (p.n == 4) {
        out.Add(QuadPiece(p.v[0], p.v[1], p.v[2], p.v[3]));
        return;
    }
    for (int k = 1; k + 1 < p.n; ++k)
        out.Add(TrianglePiece(p.v[0], p.v[k], p.v[k + 1]));
}

// Where the receiver touches the emitter's plane (along a shared edge, at a shared
// corner), the point form factor is bounded but, at the ends of the contact, depends on
// the direction of approach: a point singularity that tensor rules resolve only by
// refining toward it geometrically, some 15 levels for 1e-9. At the apex of collapsed
// triangles it is a smooth function of t instead. Fans _p_ (convex) from _apex_ (in p
// or on its boundary, within _tolerance_), leaving out the edges that contain it.
void AddFan(const Corners &p, const Vec3 &apex, double tolerance, Pieces &out) {
    for (int k = 0; k < p.n; ++k) {
        const Vec3 &a = p.v[k], &b = p.v[(k + 1) % p.n];
        if ((a - apex).cross(b - apex).norm() > tolerance * (b - a).norm())
            out.Add(TrianglePiece(apex, a, b));
    }
}

// Around a contact segment from _s0_ to _s1_: the band of _p_ within half the segment's
// length of it, cut across at its midpoint into two halves, each fanned from its end
// of the segment; the rest of p (if any) is plain. The band keeps the triangles from
// becoming slivers as long as the polygon.
void AddAroundContact(const Corners &p, const Vec3 &s0, const Vec3 &s1, const Vec3 &normal,
                      double tolerance, Pieces &out) {
    Vec3 along = s1 - s0;
    double length = along.norm();
    Vec3 inward = normal.cross(along / length), centroid = Vec3::Zero();
    for (int k = 0; k < p.n; ++k)
        centroid += p.v[k] / p.n;
    if (inward.dot(centroid - s0) < 0)
        inward = -inward;
    Vec3 cut = s0 + 0.5 * length * inward, middle = 0.5 * (s0 + s1);
    Corners band = ClipToFront(p, cut, -inward), rest = ClipToFront(p, cut, inward);
    if (band.n == 0 || rest.n == 0) {  // p is no deeper than the band
        band = p;
        rest.n = 0;
    }
    AddFan(ClipToFront(band, middle, -along), s0, tolerance, out);
    AddFan(ClipToFront(band, middle, along), s1, tolerance, out);
    AddPlain(rest, out);
}

// ---------------------------------------------------------------------------------------
// 3D: the adaptive rule over the pieces

// The Gauss-Legendre nodes and weights on [0, 1] of the two orders of the rule, 4 and 6.
constexpr std::array<double, 4> kLowNodes = {0.069431844202973712388, 0.330009478207571867599,
                                             0.669990521792428132401, 0.930568155797026287612};
constexpr std::array<double, 4> kLowWeights = {0.173927422568726928687, 0.326072577431273071313,
                                               0.326072577431273071313, 0.173927422568726928687};
constexpr std::array<double, 6> kHighNodes = {0.0337652428984239860938, 0.169395306766867743169,
                                              0.380690406958401545685,  0.619309593041598454315,
                                              0.830604693233132256831,  0.966234757101576013906};
constexpr std::array<double, 6> kHighWeights = {0.0856622461895851725201, 0.180380786524069303785,
                                                0.233956967286345523695,  0.233956967286345523695,
                                                0.180380786524069303785,  0.0856622461895851725201};

// The quadrature rule of FormFactor(Polygon, Polygon) (docs/solve.md#form-factors):
//  - the pieces of the emitter (above) are maps of the unit square;
//  - a cell's value is the 6x6 tensor Gauss-Legendre rule, its error estimate the
//    difference from the 4x4 rule: 52 evaluations of Lambert's formula. That estimates
//    the error of the 4x4 rule, so the 6x6 value is in practice better than it says (5
//    to 400 times below the tolerance, docs/solve.md); a 3x3/4x4 pair, cheaper, was
//    fooled (3x3 and 4x4 agreeing on a wrong value) by a factor of 20 on some pairs
//    sharing an edge;
//  - globally adaptive: while the estimates add up to more than kTolerance times the
//    integral (or kAbsoluteTolerance times the emitter's area), the cell of largest
//    estimate is halved in s, in t, or both: in one direction only when the rule of
//    order 4 in that direction (and 6 in the other: 24 more evaluations each way)
//    differs from the 6x6 by more than kAnisotropy times the rule of order 4 in the
//    other direction does;
//  - a cell halved kMaxDepth times in a direction is no longer halved that way, and the
//    rule stops after kMaxCells cells: it always terminates.
constexpr double kTolerance = 1e-7;
constexpr double kAbsoluteTolerance = 1e-15;
constexpr double kAnisotropy = 4;
constexpr int kMaxDepth = 40;
constexpr int kMaxCells = 1000;

struct Cell {
    double s0, s1, t0, t1;
    double value, error;
    int piece, depthS, depthT;
};

// The integrand F(dA(x) -> receiver) |dx/ds x dx/dt| on the emitter's pieces.
class Integrand {
  public:
    Integrand(const Vec3 &emitterNormal, const Corners &receiver, const Vec3 &receiverNormal,
              const Pieces &pieces)
        : normal_(emitterNormal), receiver_(receiver), receiverNormal_(receiverNormal),
          pieces_(pieces) {}

    int Count() const { return pieces_.n; }

    double operator()(int piece, double s, double t) const {
        const Piece &p = pieces_.piece[piece];
        Vec3 x = p.o + s * p.a + t * p.b + (s * t) * p.c;
        // The receiver's back, or its plane, sends nothing.
        if (!(receiverNormal_.dot(x - receiver_.v[0]) > 0))
            return 0;
        double jacobian = (p.a + t * p.c).cross(p.b + s * p.c).norm();
        return Lambert(x, normal_, receiver_) * jacobian;
    }

  private:
    Vec3 normal_;
    Corners receiver_;
    Vec3 receiverNormal_;
    const Pieces &pieces_;
};

// The tensor Gauss-Legendre rule of orders NS (in s) and NT (in t) on a cell.
template <size_t NS, size_t NT>
double TensorRule(const Integrand &f, const Cell &c, const std::array<double, NS> &nodesS,
                  const std::array<double, NS> &weightsS, const std::array<double, NT> &nodesT,
                  const std::array<double, NT> &weightsT) {
    double ds = c.s1 - c.s0, dt = c.t1 - c.t0, sum = 0;
    for (size_t i = 0; i < NS; ++i) {
        double row = 0;
        for (size_t j = 0; j < NT; ++j)
            row += weightsT[j] * f(c.piece, c.s0 + ds * nodesS[i], c.t0 + dt * nodesT[j]);
        sum += weightsS[i] * row;
    }
    return sum * ds * dt;
}

void Evaluate(const Integrand &f, Cell &c) {
    c.value = TensorRule(f, c, kHighNodes, kHighWeights, kHighNodes, kHighWeights);
    c.error = std::abs(c.value - TensorRule(f, c, kLowNodes, kLowWeights, kLowNodes, kLowWeights));
}

bool ByError(const Cell &x, const Cell &y) { return x.error < y.error; }

// _scale_ is the emitter's area, which bounds the integral (form factors are at most 1).
bool Converged(double error, double total, double scale) {
    return !(error > std::max(kTolerance * std::abs(total), kAbsoluteTolerance * scale));
}

// The children of _c_ that halve it in s, in t, or both (see the rule above).
int Split(const Integrand &f, const Cell &c, std::array<Cell, 4> &children) {
    bool splitS = c.depthS < kMaxDepth, splitT = c.depthT < kMaxDepth;
    if (splitS && splitT) {
        double errorS =
            std::abs(c.value - TensorRule(f, c, kLowNodes, kLowWeights, kHighNodes, kHighWeights));
        double errorT =
            std::abs(c.value - TensorRule(f, c, kHighNodes, kHighWeights, kLowNodes, kLowWeights));
        splitS = !(errorT > kAnisotropy * errorS);
        splitT = !(errorS > kAnisotropy * errorT);
    }
    double sm = 0.5 * (c.s0 + c.s1), tm = 0.5 * (c.t0 + c.t1);
    int count = 0;
    for (int i = 0; i < (splitS ? 2 : 1); ++i)
        for (int j = 0; j < (splitT ? 2 : 1); ++j) {
            Cell child = c;
            if (splitS) {
                (i == 0 ? child.s1 : child.s0) = sm;
                ++child.depthS;
            }
            if (splitT) {
                (j == 0 ? child.t1 : child.t0) = tm;
                ++child.depthT;
            }
            children[count++] = child;
        }
    return count;
}

// The integral of _f_ over all its pieces (of total area _area_), by the rule above.
double Integrate(const Integrand &f, double area) {
    std::array<Cell, 18> roots;
    double total = 0, error = 0;
    for (int k = 0; k < f.Count(); ++k) {
        roots[k] = Cell{0, 1, 0, 1, 0, 0, k, 0, 0};
        Evaluate(f, roots[k]);
        total += roots[k].value;
        error += roots[k].error;
    }
    // Separated polygons: one rule per piece, and no allocation.
    if (Converged(error, total, area))
        return total;
    std::vector<Cell> open(roots.begin(), roots.begin() + f.Count()), done;
    std::make_heap(open.begin(), open.end(), ByError);
    int cells = f.Count();
    while (!open.empty() && !Converged(error, total, area) && cells < kMaxCells) {
        std::pop_heap(open.begin(), open.end(), ByError);
        Cell c = open.back();
        open.pop_back();
        error -= c.error;
        if (c.depthS >= kMaxDepth && c.depthT >= kMaxDepth) {
            done.push_back(c);  // its value stays in the total, its error is given up
            continue;
        }
        total -= c.value;
        std::array<Cell, 4> children;
        int count = Split(f, c, children);
        for (int k = 0; k < count; ++k) {
            Evaluate(f, children[k]);
            total += children[k].value;
            error += children[k].error;
            open.push_back(children[k]);
            std::push_heap(open.begin(), open.end(), ByError);
        }
        cells += count;
    }
    // Sum afresh: the running total has absorbed and removed every parent.
    double sum = 0;
    for (const Cell &c : done)
        sum += c.value;
    for (const Cell &c : open)
        sum += c.value;
    return sum;
}

}  // namespace

double FormFactor(const Segment &from, const Segment &to) {
    double length = from.Length();
    if (!(length > 0))
        return 0;
    Segment p = from, q = to;
    if (!ClipToFront(q, from) || !ClipToFront(p, to))
        return 0;
    // Clipped, p and q lie on the boundary of the convex region in front of both lines,
    // each oriented along it: a convex quadrilateral p.a p.b q.a q.b, whose diagonals are
    // the crossed strings and whose other two sides the uncrossed ones.
    double crossed = (p.a - q.a).norm() + (p.b - q.b).norm();
    double uncrossed = (p.b - q.a).norm() + (q.b - p.a).norm();
    return std::max(0.0, (crossed - uncrossed) / (2 * length));
}

double PointToPolygonFormFactor(const Vec3 &point, const Vec3 &normal, const Polygon &polygon) {
    if (!(polygon.Normal().dot(point - polygon.v[0]) > 0))
        return 0;
    Corners visible = ClipToFront(CornersOf(polygon), point, normal);
    if (visible.n == 0)
        return 0;
    return std::max(0.0, Lambert(point, normal, visible));
}

double FormFactor(const Polygon &from, const Polygon &to) {
    double area = from.Area();
    if (!(area > 0))
        return 0;
    Vec3 fromNormal = from.Normal(), toNormal = to.Normal();
    // Every point of _from_ has the same tangent plane: clip _to_ to it once.
    Corners receiver = ClipToFront(CornersOf(to), from.v[0], fromNormal);
    if (receiver.n == 0)
        return 0;
    // Contact is decided within 1e-9 of _from_'s size, and never finer than 1e-13 of its
    // coordinates, whose rounding would hide it.
    double magnitude = 0;
    for (int k = 0; k < from.n; ++k)
        magnitude = std::max(magnitude, from.v[k].cwiseAbs().maxCoeff());
    double tolerance = std::max(1e-9 * from.Diameter(), 1e-13 * magnitude);
    // The part of _from_ behind _to_'s plane sends nothing. A corner behind it by no
    // more than the tolerance (the shared edge of two walls) keeps the whole polygon.
    bool whole = true, any = false;
    for (int k = 0; k < from.n; ++k) {
        double d = toNormal.dot(from.v[k] - to.v[0]);
        whole = whole && d >= -tolerance;
        any = any || d > 0;
    }
    if (!any)
        return 0;
    Corners emitter = whole ? CornersOf(from) : ClipToFront(CornersOf(from), to.v[0], toNormal);
    if (emitter.n == 0)
        return 0;
    // The receiver's corners in _from_'s plane and on _from_, projected onto the plane:
    // the singular points of the integrand.
    Corners singular;
    for (int k = 0; k < receiver.n && singular.n < 2; ++k) {
        double height = fromNormal.dot(receiver.v[k] - from.v[0]);
        if (std::abs(height) > tolerance)
            continue;
        Vec3 point = receiver.v[k] - height * fromNormal;
        bool inside = true;
        for (int i = 0; i < emitter.n; ++i) {
            Vec3 edge = emitter.v[(i + 1) % emitter.n] - emitter.v[i];
            double side = fromNormal.cross(edge).normalized().dot(point - emitter.v[i]);
            inside = inside && side >= -tolerance;
        }
        bool known = singular.n > 0 && (point - singular.v[0]).norm() <= tolerance;
        if (inside && !known)
            singular.v[singular.n++] = point;
    }
    Pieces pieces;
    if (singular.n == 2)
        AddAroundContact(emitter, singular.v[0], singular.v[1], fromNormal, tolerance, pieces);
    else if (singular.n == 1)
        AddFan(emitter, singular.v[0], tolerance, pieces);
    else
        AddPlain(emitter, pieces);
    Integrand f(fromNormal, receiver, toNormal, pieces);
    return std::max(0.0, Integrate(f, area) / area);
}

}  // namespace hrbench
