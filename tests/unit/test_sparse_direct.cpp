// SparseDirect (CHOLMOD Cholesky, UMFPACK LU; solver/SparseDirect.hpp) against a plain host
// reference: Eigen's dense LU with full pivoting of the same matrix.
#include <solver/LinearSolver.hpp>
#include <solver/SparseDirect.hpp>
#include <support/KernelFixture.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <dlfcn.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include <cmath>
#include <cstdio>
#include <vector>

namespace mixcon {
namespace {

/// A CSR matrix with its dense copy (the reference).
struct TestMatrix {
  std::vector<Offset> rows{0};
  std::vector<LocalIndex> columns;
  std::vector<double> values;
  Eigen::MatrixXd dense;

  explicit TestMatrix(int n) : dense(Eigen::MatrixXd::Zero(n, n)) {}
  HostCsr csr() const {
    return HostCsr{static_cast<std::int64_t>(dense.rows()), rows.data(), columns.data(),
                   values.data()};
  }
};

/// The 5-point Laplacian of an m x m grid, Dirichlet on all sides (SPD), plus `shift` on the
/// diagonal and `skew` times a nonsymmetric first-derivative term; each row's columns are
/// written in reverse order (CSR inputs need not be sorted).
TestMatrix grid(int m, double shift, double skew) {
  const int n = m * m;
  TestMatrix a(n);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const int r = i * m + j;
      std::vector<std::pair<int, double>> row;
      row.emplace_back(r, 4.0 + shift);
      if (i > 0)
        row.emplace_back(r - m, -1.0 - skew);
      if (i + 1 < m)
        row.emplace_back(r + m, -1.0 + skew);
      if (j > 0)
        row.emplace_back(r - 1, -1.0);
      if (j + 1 < m)
        row.emplace_back(r + 1, -1.0);
      for (auto it = row.rbegin(); it != row.rend(); ++it) {
        a.columns.push_back(it->first);
        a.values.push_back(it->second);
        a.dense(r, it->first) = it->second;
      }
      a.rows.push_back(static_cast<Offset>(a.columns.size()));
    }
  return a;
}

std::vector<double> rightHandSide(int n) {
  std::vector<double> b(n);
  for (int i = 0; i < n; ++i)
    b[i] = std::sin(0.7 * i + 0.3);
  return b;
}

/// max |x - x_ref| / max |x_ref| with x_ref from Eigen's dense full-pivoting LU.
double errorAgainstDense(const TestMatrix &a, const std::vector<double> &b,
                         const std::vector<double> &x) {
  const Eigen::VectorXd ref =
      a.dense.fullPivLu().solve(Eigen::Map<const Eigen::VectorXd>(b.data(), b.size()));
  return (Eigen::Map<const Eigen::VectorXd>(x.data(), x.size()) - ref).cwiseAbs().maxCoeff() /
         ref.cwiseAbs().maxCoeff();
}

TEST(SparseDirect, CholeskyOfAPositiveDefiniteMatrixMatchesTheDenseReference) {
  const TestMatrix a = grid(30, 0.0, 0.0); // 900 unknowns
  SparseDirect f;
  ASSERT_EQ(f.factor(SparseDirect::Method::Cholesky, a.csr()), SparseDirect::Outcome::Factored);
  const auto b = rightHandSide(900);
  std::vector<double> x(900), r(900);
  f.solve(b.data(), x.data());
  EXPECT_LT(errorAgainstDense(a, b, x), 1e-12);
  EXPECT_LT(f.residual(b.data(), x.data(), r.data()), 1e-12);
  // min/max pivot of the Dirichlet Laplacian: well above round-off, below 1.
  EXPECT_GT(f.pivotRatio(), 1e-3);
  EXPECT_LT(f.pivotRatio(), 1.0);
  EXPECT_STREQ(SparseDirect::name(f.method()), "CHOLMOD Cholesky");
}

TEST(SparseDirect, LuOfANonsymmetricMatrixMatchesTheDenseReference) {
  const TestMatrix a = grid(25, 0.5, 0.4);
  SparseDirect f;
  ASSERT_EQ(f.factor(SparseDirect::Method::Lu, a.csr()), SparseDirect::Outcome::Factored);
  const auto b = rightHandSide(625);
  std::vector<double> x(625), r(625);
  f.solve(b.data(), x.data());
  EXPECT_LT(errorAgainstDense(a, b, x), 1e-12);
  // The residual r = b - A x, entry by entry against the dense product.
  const double rn = f.residual(b.data(), x.data(), r.data());
  const Eigen::VectorXd ref = Eigen::Map<const Eigen::VectorXd>(b.data(), 625) -
                              a.dense * Eigen::Map<const Eigen::VectorXd>(x.data(), 625);
  EXPECT_NEAR(rn, ref.norm(), 1e-14);
  EXPECT_NEAR(r[17], ref(17), 1e-14);
  EXPECT_STREQ(SparseDirect::name(f.method()), "UMFPACK LU");
}

// solveRefined: no step is the plain solve; with steps, the residual it returns is that of the x
// it returns, never above the plain solve's, and x is still the dense reference's.
TEST(SparseDirect, RefinedSolveReturnsTheResidualOfItsSolution) {
  const TestMatrix a = grid(25, 0.5, 0.4);
  SparseDirect f;
  ASSERT_EQ(f.factor(SparseDirect::Method::Lu, a.csr()), SparseDirect::Outcome::Factored);
  const auto b = rightHandSide(625);
  std::vector<double> plain(625), x0(625), x3(625), r(625);
  f.solve(b.data(), plain.data());
  const double r0 = f.solveRefined(b.data(), x0.data(), 0, 0.0);
  EXPECT_EQ(x0, plain);
  EXPECT_EQ(r0, f.residual(b.data(), plain.data(), r.data()));
  const double r3 = f.solveRefined(b.data(), x3.data(), 3, 0.0);
  EXPECT_EQ(r3, f.residual(b.data(), x3.data(), r.data()));
  EXPECT_LE(r3, r0);
  EXPECT_LT(errorAgainstDense(a, b, x3), 1e-12);
}

// A threaded OpenBLAS is held to one thread inside factor() and solve() and given its count
// back, and the caller's OpenMP thread count is left as it was (OpenBLAS's OpenMP build sets
// it). Run here with Debian's serial, pthread and OpenMP OpenBLAS builds selected in turn.
TEST(SparseDirect, BlasAndOpenMpThreadCountsAreGivenBack) {
  using Get = int (*)();
  const auto get = reinterpret_cast<Get>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  EXPECT_EQ(SparseDirect::controlsBlasThreads(), get != nullptr);
  const int blasBefore = get ? get() : 0;
#ifdef _OPENMP
  const int openmpBefore = omp_get_max_threads();
#endif
  std::printf("  BLAS threads: %d (%s)\n", blasBefore,
              get ? "OpenBLAS" : "not OpenBLAS, not controlled");
  const TestMatrix a = grid(20, 0.0, 0.0);
  SparseDirect f;
  ASSERT_EQ(f.factor(SparseDirect::Method::Cholesky, a.csr()), SparseDirect::Outcome::Factored);
  const auto b = rightHandSide(400);
  std::vector<double> x(400);
  f.solve(b.data(), x.data());
  ASSERT_EQ(f.factor(SparseDirect::Method::Lu, a.csr()), SparseDirect::Outcome::Factored);
  f.solve(b.data(), x.data());
  EXPECT_LT(errorAgainstDense(a, b, x), 1e-12);
  if (get) {
    EXPECT_EQ(get(), blasBefore);
  }
#ifdef _OPENMP
  EXPECT_EQ(omp_get_max_threads(), openmpBefore);
#endif
}

TEST(SparseDirect, CholeskyRefusesAnIndefiniteMatrixWhichLuSolves) {
  // Eigenvalues of the Dirichlet Laplacian shifted by -3.3: of both signs, none near zero. At
  // this size CHOLMOD's factor is simplicial, whose default LDL' would take negative pivots.
  const TestMatrix a = grid(12, -3.3, 0.0);
  SparseDirect f;
  EXPECT_EQ(f.factor(SparseDirect::Method::Cholesky, a.csr()),
            SparseDirect::Outcome::NotPositiveDefinite);
  ASSERT_EQ(f.factor(SparseDirect::Method::Lu, a.csr()), SparseDirect::Outcome::Factored);
  const auto b = rightHandSide(144);
  std::vector<double> x(144);
  f.solve(b.data(), x.data());
  EXPECT_LT(errorAgainstDense(a, b, x), 1e-10);
}

TEST(SparseDirect, SingularMatricesAreReported) {
  // The Neumann Laplacian of a path (each row sums to zero): singular, the constant its kernel.
  const int n = 50;
  TestMatrix a(n);
  for (int i = 0; i < n; ++i) {
    const double d = (i == 0 || i == n - 1) ? 1.0 : 2.0;
    if (i > 0)
      a.columns.push_back(i - 1), a.values.push_back(-1.0);
    a.columns.push_back(i), a.values.push_back(d);
    if (i + 1 < n)
      a.columns.push_back(i + 1), a.values.push_back(-1.0);
    a.rows.push_back(static_cast<Offset>(a.columns.size()));
  }
  SparseDirect f;
  const auto outcome = f.factor(SparseDirect::Method::Cholesky, a.csr());
  EXPECT_TRUE(outcome == SparseDirect::Outcome::NotPositiveDefinite || !(f.pivotRatio() > 1e-14))
      << "pivot ratio " << f.pivotRatio();
  // An exactly zero row: LU's zero pivot.
  TestMatrix z = grid(6, 0.0, 0.3);
  for (Offset k = z.rows[7]; k < z.rows[8]; ++k)
    z.values[k] = 0.0;
  EXPECT_EQ(f.factor(SparseDirect::Method::Lu, z.csr()), SparseDirect::Outcome::Singular);
}

TEST(SparseDirect, TheAnalysisIsReusedForTheSamePatternAndRedoneForAnother) {
  TestMatrix a = grid(20, 0.0, 0.0);
  SparseDirect f;
  const auto b = rightHandSide(400);
  std::vector<double> x(400);
  for (auto method : {SparseDirect::Method::Cholesky, SparseDirect::Method::Lu}) {
    const int before = f.analysisReuses();
    ASSERT_EQ(f.factor(method, a.csr()), SparseDirect::Outcome::Factored);
    EXPECT_EQ(f.analysisReuses(), before); // a new method: analysed anew
    // New values on the same pattern (a contact correction): the kept analysis, the new numbers.
    TestMatrix c = a;
    for (std::size_t k = 0; k < c.values.size(); ++k)
      c.values[k] *= 1.0 + 0.1 * ((k % 3) == 0);
    for (std::size_t r = 0; r + 1 < c.rows.size(); ++r)
      for (Offset k = c.rows[r]; k < c.rows[r + 1]; ++k)
        c.dense(static_cast<Eigen::Index>(r), c.columns[k]) = c.values[k];
    // Keep it symmetric for the Cholesky: symmetrize the dense copy and the CSR values.
    c.dense = 0.5 * (c.dense + c.dense.transpose()).eval();
    for (std::size_t r = 0; r + 1 < c.rows.size(); ++r)
      for (Offset k = c.rows[r]; k < c.rows[r + 1]; ++k)
        c.values[k] = c.dense(static_cast<Eigen::Index>(r), c.columns[k]);
    ASSERT_EQ(f.factor(method, c.csr()), SparseDirect::Outcome::Factored);
    EXPECT_EQ(f.analysisReuses(), before + 1);
    f.solve(b.data(), x.data());
    EXPECT_LT(errorAgainstDense(c, b, x), 1e-12);
    // Another pattern (one more grid line): analysed anew, still right.
    const TestMatrix d = grid(21, 0.0, 0.0);
    ASSERT_EQ(f.factor(method, d.csr()), SparseDirect::Outcome::Factored);
    EXPECT_EQ(f.analysisReuses(), before + 1);
    const auto bd = rightHandSide(441);
    std::vector<double> xd(441);
    f.solve(bd.data(), xd.data());
    EXPECT_LT(errorAgainstDense(d, bd, xd), 1e-12);
  }
}

/// A CSR matrix of the given pattern (every entry 1: estimateCholesky reads no values).
TestMatrix pattern(int n, const std::vector<std::vector<int>> &rows) {
  TestMatrix a(n);
  for (const auto &row : rows) {
    for (int c : row) {
      a.columns.push_back(c);
      a.values.push_back(1.0);
    }
    a.rows.push_back(static_cast<Offset>(a.columns.size()));
  }
  return a;
}

/// CHOLMOD's figures for a Cholesky factor whose columns hold c_j entries (the diagonal
/// included): sum c_j entries and sum c_j^2 flops (cholmod_rowcolcounts).
SparseDirect::Estimate figures(const std::vector<int> &columnCounts) {
  SparseDirect::Estimate e;
  for (int c : columnCounts) {
    e.factorEntries += c;
    e.flops += static_cast<double>(c) * c;
  }
  return e;
}

TEST(SparseDirect, TheCostEstimateCountsTheFactorOfAnyOrdering) {
  // Patterns whose factor's column counts are the same for every fill-reducing ordering: a dense
  // matrix (n, n - 1, ..., 1), a path numbered out of order (a tree: no fill, 2, ..., 2, 1) and
  // a diagonal one (1 each).
  const int n = 12;
  std::vector<std::vector<int>> dense(n), path(n), diagonal(n);
  std::vector<int> denseCounts, pathCounts(n, 2);
  pathCounts.back() = 1;
  for (int i = 0; i < n; ++i) {
    for (int j = n - 1; j >= 0; --j)
      dense[i].push_back(j);
    denseCounts.push_back(n - i);
    diagonal[i] = {i};
  }
  std::vector<int> position(n); // the path's k-th vertex is unknown (5 k) mod 12
  for (int k = 0; k < n; ++k)
    position[k] = (5 * k) % n;
  for (int k = 0; k < n; ++k) {
    path[position[k]].push_back(position[k]);
    if (k > 0)
      path[position[k]].push_back(position[k - 1]);
    if (k + 1 < n)
      path[position[k]].push_back(position[k + 1]);
  }
  for (const auto &[rows, counts] : {std::pair{dense, denseCounts}, std::pair{path, pathCounts},
                                     std::pair{diagonal, std::vector<int>(n, 1)}}) {
    const SparseDirect::Estimate e = SparseDirect::estimateCholesky(pattern(n, rows).csr());
    const SparseDirect::Estimate reference = figures(counts);
    EXPECT_EQ(e.factorEntries, reference.factorEntries);
    EXPECT_EQ(e.flops, reference.flops);
  }
  // A 2D grid fills in: more entries than its lower triangle, fewer than dense.
  const TestMatrix g = grid(20, 0.0, 0.0);
  const SparseDirect::Estimate e = SparseDirect::estimateCholesky(g.csr());
  EXPECT_GT(e.factorEntries, (g.values.size() + 400) / 2.0);
  EXPECT_LT(e.factorEntries, 400.0 * 401.0 / 2.0);
  // The model of its time: the per-entry term plus the flops, twice those for an LU.
  const double nnz = static_cast<double>(g.values.size());
  const double cholesky = detail::estimatedDirectSeconds(g.rows.back(), e.flops, true);
  EXPECT_NEAR(cholesky,
              nnz * detail::kDirectSecondsPerNonzero + e.flops / detail::kDirectFlopsPerSecond,
              1e-12 * cholesky);
  EXPECT_NEAR(detail::estimatedDirectSeconds(g.rows.back(), e.flops, false) - cholesky,
              e.flops / detail::kDirectFlopsPerSecond, 1e-9 * cholesky);
}

TEST(SparseDirect, SymmetryToRoundOffIsDetected) {
  TestMatrix a = grid(10, 0.0, 0.0);
  EXPECT_TRUE(SparseDirect::isSymmetric(a.csr(), 1e-12, 0.0));
  a.values[5] *= 1.0 + 1e-14; // round-off
  EXPECT_TRUE(SparseDirect::isSymmetric(a.csr(), 1e-12, 0.0));
  a.values[5] *= 1.0 + 1e-9;
  EXPECT_FALSE(SparseDirect::isSymmetric(a.csr(), 1e-12, 0.0));
  EXPECT_TRUE(SparseDirect::isSymmetric(a.csr(), 1e-12, 1e-6)); // below the absolute bound
  EXPECT_FALSE(SparseDirect::isSymmetric(grid(10, 0.0, 0.2).csr(), 1e-12, 0.0));
  // An entry below the diagonal whose partner above is absent.
  TestMatrix b(3);
  b.rows = {0, 1, 3, 4};
  b.columns = {0, 0, 1, 2};
  b.values = {2.0, -1.0, 2.0, 2.0};
  EXPECT_FALSE(SparseDirect::isSymmetric(b.csr(), 1e-12, 0.0));
  b.values[1] = 0.0; // an explicit zero: symmetric
  EXPECT_TRUE(SparseDirect::isSymmetric(b.csr(), 1e-12, 0.0));
}

/// The direct LinearSolver told the matrix is not symmetric (as the nonlinear models say of their
/// exact tangent) on `a`: its name after the setup, and its solution's error against the dense
/// reference.
std::pair<std::string, double> directSolve(const Eigen::MatrixXd &a) {
  const Eigen::SparseMatrix<double, Eigen::RowMajor, int> sparse = a.sparseView();
  LinearSolverOptions o;
  o.type = LinearSolverType::Direct;
  o.symmetric = false;
  o.tolerance = 1e-12;
  const auto n = static_cast<LocalIndex>(a.rows());
  auto solver = makeLinearSolver(o, DofMap::serial(n / 2, 2), MPI_COMM_WORLD);
  solver->setup(test::sparseToCsr(sparse));
  const std::vector<double> b = rightHandSide(n);
  Kokkos::View<double *, test::Memory> bd("b", n), xd("x", n);
  copyToDevice(bd, b);
  const LinearSolveStats stats = solver->solve(bd, xd);
  EXPECT_TRUE(stats.converged) << stats.relativeResidual;
  const auto xh = copyToHost(xd);
  const std::vector<double> x(xh.data(), xh.data() + n);
  TestMatrix reference(n);
  reference.dense = a;
  return {solver->name(), errorAgainstDense(reference, b, x)};
}

// A matrix said to be nonsymmetric but symmetric to round-off (linear kinematics, frictionless
// contact) is factored by Cholesky, half the LU's work; one that is not, by LU.
TEST(SparseDirect, TheDirectSolverTakesTheCholeskyWhereTheMatrixIsSymmetricToRoundOff) {
  Eigen::MatrixXd a = grid(16, 0.0, 0.0).dense; // 256 unknowns, SPD
  a(3, 19) *= 1.0 + 1e-15;                      // round-off apart from a(19, 3)
  auto [name, error] = directSolve(a);
  EXPECT_EQ(name, "direct (CHOLMOD Cholesky)");
  EXPECT_LT(error, 1e-12);
  a(3, 19) *= 1.0 + 1e-6; // no longer symmetric
  std::tie(name, error) = directSolve(a);
  EXPECT_EQ(name, "direct (UMFPACK LU)");
  EXPECT_LT(error, 1e-12);
  // Symmetric but indefinite: the Cholesky meets a negative pivot, the LU takes over.
  std::tie(name, error) = directSolve(grid(16, -3.3, 0.0).dense);
  EXPECT_EQ(name, "direct (UMFPACK LU)");
  EXPECT_LT(error, 1e-10);
}

} // namespace
} // namespace mixcon
