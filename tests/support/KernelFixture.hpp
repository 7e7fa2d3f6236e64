// The kernel tests' shared fixture: a distorted rectangle with two anisotropic materials in a
// checkerboard, its element data on the device (with the compliances for the mixed kernels), and
// the Eigen <-> device conversions the kernel and constraint tests compare through. Tests only.
#pragma once

#include <kernels/LinearElasticity.hpp>
#include <kernels/MixedElasticity.hpp>
#include <mesh/Generators.hpp>
#include <support/Reference.hpp>

#include <Eigen/SparseCore>

#include <random>
#include <vector>

namespace mixcon::test {

using Memory = Kokkos::DefaultExecutionSpace::memory_space;

struct Fixture {
  Mesh mesh;
  ElementData<Memory> data;
  std::vector<PlaneMatrix> materials;
  std::vector<int> elementMaterial;
};

/// Distorted mesh with two anisotropic materials assigned in a checkerboard.
inline Fixture makeFixture(ElementType type, int nx = 6, int ny = 5) {
  Fixture f;
  f.mesh = rectangleMesh(3.0, 2.0, nx, ny, type);
  test::distortInterior(f.mesh, 3.0 / nx, 0.2, 7);
  validateMesh(f.mesh);
  f.materials = {orthotropicStiffness({1.6e6, 1.1e5, 1.1e5, 1.0e5, 0.4, 0.4, 0.4},
                                      PlaneAnalysis::PlaneStress, 0.5),
                 isotropicStiffness(2.0e5, 0.3, PlaneAnalysis::PlaneStrain)};
  f.data.mesh = toDevice<Memory>(f.mesh);
  f.data.thickness = 0.7;
  f.data.material = Kokkos::View<int *, Memory>("material", f.mesh.numElements());
  f.data.stiffness = Kokkos::View<PlaneMatrix *, Memory>("stiffness", 2);
  auto hm = Kokkos::create_mirror_view(f.data.material);
  f.elementMaterial.resize(f.mesh.numElements());
  for (LocalIndex e = 0; e < f.mesh.numElements(); ++e)
    hm(e) = f.elementMaterial[e] = e % 2;
  Kokkos::deep_copy(f.data.material, hm);
  auto hs = Kokkos::create_mirror_view(f.data.stiffness);
  hs(0) = f.materials[0];
  hs(1) = f.materials[1];
  Kokkos::deep_copy(f.data.stiffness, hs);
  return f;
}

/// The fixture's element data with the compliance D = C^-1 of each of its materials.
inline MixedElementData<Memory> mixedElementData(const Fixture &f) {
  MixedElementData<Memory> d;
  static_cast<ElementData<Memory> &>(d) = f.data;
  d.compliance = Kokkos::View<PlaneMatrix *, Memory>("compliance", f.materials.size());
  auto h = Kokkos::create_mirror_view(d.compliance);
  for (std::size_t i = 0; i < f.materials.size(); ++i)
    invert3(f.materials[i], h(i));
  Kokkos::deep_copy(d.compliance, h);
  return d;
}

/// Random vector with entries in [-1, 1], reproducible by seed.
inline Eigen::VectorXd randomVector(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i)
    v(i) = d(rng);
  return v;
}

inline Kokkos::View<double *, Memory> toView(const Eigen::VectorXd &v) {
  Kokkos::View<double *, Memory> d("v", v.size());
  auto h = Kokkos::create_mirror_view(d);
  for (int i = 0; i < v.size(); ++i)
    h(i) = v(i);
  Kokkos::deep_copy(d, h);
  return d;
}

inline Eigen::VectorXd toEigen(const Kokkos::View<double *, Memory> &d) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), d);
  return Eigen::Map<const Eigen::VectorXd>(h.data(), h.extent(0));
}

/// Dense host copy of a CSR matrix.
inline Eigen::MatrixXd toDense(const CsrMatrix<Memory> &a) {
  auto ro = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.rowOffsets);
  auto co = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.columns);
  auto va = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.values);
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(a.numRows, a.numColumns);
  for (LocalIndex i = 0; i < a.numRows; ++i)
    for (Offset k = ro(i); k < ro(i + 1); ++k)
      d(i, co(k)) += va(k);
  return d;
}

/// A square n x n CSR matrix on the device from its host row offsets, columns and values.
inline CsrMatrix<Memory> csrToDevice(LocalIndex n, const std::vector<Offset> &ro,
                                     const std::vector<LocalIndex> &co,
                                     const std::vector<double> &va) {
  CsrMatrix<Memory> m;
  m.numRows = m.numColumns = n;
  m.rowOffsets = Kokkos::View<Offset *, Memory>("ro", ro.size());
  m.columns = Kokkos::View<LocalIndex *, Memory>("co", co.size());
  m.values = Kokkos::View<double *, Memory>("va", va.size());
  copyToDevice(m.rowOffsets, ro);
  copyToDevice(m.columns, co);
  copyToDevice(m.values, va);
  return m;
}

/// Device CSR copy of a dense square matrix with every entry stored (the full n x n pattern).
inline CsrMatrix<Memory> denseToCsr(const Eigen::MatrixXd &a) {
  const LocalIndex n = static_cast<LocalIndex>(a.rows());
  std::vector<Offset> ro(n + 1);
  std::vector<LocalIndex> co;
  std::vector<double> va;
  for (LocalIndex i = 0; i < n; ++i) {
    ro[i] = static_cast<Offset>(co.size());
    for (LocalIndex j = 0; j < n; ++j) {
      co.push_back(j);
      va.push_back(a(i, j));
    }
  }
  ro[n] = static_cast<Offset>(co.size());
  return csrToDevice(n, ro, co, va);
}

/// Device CSR copy of a compressed row-major Eigen sparse square matrix: its pattern and values.
template <class Index>
CsrMatrix<Memory> sparseToCsr(const Eigen::SparseMatrix<double, Eigen::RowMajor, Index> &a) {
  const std::vector<Offset> ro(a.outerIndexPtr(), a.outerIndexPtr() + a.rows() + 1);
  const std::vector<LocalIndex> co(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros());
  const std::vector<double> va(a.valuePtr(), a.valuePtr() + a.nonZeros());
  return csrToDevice(static_cast<LocalIndex>(a.rows()), ro, co, va);
}

inline double relativeError(const Eigen::MatrixXd &a, const Eigen::MatrixXd &b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

} // namespace mixcon::test
