// Shape functions and quadrature of the element traits (core/ElementTraits.hpp) against the
// independent reference in tests/support and finite differences.
#include <core/ElementTraits.hpp>
#include <support/Reference.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <stdexcept>
#include <string>

using namespace mixcon;

template <class Elem> class ElementTraitsTest : public ::testing::Test {};
using ElementTypes = ::testing::Types<Quad4, Quad8>;
TYPED_TEST_SUITE(ElementTraitsTest, ElementTypes);

TYPED_TEST(ElementTraitsTest, KroneckerDeltaAtNodesAndPartitionOfUnity) {
  using Elem = TypeParam;
  for (int b = 0; b < Elem::kNumNodes; ++b) {
    double xi, eta, n[Elem::kNumNodes], dn[Elem::kNumNodes][2];
    Elem::nodeNatural(b, xi, eta);
    Elem::shape(xi, eta, n, dn);
    for (int a = 0; a < Elem::kNumNodes; ++a)
      EXPECT_NEAR(n[a], a == b ? 1.0 : 0.0, 1e-14) << "N_" << a << " at node " << b;
  }
  for (double xi : {-0.7, 0.1, 0.9})
    for (double eta : {-0.3, 0.5}) {
      double n[Elem::kNumNodes], dn[Elem::kNumNodes][2], s = 0, sx = 0, se = 0;
      Elem::shape(xi, eta, n, dn);
      for (int a = 0; a < Elem::kNumNodes; ++a) {
        s += n[a];
        sx += dn[a][0];
        se += dn[a][1];
      }
      EXPECT_NEAR(s, 1.0, 1e-14);
      EXPECT_NEAR(sx, 0.0, 1e-14);
      EXPECT_NEAR(se, 0.0, 1e-14);
    }
}

TYPED_TEST(ElementTraitsTest, MatchesReferenceAndFiniteDifferences) {
  using Elem = TypeParam;
  const double h = 1e-6;
  for (double xi : {-0.77, 0.0, 0.31})
    for (double eta : {-0.5, 0.66}) {
      double n[Elem::kNumNodes], dn[Elem::kNumNodes][2];
      double np[Elem::kNumNodes], nm[Elem::kNumNodes], tmp[Elem::kNumNodes][2];
      Elem::shape(xi, eta, n, dn);
      Eigen::VectorXd rn;
      Eigen::MatrixXd rdn;
      test::referenceShape(Elem::kNumNodes, xi, eta, rn, rdn);
      for (int a = 0; a < Elem::kNumNodes; ++a) {
        EXPECT_NEAR(n[a], rn(a), 1e-14);
        EXPECT_NEAR(dn[a][0], rdn(a, 0), 1e-14);
        EXPECT_NEAR(dn[a][1], rdn(a, 1), 1e-14);
      }
      Elem::shape(xi + h, eta, np, tmp);
      Elem::shape(xi - h, eta, nm, tmp);
      for (int a = 0; a < Elem::kNumNodes; ++a)
        EXPECT_NEAR(dn[a][0], (np[a] - nm[a]) / (2 * h), 1e-8);
      Elem::shape(xi, eta + h, np, tmp);
      Elem::shape(xi, eta - h, nm, tmp);
      for (int a = 0; a < Elem::kNumNodes; ++a)
        EXPECT_NEAR(dn[a][1], (np[a] - nm[a]) / (2 * h), 1e-8);
    }
}

TYPED_TEST(ElementTraitsTest, QuadratureIntegratesPolynomialsExactly) {
  using Elem = TypeParam;
  // Gauss with p points per direction integrates xi^i eta^j exactly for i, j <= 2p - 1.
  const int p = Elem::kGaussOrder;
  for (int i = 0; i <= 2 * p - 1; ++i)
    for (int j = 0; j <= 2 * p - 1; ++j) {
      double s = 0.0;
      for (int q = 0; q < Elem::kNumQp; ++q) {
        double xi, eta, w;
        Elem::quadraturePoint(q, xi, eta, w);
        s += w * std::pow(xi, i) * std::pow(eta, j);
      }
      const double exact = (i % 2 ? 0.0 : 2.0 / (i + 1)) * (j % 2 ? 0.0 : 2.0 / (j + 1));
      EXPECT_NEAR(s, exact, 1e-14) << "xi^" << i << " eta^" << j;
    }
}

TYPED_TEST(ElementTraitsTest, JacobianGivesAreaOfMappedElement) {
  using Elem = TypeParam;
  // A straight-sided general quadrilateral: area by the shoelace formula.
  const double corners[4][2] = {{0.1, -0.2}, {2.3, 0.1}, {1.9, 1.7}, {-0.2, 1.2}};
  double xe[Elem::kNumNodes][2];
  for (int a = 0; a < 4; ++a) {
    xe[a][0] = corners[a][0];
    xe[a][1] = corners[a][1];
  }
  for (int a = 4; a < Elem::kNumNodes; ++a)
    for (int c = 0; c < 2; ++c)
      xe[a][c] = 0.5 * (corners[a - 4][c] + corners[(a - 3) % 4][c]);
  double area = 0.0, shoelace = 0.0;
  for (int a = 0; a < 4; ++a)
    shoelace +=
        0.5 * (corners[a][0] * corners[(a + 1) % 4][1] - corners[(a + 1) % 4][0] * corners[a][1]);
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double xi, eta, w, n[Elem::kNumNodes], dn[Elem::kNumNodes][2], g[Elem::kNumNodes][2];
    Elem::quadraturePoint(q, xi, eta, w);
    Elem::shape(xi, eta, n, dn);
    area += w * physicalGradients<Elem>(xe, dn, g);
  }
  EXPECT_NEAR(area, shoelace, 1e-13);
}

TEST(EdgeShape, InterpolatesAndDifferentiates) {
  for (double s : {-1.0, -0.4, 0.0, 0.8, 1.0}) {
    double n2[2], d2[2], n3[3], d3[3];
    edgeShape<2>(s, n2, d2);
    edgeShape<3>(s, n3, d3);
    EXPECT_NEAR(n2[0] + n2[1], 1.0, 1e-15);
    EXPECT_NEAR(n3[0] + n3[1] + n3[2], 1.0, 1e-15);
    // Reproduce x(s) = s and x(s) = s^2 (nodes at -1, 1, 0).
    EXPECT_NEAR(-n2[0] + n2[1], s, 1e-15);
    EXPECT_NEAR(-n3[0] + n3[1], s, 1e-15);
    EXPECT_NEAR(n3[0] + n3[1], s * s, 1e-15);
    EXPECT_NEAR(d3[0] + d3[1], 2 * s, 1e-15);
  }
}

namespace {
/// The default execution space Kokkos picks among the backends this build enabled (Kokkos'
/// order: a device backend, then host threads, then Serial), from the configuration macros.
const char *expectedDefaultSpace() {
#if defined(KOKKOS_ENABLE_CUDA)
  return "Cuda";
#elif defined(KOKKOS_ENABLE_HIP)
  return "HIP";
#elif defined(KOKKOS_ENABLE_SYCL)
  return "SYCL";
#elif defined(KOKKOS_ENABLE_OPENMPTARGET)
  return "OpenMPTarget";
#elif defined(KOKKOS_ENABLE_OPENMP)
  return "OpenMP";
#elif defined(KOKKOS_ENABLE_THREADS)
  return "Threads";
#elif defined(KOKKOS_ENABLE_HPX)
  return "HPX";
#else
  return "Serial";
#endif
}
} // namespace

TEST(ElementDispatch, ChoosesTheTraitsAndRefusesUnknownTypes) {
  EXPECT_EQ(dispatchElement(ElementType::Quad4, [](auto e) { return decltype(e)::kNumNodes; }), 4);
  EXPECT_EQ(dispatchElement(ElementType::Quad8, [](auto e) { return decltype(e)::kNumNodes; }), 8);
  EXPECT_EQ(dispatchElement(ElementType::Quad8,
                            [](auto e) { return LayoutOf<decltype(e)>::kMixedUnknowns; }),
            5);
  // A value outside the enumeration (e.g. a corrupted restart record) is an error, not a Quad4.
  const auto unknown = static_cast<ElementType>(7);
  try {
    dispatchElement(unknown, [](auto e) { return decltype(e)::kNumNodes; });
    FAIL() << "dispatchElement accepted an unknown element type";
  } catch (const std::invalid_argument &e) {
    EXPECT_NE(std::string(e.what()).find("7"), std::string::npos) << e.what();
  }
}

TEST(Backend, RunsOnTheExpectedKokkosBackend) {
  const std::string actual = Kokkos::DefaultExecutionSpace::name();
  const int concurrency = Kokkos::DefaultExecutionSpace().concurrency();
  std::cout << "Kokkos default execution space: " << actual << " with " << concurrency
            << " threads\n";
  EXPECT_EQ(actual, expectedDefaultSpace()) << "the default space of the enabled backends";
  EXPECT_GE(concurrency, 1);
  if (actual == "Serial") {
    EXPECT_EQ(concurrency, 1);
  }
  // OpenMP runs as many threads as OMP_NUM_THREADS asks (its first entry when it is a list),
  // unless Kokkos' own KOKKOS_NUM_THREADS overrides it.
  const char *threads = std::getenv("OMP_NUM_THREADS");
  if (actual == "OpenMP" && threads != nullptr && std::atoi(threads) > 0 &&
      std::getenv("KOKKOS_NUM_THREADS") == nullptr) {
    EXPECT_EQ(concurrency, std::atoi(threads)) << "OMP_NUM_THREADS=" << threads;
  }
  // CI sets MIXCON_EXPECT_BACKEND=OpenMP: races hide under Serial, so the suite must run threaded.
  const char *expected = std::getenv("MIXCON_EXPECT_BACKEND");
  if (expected != nullptr) {
    EXPECT_EQ(actual, expected);
    EXPECT_GE(concurrency, 2);
  }
}
