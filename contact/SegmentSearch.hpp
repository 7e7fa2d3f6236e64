// Node-to-segment contact search, usable on its own (points and segments in, closest segments
// out; no other part of mixcon needed): for every query point the segment of a contact surface
// closest to it within a search radius, with the parametric coordinate of the closest point, the
// signed gap, the segment's unit normal and tangent there.
//  - Narrow phase: closest-point projection onto linear (2-node) and quadratic (3-node, Quad8
//    edge) segments; the quadratic one minimizes |x(xi) - p|^2 over xi in [-1, 1] (best of 17
//    samples, then Newton on (x - p) . x' = 0, clamped, compared with both ends).
//  - Broad phase: a uniform grid built with Kokkos (count, scan, fill): every segment is entered
//    in each cell that its bounding box (for a quadratic segment the box of its Bezier control
//    polygon, which contains the curve), grown by the radius, overlaps; a query tests only the
//    segments of its own cell. Every segment within the radius of a point has its grown box
//    around the point, so the grid returns exactly what the brute-force search returns.
//  - Ties (equal distances) go to the lowest segment index in both searches, so results are
//    identical, not just equally close.
// Conventions: a segment runs from its node 0 to its node 1 (node 2: the middle node of a
// quadratic segment, -1 for a linear one); the body lies on its left, the outward normal
// n = (t_y, -t_x) on its right (the orientation of mixcon's boundary edges); the gap is
// (p - c) . n at the closest point c, positive outside the body; where the closest point is an
// end of the segment the gap is +-|p - c| with the sign of (p - c) . n. A degenerate segment
// (coincident ends) has n = (p - c) / |p - c| and gap +|p - c|.
// Extension to 3D (node-to-face on Quad4/Quad8 faces) keeps the grid (3 indices per cell) and
// replaces the projection; nothing else here is 2D-specific. Data flow: solver -> contact.
#pragma once

#include <core/Compat.hpp>
#include <solver/LocalFrames.hpp>

#include <Kokkos_Core.hpp>

#include <algorithm>

namespace mixcon {

/// A contact surface: `points` (P x 2) and `nodes` (S x 3 point indices: the ends, then the
/// middle node of a quadratic segment or -1).
template <class MemorySpace> struct SegmentSet {
  Kokkos::View<const double *[2], MemorySpace> points;
  Kokkos::View<const int *[3], MemorySpace> nodes;
  LocalIndex size() const { return static_cast<LocalIndex>(nodes.extent(0)); }
};

/// Closest point of one query point on one segment.
struct SegmentProjection {
  double distance2 = 0.0; ///< squared distance to the closest point
  double xi = -1.0;       ///< its parametric coordinate in [-1, 1]
  double gap = 0.0;       ///< signed distance (positive outside the body)
  double normal[2] = {0.0, 0.0};
  double tangent[2] = {0.0, 0.0};
  double closest[2] = {0.0, 0.0};
};

/// Per query point: the closest segment within the radius (-1: none) and its projection.
template <class MemorySpace> struct SearchResults {
  Kokkos::View<int *, MemorySpace> segment;
  Kokkos::View<double *, MemorySpace> xi, gap;
  Kokkos::View<double *[2], MemorySpace> normal, tangent, closest;
  SearchResults() = default;
  explicit SearchResults(LocalIndex n)
      : segment("mixcon::search::segment", n), xi("mixcon::search::xi", n),
        gap("mixcon::search::gap", n), normal("mixcon::search::normal", n),
        tangent("mixcon::search::tangent", n), closest("mixcon::search::closest", n) {}
};

namespace search_detail {
#if KOKKOS_VERSION >= 30700
using Kokkos::hypot;
#else
using Kokkos::Experimental::hypot;
#endif

/// x(xi) and x'(xi) of a linear (m == nullptr) or quadratic segment.
KOKKOS_INLINE_FUNCTION void segmentPoint(const double (&a)[2], const double (&b)[2],
                                         const double (&m)[2], bool quadratic, double xi,
                                         double (&x)[2], double (&dx)[2]) {
  if (!quadratic) {
    for (int i = 0; i < 2; ++i) {
      x[i] = 0.5 * (1 - xi) * a[i] + 0.5 * (1 + xi) * b[i];
      dx[i] = 0.5 * (b[i] - a[i]);
    }
    return;
  }
  const double n0 = 0.5 * xi * (xi - 1), n1 = 0.5 * xi * (xi + 1), n2 = 1 - xi * xi;
  for (int i = 0; i < 2; ++i) {
    x[i] = n0 * a[i] + n1 * b[i] + n2 * m[i];
    dx[i] = (xi - 0.5) * a[i] + (xi + 0.5) * b[i] - 2 * xi * m[i];
  }
}

KOKKOS_INLINE_FUNCTION double distance2At(const double (&a)[2], const double (&b)[2],
                                          const double (&m)[2], bool quadratic, double xi,
                                          const double (&p)[2]) {
  double x[2], dx[2];
  segmentPoint(a, b, m, quadratic, xi, x, dx);
  return (x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]);
}

} // namespace search_detail

/// Parametric coordinate in [-1, 1] of the point of segment a-b (linear) or a-m-b (quadratic, m
/// the middle node at xi = 0) closest to p.
KOKKOS_INLINE_FUNCTION double closestParameter(const double (&p)[2], const double (&a)[2],
                                               const double (&b)[2], const double (&m)[2],
                                               bool quadratic) {
  using namespace search_detail;
  double xi = -1.0;
  if (!quadratic) {
    const double d[2] = {b[0] - a[0], b[1] - a[1]};
    const double len2 = d[0] * d[0] + d[1] * d[1];
    if (len2 > 0.0) {
      double t = ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2;
      t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
      xi = 2 * t - 1;
    }
    return xi;
  }
  // Best of 17 samples, Newton on f = (x - p) . x' from there (f' = x'.x' + (x - p).x''),
  // clamped to [-1, 1]; the ends are candidates too.
  double best = distance2At(a, b, m, true, -1.0, p);
  for (int k = 1; k <= 16; ++k) {
    const double s = -1.0 + k / 8.0, d2 = distance2At(a, b, m, true, s, p);
    if (d2 < best) {
      best = d2;
      xi = s;
    }
  }
  const double x2[2] = {a[0] + b[0] - 2 * m[0], a[1] + b[1] - 2 * m[1]}; // x''
  double z = xi;
  for (int it = 0; it < 20; ++it) {
    double x[2], dx[2];
    segmentPoint(a, b, m, true, z, x, dx);
    const double f = (x[0] - p[0]) * dx[0] + (x[1] - p[1]) * dx[1];
    const double fp = dx[0] * dx[0] + dx[1] * dx[1] + (x[0] - p[0]) * x2[0] + (x[1] - p[1]) * x2[1];
    if (!(fp > 0.0))
      break;
    double next = z - f / fp;
    next = next < -1.0 ? -1.0 : (next > 1.0 ? 1.0 : next);
    const bool done = detail::fabs(next - z) < 1e-15;
    z = next;
    if (done)
      break;
  }
  return distance2At(a, b, m, true, z, p) <= best ? z : xi;
}

/// The projection of p at parameter xi of the segment (closestParameter gives the closest).
KOKKOS_INLINE_FUNCTION SegmentProjection projectionAt(const double (&p)[2], const double (&a)[2],
                                                      const double (&b)[2], const double (&m)[2],
                                                      bool quadratic, double xi) {
  using namespace search_detail;
  SegmentProjection r;
  double x[2], dx[2];
  segmentPoint(a, b, m, quadratic, xi, x, dx);
  r.xi = xi;
  r.closest[0] = x[0];
  r.closest[1] = x[1];
  const double v[2] = {p[0] - x[0], p[1] - x[1]};
  r.distance2 = v[0] * v[0] + v[1] * v[1];
  const double dist = detail::sqrt(r.distance2);
  const double len = detail::sqrt(dx[0] * dx[0] + dx[1] * dx[1]);
  if (len > 0.0) {
    r.tangent[0] = dx[0] / len;
    r.tangent[1] = dx[1] / len;
    r.normal[0] = r.tangent[1];
    r.normal[1] = -r.tangent[0];
    const double along = v[0] * r.normal[0] + v[1] * r.normal[1];
    const bool end = xi <= -1.0 || xi >= 1.0;
    r.gap = end ? (along < 0.0 ? -dist : dist) : along;
  } else { // degenerate: no direction of its own
    r.normal[0] = dist > 0.0 ? v[0] / dist : 1.0;
    r.normal[1] = dist > 0.0 ? v[1] / dist : 0.0;
    double t[1][2];
    tangentBasis<2>(r.normal, t);
    r.tangent[0] = t[0][0];
    r.tangent[1] = t[0][1];
    r.gap = dist;
  }
  return r;
}

/// Closest-point projection of p onto the segment a-b (linear) or a-m-b (quadratic).
KOKKOS_INLINE_FUNCTION SegmentProjection projectOntoSegment(const double (&p)[2],
                                                            const double (&a)[2],
                                                            const double (&b)[2],
                                                            const double (&m)[2], bool quadratic) {
  return projectionAt(p, a, b, m, quadratic, closestParameter(p, a, b, m, quadratic));
}

namespace search_detail {

/// Nodes of segment s of `set`; returns whether it is quadratic.
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION bool segmentNodes(const SegmentSet<MemorySpace> &set, int s, double (&a)[2],
                                         double (&b)[2], double (&m)[2]) {
  const int ia = set.nodes(s, 0), ib = set.nodes(s, 1), im = set.nodes(s, 2);
  for (int i = 0; i < 2; ++i) {
    a[i] = set.points(ia, i);
    b[i] = set.points(ib, i);
    m[i] = im >= 0 ? set.points(im, i) : 0.0;
  }
  return im >= 0;
}

/// The closest segment so far: squared distance, parameter and index.
struct Candidate {
  double distance2 = 0.0, xi = 0.0;
  int segment = -1;
};

/// Tests segment s for query p: kept when within the radius and closer than the best so far
/// (equal distances go to the lower segment index).
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION void testSegment(const SegmentSet<MemorySpace> &set, int s,
                                        const double (&p)[2], double radius2, Candidate &best) {
  double a[2], b[2], m[2];
  const bool quadratic = segmentNodes(set, s, a, b, m);
  const double xi = closestParameter(p, a, b, m, quadratic);
  const double d2 = distance2At(a, b, m, quadratic, xi, p);
  if (d2 > radius2)
    return;
  if (best.segment < 0 || d2 < best.distance2 || (d2 == best.distance2 && s < best.segment)) {
    best.distance2 = d2;
    best.xi = xi;
    best.segment = s;
  }
}

/// Writes the projection of query k onto its closest segment (or -1 and zeros).
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION void store(const SegmentSet<MemorySpace> &set,
                                  const SearchResults<MemorySpace> &out, LocalIndex k,
                                  const double (&p)[2], const Candidate &c) {
  SegmentProjection r;
  if (c.segment >= 0) {
    double a[2], b[2], m[2];
    const bool quadratic = segmentNodes(set, c.segment, a, b, m);
    r = projectionAt(p, a, b, m, quadratic, c.xi);
  }
  const bool found = c.segment >= 0;
  out.segment(k) = c.segment;
  out.xi(k) = found ? r.xi : 0.0;
  out.gap(k) = found ? r.gap : 0.0;
  for (int i = 0; i < 2; ++i) {
    out.normal(k, i) = found ? r.normal[i] : 0.0;
    out.tangent(k, i) = found ? r.tangent[i] : 0.0;
    out.closest(k, i) = found ? r.closest[i] : 0.0;
  }
}

/// Bounding box of segment s (quadratic: of its Bezier control polygon a, 2m - (a + b)/2, b),
/// grown by r: box = {xmin, ymin, xmax, ymax}.
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION void segmentBox(const SegmentSet<MemorySpace> &set, int s, double r,
                                       double (&box)[4]) {
  const int ia = set.nodes(s, 0), ib = set.nodes(s, 1), im = set.nodes(s, 2);
  for (int i = 0; i < 2; ++i) {
    const double a = set.points(ia, i), b = set.points(ib, i);
    double lo = a < b ? a : b, hi = a < b ? b : a;
    if (im >= 0) {
      const double c = 2 * set.points(im, i) - 0.5 * (a + b);
      lo = c < lo ? c : lo;
      hi = c > hi ? c : hi;
    }
    box[i] = lo - r;
    box[2 + i] = hi + r;
  }
}

} // namespace search_detail

/// Brute force: every query against every segment (the reference of the grid search).
template <class ExecSpace, class MemorySpace>
void bruteForceSearch(const ExecSpace &exec, const SegmentSet<MemorySpace> &set,
                      const Kokkos::View<const double *[2], MemorySpace> &queries, double radius,
                      const SearchResults<MemorySpace> &out) {
  const int ns = set.size();
  const double r2 = radius * radius;
  Kokkos::parallel_for(
      "mixcon::search::bruteForce", Kokkos::RangePolicy<ExecSpace>(exec, 0, queries.extent(0)),
      KOKKOS_LAMBDA(LocalIndex k) {
        using namespace search_detail;
        const double p[2] = {queries(k, 0), queries(k, 1)};
        Candidate best;
        for (int s = 0; s < ns; ++s)
          testSegment(set, s, p, r2, best);
        store(set, out, k, p, best);
      });
}

/// Uniform-grid search: build() once per surface configuration, query() for any points. The
/// cells are folded into 2 S + 16 buckets (S segments; row-major cell index modulo the bucket
/// count), so the cell size follows the segments however sparse the surface is in its bounding
/// box (a curve in a plane); a bucket shared by several cells only adds candidates, never loses
/// one.
template <class ExecSpace, class MemorySpace = typename ExecSpace::memory_space> class SegmentGrid {
public:
  /// Bins the segments for queries within `radius` (> 0). `cellSize` 0 chooses the mean size of
  /// the segments' bounding boxes grown by the radius.
  void build(const ExecSpace &exec, const SegmentSet<MemorySpace> &set, double radius,
             double cellSize = 0.0);
  /// Closest segment within the radius for every query point.
  void query(const ExecSpace &exec, const Kokkos::View<const double *[2], MemorySpace> &queries,
             const SearchResults<MemorySpace> &out) const;
  /// Segment entries over all cells (a segment counts once per cell it is in), buckets, and the
  /// cell size.
  Offset entries() const { return entries_; }
  int buckets() const { return buckets_; }
  double cellSize() const { return h_; }

private:
  SegmentSet<MemorySpace> set_;
  double radius_ = 0.0, origin_[2] = {0.0, 0.0}, extent_[2] = {0.0, 0.0}, h_ = 1.0;
  int buckets_ = 0;
  Offset entries_ = 0;
  Kokkos::View<Offset *, MemorySpace> offsets_;
  Kokkos::View<int *, MemorySpace> cellSegments_;
};

namespace search_detail {

/// One bound of the grown segment boxes for a reduction: 0 xmin, 1 ymin, 2 xmax, 3 ymax, 4 the
/// box size (mean of its sides) for a sum.
template <class MemorySpace> struct BoxBound {
  SegmentSet<MemorySpace> set;
  double radius;
  int which;
  KOKKOS_INLINE_FUNCTION void operator()(int s, double &v) const {
    double box[4];
    segmentBox(set, s, radius, box);
    if (which < 2)
      v = box[which] < v ? box[which] : v;
    else if (which < 4)
      v = box[which] > v ? box[which] : v;
    else
      v += 0.5 * ((box[2] - box[0]) + (box[3] - box[1]));
  }
};

/// The hashed grid's geometry: cell (i, j) of a point at origin + h (i, j) + [0, h)^2, bucket
/// of a cell.
struct HashGrid {
  double origin[2], h;
  long long cells[2]; ///< cells along x and y (the grown boxes' extent)
  int buckets;
  /// Row-major cell index modulo the bucket count: neighbouring cells of a row share cache
  /// lines, and a cell list of a surface stays local in memory (computed modulo M throughout,
  /// so no overflow for any grid size).
  KOKKOS_INLINE_FUNCTION int bucket(long long i, long long j) const {
    const unsigned long long m = static_cast<unsigned long long>(buckets);
    const unsigned long long k =
        static_cast<unsigned long long>(i) % m +
        (static_cast<unsigned long long>(j) % m) * (static_cast<unsigned long long>(cells[0]) % m);
    return static_cast<int>(k % m);
  }
  /// Cells [i0, i1] x [j0, j1] overlapped by a box (clamped to the grid).
  KOKKOS_INLINE_FUNCTION void range(const double (&box)[4], long long (&r)[4]) const {
    for (int i = 0; i < 2; ++i) {
      double lo = (box[i] - origin[i]) / h, hi = (box[2 + i] - origin[i]) / h;
      lo = lo < 0.0 ? 0.0 : lo;
      hi = hi > cells[i] - 1 ? cells[i] - 1 : hi;
      r[i] = static_cast<long long>(lo);
      r[2 + i] = static_cast<long long>(hi);
    }
  }
};

/// Adds one entry per cell overlapped by segment s to its bucket: counts (fill == false) or
/// segment indices at offsets + cursor (fill == true).
template <class MemorySpace> struct BinSegments {
  SegmentSet<MemorySpace> set;
  double radius;
  HashGrid grid;
  Kokkos::View<Offset *, MemorySpace> count, offsets;
  Kokkos::View<int *, MemorySpace> cells;
  bool fill;
  KOKKOS_INLINE_FUNCTION void operator()(int s) const {
    double box[4];
    segmentBox(set, s, radius, box);
    long long r[4];
    grid.range(box, r);
    for (long long j = r[1]; j <= r[3]; ++j)
      for (long long i = r[0]; i <= r[2]; ++i) {
        const int b = grid.bucket(i, j);
        if (fill)
          cells(offsets(b) + Kokkos::atomic_fetch_add(&count(b), Offset(1))) = s;
        else
          Kokkos::atomic_add(&count(b), Offset(1));
      }
  }
};

/// Exclusive prefix sum of counts into offsets (one more entry: the total).
template <class MemorySpace> struct ScanCounts {
  Kokkos::View<Offset *, MemorySpace> count, offsets;
  KOKKOS_INLINE_FUNCTION void operator()(int c, Offset &partial, bool final) const {
    if (final)
      offsets(c) = partial;
    partial += count(c);
  }
};

/// Closest segment of every query among the segments of its cell's bucket.
template <class MemorySpace> struct QueryGrid {
  SegmentSet<MemorySpace> set;
  HashGrid grid;
  double radius2;
  Kokkos::View<const Offset *, MemorySpace> offsets;
  Kokkos::View<const int *, MemorySpace> cells;
  Kokkos::View<const double *[2], MemorySpace> queries;
  SearchResults<MemorySpace> out;
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex k) const {
    const double p[2] = {queries(k, 0), queries(k, 1)};
    Candidate best;
    const double u = (p[0] - grid.origin[0]) / grid.h, v = (p[1] - grid.origin[1]) / grid.h;
    if (u >= 0.0 && v >= 0.0 && u < grid.cells[0] && v < grid.cells[1]) {
      const int b = grid.bucket(static_cast<long long>(u), static_cast<long long>(v));
      for (Offset e = offsets(b); e < offsets(b + 1); ++e)
        testSegment(set, cells(e), p, radius2, best);
    }
    store(set, out, k, p, best);
  }
};

} // namespace search_detail

template <class ExecSpace, class MemorySpace>
void SegmentGrid<ExecSpace, MemorySpace>::build(const ExecSpace &exec,
                                                const SegmentSet<MemorySpace> &set, double radius,
                                                double cellSize) {
  using namespace search_detail;
  set_ = set;
  radius_ = radius;
  const int ns = set.size();
  // Extent of the grown boxes and their mean size.
  double lo[2] = {0.0, 0.0}, hi[2] = {1.0, 1.0}, meanSize = 0.0;
  if (ns > 0) {
    const Kokkos::RangePolicy<ExecSpace> policy(exec, 0, ns);
    Kokkos::parallel_reduce("mixcon::search::xmin", policy, BoxBound<MemorySpace>{set, radius, 0},
                            Kokkos::Min<double>(lo[0]));
    Kokkos::parallel_reduce("mixcon::search::ymin", policy, BoxBound<MemorySpace>{set, radius, 1},
                            Kokkos::Min<double>(lo[1]));
    Kokkos::parallel_reduce("mixcon::search::xmax", policy, BoxBound<MemorySpace>{set, radius, 2},
                            Kokkos::Max<double>(hi[0]));
    Kokkos::parallel_reduce("mixcon::search::ymax", policy, BoxBound<MemorySpace>{set, radius, 3},
                            Kokkos::Max<double>(hi[1]));
    Kokkos::parallel_reduce("mixcon::search::size", policy, BoxBound<MemorySpace>{set, radius, 4},
                            Kokkos::Sum<double>(meanSize));
    meanSize /= ns;
  }
  double h = cellSize > 0.0 ? cellSize : meanSize;
  const double span = std::max({hi[0] - lo[0], hi[1] - lo[1], 1e-300});
  if (!(h > 0.0))
    h = span;
  h = std::max(h, span / 1e15); // cell indices stay exact in double and long long
  h_ = h;
  origin_[0] = lo[0];
  origin_[1] = lo[1];
  HashGrid grid{{lo[0], lo[1]},
                h,
                {static_cast<long long>((hi[0] - lo[0]) / h) + 1,
                 static_cast<long long>((hi[1] - lo[1]) / h) + 1},
                2 * ns + 16};
  extent_[0] = static_cast<double>(grid.cells[0]);
  extent_[1] = static_cast<double>(grid.cells[1]);
  buckets_ = grid.buckets;
  // Count, scan, fill.
  Kokkos::View<Offset *, MemorySpace> count("mixcon::search::count", buckets_ + 1);
  offsets_ = Kokkos::View<Offset *, MemorySpace>("mixcon::search::offsets", buckets_ + 1);
  const Kokkos::RangePolicy<ExecSpace> segments(exec, 0, ns);
  Kokkos::parallel_for("mixcon::search::countCells", segments,
                       BinSegments<MemorySpace>{set, radius, grid, count, offsets_, {}, false});
  Kokkos::parallel_scan("mixcon::search::scan",
                        Kokkos::RangePolicy<ExecSpace>(exec, 0, buckets_ + 1),
                        ScanCounts<MemorySpace>{count, offsets_});
  Offset total = 0;
  Kokkos::deep_copy(exec, total, Kokkos::subview(offsets_, buckets_));
  exec.fence();
  entries_ = total;
  cellSegments_ = Kokkos::View<int *, MemorySpace>("mixcon::search::cellSegments", entries_);
  Kokkos::deep_copy(exec, count, Offset(0));
  Kokkos::parallel_for(
      "mixcon::search::fillCells", segments,
      BinSegments<MemorySpace>{set, radius, grid, count, offsets_, cellSegments_, true});
  exec.fence();
}

template <class ExecSpace, class MemorySpace>
void SegmentGrid<ExecSpace, MemorySpace>::query(
    const ExecSpace &exec, const Kokkos::View<const double *[2], MemorySpace> &queries,
    const SearchResults<MemorySpace> &out) const {
  using namespace search_detail;
  const HashGrid grid{{origin_[0], origin_[1]},
                      h_,
                      {static_cast<long long>(extent_[0]), static_cast<long long>(extent_[1])},
                      buckets_};
  Kokkos::parallel_for(
      "mixcon::search::query", Kokkos::RangePolicy<ExecSpace>(exec, 0, queries.extent(0)),
      QueryGrid<MemorySpace>{set_, grid, radius_ * radius_, offsets_, cellSegments_, queries, out});
}

} // namespace mixcon
