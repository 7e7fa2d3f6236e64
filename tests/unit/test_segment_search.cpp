// Node-to-segment search (contact/SegmentSearch.hpp): projections against host formulas and
// dense sampling; the grid search against the brute-force search (identical segment, xi and gap)
// on random and adversarial geometries: queries exactly on segment ends and nodes (ties),
// collinear segments, degenerate (zero-length) segments, points outside the grid.
#include <contact/SegmentSearch.hpp>
#include <mesh/Mesh.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace mixcon;
using Exec = Kokkos::DefaultExecutionSpace;
using Memory = Exec::memory_space;

namespace segment_search_tests {

struct Surface {
  std::vector<double> points;  // 2 per point
  std::vector<int> nodes;      // 3 per segment
  std::vector<double> queries; // 2 per query
};

struct Found {
  std::vector<int> segment;
  std::vector<double> xi, gap, normal;
};

Found search(const Surface &s, double radius, bool grid) {
  const LocalIndex np = static_cast<LocalIndex>(s.points.size() / 2);
  const LocalIndex ns = static_cast<LocalIndex>(s.nodes.size() / 3);
  const LocalIndex nq = static_cast<LocalIndex>(s.queries.size() / 2);
  Kokkos::View<double *[2], Memory> p("p", np), q("q", nq);
  Kokkos::View<int *[3], Memory> n("n", ns);
  auto hp = Kokkos::create_mirror_view(p);
  auto hq = Kokkos::create_mirror_view(q);
  auto hn = Kokkos::create_mirror_view(n);
  for (LocalIndex i = 0; i < np; ++i)
    for (int c = 0; c < 2; ++c)
      hp(i, c) = s.points[2 * i + c];
  for (LocalIndex i = 0; i < nq; ++i)
    for (int c = 0; c < 2; ++c)
      hq(i, c) = s.queries[2 * i + c];
  for (LocalIndex i = 0; i < ns; ++i)
    for (int c = 0; c < 3; ++c)
      hn(i, c) = s.nodes[3 * i + c];
  Kokkos::deep_copy(p, hp);
  Kokkos::deep_copy(q, hq);
  Kokkos::deep_copy(n, hn);
  const SegmentSet<Memory> set{p, n};
  SearchResults<Memory> out(nq);
  if (grid) {
    SegmentGrid<Exec> g;
    g.build(Exec(), set, radius);
    g.query(Exec(), Kokkos::View<const double *[2], Memory>(q), out);
  } else {
    bruteForceSearch(Exec(), set, Kokkos::View<const double *[2], Memory>(q), radius, out);
  }
  Found f;
  auto seg = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out.segment);
  auto xi = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out.xi);
  auto gap = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out.gap);
  auto nor = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out.normal);
  for (LocalIndex k = 0; k < nq; ++k) {
    f.segment.push_back(seg(k));
    f.xi.push_back(xi(k));
    f.gap.push_back(gap(k));
    f.normal.push_back(nor(k, 0));
    f.normal.push_back(nor(k, 1));
  }
  return f;
}

void expectIdentical(const Surface &s, double radius) {
  const Found a = search(s, radius, false), b = search(s, radius, true);
  int found = 0;
  for (std::size_t k = 0; k < a.segment.size(); ++k) {
    ASSERT_EQ(a.segment[k], b.segment[k]) << "query " << k;
    EXPECT_EQ(a.xi[k], b.xi[k]) << "query " << k;
    EXPECT_EQ(a.gap[k], b.gap[k]) << "query " << k;
    found += a.segment[k] >= 0;
  }
  EXPECT_GT(found, 0);
}

/// A closed wavy loop of n segments around the origin, counter-clockwise (the body inside, on
/// the left), linear or quadratic; queries scattered around it.
Surface wavyLoop(int n, bool quadratic, int nq, unsigned seed) {
  Surface s;
  const int per = quadratic ? 2 : 1;
  const int np = per * n;
  for (int i = 0; i < np; ++i) {
    const double t = 2 * M_PI * i / np;
    const double r = 1.0 + 0.2 * std::sin(5 * t);
    s.points.push_back(r * std::cos(t));
    s.points.push_back(r * std::sin(t));
  }
  for (int e = 0; e < n; ++e) {
    s.nodes.push_back(per * e);
    s.nodes.push_back((per * e + per) % np);
    s.nodes.push_back(quadratic ? per * e + 1 : -1);
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int k = 0; k < nq; ++k) {
    s.queries.push_back(u(rng));
    s.queries.push_back(u(rng));
  }
  return s;
}

} // namespace segment_search_tests
using namespace segment_search_tests;

TEST(SegmentSearch, LinearProjectionMatchesHostFormulaAndSignsTheGap) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const double m[2] = {0.0, 0.0};
  for (int k = 0; k < 200; ++k) {
    const double a[2] = {u(rng), u(rng)}, b[2] = {u(rng), u(rng)}, p[2] = {u(rng), u(rng)};
    const SegmentProjection r = projectOntoSegment(p, a, b, m, false);
    const double d[2] = {b[0] - a[0], b[1] - a[1]};
    const double t = std::clamp(
        ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]), 0.0, 1.0);
    const double c[2] = {a[0] + t * d[0], a[1] + t * d[1]};
    EXPECT_NEAR(r.xi, 2 * t - 1, 1e-14);
    EXPECT_NEAR(r.closest[0], c[0], 1e-14);
    EXPECT_NEAR(std::abs(r.gap), std::hypot(p[0] - c[0], p[1] - c[1]), 1e-14);
    // Outward normal on the right of a -> b: the sign of the cross product.
    const double cross = d[0] * (p[1] - a[1]) - d[1] * (p[0] - a[0]);
    if (std::abs(cross) > 1e-9) {
      EXPECT_EQ(r.gap > 0, cross < 0) << k;
    }
  }
}

TEST(SegmentSearch, QuadraticProjectionIsTheClosestPointOfTheCurve) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 100; ++k) {
    const double a[2] = {-1.0 + 0.2 * u(rng), 0.2 * u(rng)},
                 b[2] = {1.0 + 0.2 * u(rng), 0.2 * u(rng)};
    const double m[2] = {0.3 * u(rng), 0.6 * u(rng)}; // curved
    const double p[2] = {1.5 * u(rng), 1.5 * u(rng)};
    const SegmentProjection r = projectOntoSegment(p, a, b, m, true);
    double best = 1e300;
    for (int i = 0; i <= 200000; ++i) {
      const double xi = -1.0 + i * 1e-5;
      const double n0 = 0.5 * xi * (xi - 1), n1 = 0.5 * xi * (xi + 1), n2 = 1 - xi * xi;
      const double x = n0 * a[0] + n1 * b[0] + n2 * m[0], y = n0 * a[1] + n1 * b[1] + n2 * m[1];
      best = std::min(best, std::hypot(x - p[0], y - p[1]));
    }
    EXPECT_LE(std::sqrt(r.distance2), best + 1e-12) << k;
    EXPECT_GE(std::sqrt(r.distance2), best - 1e-8) << k;
  }
}

TEST(SegmentSearch, GridEqualsBruteForceOnRandomLinearAndQuadraticSurfaces) {
  for (bool quadratic : {false, true})
    for (double radius : {0.02, 0.3, 5.0}) {
      SCOPED_TRACE(std::string(quadratic ? "quadratic" : "linear") + " radius " +
                   std::to_string(radius));
      expectIdentical(wavyLoop(97, quadratic, 3000, 11), radius);
    }
  // Gap sign: the loop is counter-clockwise with the body inside; the origin is inside.
  Surface s = wavyLoop(64, true, 0, 1);
  s.queries = {0.0, 0.0, 3.0, 0.0};
  const Found f = search(s, 10.0, true);
  EXPECT_LT(f.gap[0], 0.0);
  EXPECT_GT(f.gap[1], 0.0);
}

TEST(SegmentSearch, GridEqualsBruteForceOnAdversarialGeometries) {
  // A collinear chain along y = 0 with a zero-length segment in it, a short quadratic segment
  // and queries exactly on every node (ties between neighbours), on the line, on its extension,
  // and far outside the grid.
  Surface s;
  const double xs[] = {0.0, 0.25, 0.5, 0.5, 1.0, 1.5};
  for (double x : xs) {
    s.points.push_back(x);
    s.points.push_back(0.0);
  }
  for (int e = 0; e < 5; ++e) { // segment 2 is degenerate (0.5 -> 0.5)
    s.nodes.push_back(e);
    s.nodes.push_back(e + 1);
    s.nodes.push_back(-1);
  }
  s.points.insert(s.points.end(), {2.0, 0.0, 2.0, 1.0, 2.2, 0.5}); // quadratic, middle bulged
  s.nodes.insert(s.nodes.end(), {6, 7, 8});
  for (double x : xs)
    s.queries.insert(s.queries.end(), {x, 0.0});
  s.queries.insert(s.queries.end(), {0.1, 0.0, 1.2, 0.0, 1.8, 0.0, -0.3, 0.0, 0.5, 0.3, 2.0, 0.5,
                                     2.1, 0.5, 1e6, 1e6, -1e6, 0.0});
  for (double radius : {1e-9, 0.25, 0.4, 3.0}) {
    SCOPED_TRACE("radius " + std::to_string(radius));
    const Found a = search(s, radius, false), b = search(s, radius, true);
    for (std::size_t k = 0; k < a.segment.size(); ++k) {
      EXPECT_EQ(a.segment[k], b.segment[k]) << "query " << k;
      EXPECT_EQ(a.xi[k], b.xi[k]) << "query " << k;
      EXPECT_EQ(a.gap[k], b.gap[k]) << "query " << k;
    }
    // A query on the shared node of segments 0 and 1 ties: the lower index wins.
    EXPECT_EQ(b.segment[1], 0);
    // Far points find nothing.
    EXPECT_EQ(b.segment[a.segment.size() - 2], -1);
    EXPECT_EQ(b.segment[a.segment.size() - 1], -1);
  }
}
