// Random small tensors (core/Tensor.hpp's Mat and Vector) for the point-law and element-driver
// tests: entries uniform in [-amount, amount], drawn row by row. Tests only.
#pragma once

#include <core/Tensor.hpp>

#include <random>

namespace mixcon::test {

/// A Dim x Dim matrix with entries drawn from `rng`.
template <int Dim> Mat<Dim, Dim> randomMatrix(std::mt19937 &rng, double amount) {
  std::uniform_real_distribution<double> u(-amount, amount);
  Mat<Dim, Dim> m{};
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j)
      m.m[i][j] = u(rng);
  return m;
}

/// A Dim x Dim matrix from a generator of its own, reproducible by seed.
template <int Dim> Mat<Dim, Dim> randomMatrix(unsigned seed, double amount) {
  std::mt19937 rng(seed);
  return randomMatrix<Dim>(rng, amount);
}

/// An N-vector with entries drawn from `rng`.
template <int N> Vector<N> randomVector(std::mt19937 &rng, double amount) {
  std::uniform_real_distribution<double> u(-amount, amount);
  Vector<N> v{};
  for (int i = 0; i < N; ++i)
    v.v[i] = u(rng);
  return v;
}

} // namespace mixcon::test
