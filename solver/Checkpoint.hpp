// The committed state of a nonlinear analysis as named host arrays: what a restart needs to
// continue a run exactly where it stopped (the model's unknowns, contact statuses, stick anchors
// and contact forces, obstacle motion, the load factor). The driver collects it after every
// converged step, io/Results writes it with the step, `mixcon run --restart` reads it back.
// Integer data (statuses, segment numbers) is stored exactly as doubles.
// Data flow: solver (host side; contact adds its arrays through ContactIterations).
#pragma once

#include <cstddef>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace mixcon {

class Checkpoint {
public:
  void put(const std::string &name, std::vector<double> values) {
    arrays_[name] = std::move(values);
  }
  /// Integers or enumerations, stored exactly as doubles.
  template <class Int> void putIntegers(const std::string &name, const std::vector<Int> &values) {
    std::vector<double> v;
    v.reserve(values.size());
    for (const Int &x : values)
      v.push_back(static_cast<double>(static_cast<long long>(x)));
    put(name, std::move(v));
  }
  void putScalar(const std::string &name, double value) { put(name, {value}); }

  bool has(const std::string &name) const { return arrays_.count(name) > 0; }
  /// The array `name`; throws std::runtime_error when it is missing or its length is not
  /// `expected` (unless expected is kAnyLength).
  const std::vector<double> &get(const std::string &name, std::size_t expected) const {
    const auto it = arrays_.find(name);
    if (it == arrays_.end())
      throw std::runtime_error("the saved state has no array '" + name + "'");
    if (expected != kAnyLength && it->second.size() != expected)
      throw std::runtime_error("the saved array '" + name + "' has " +
                               std::to_string(it->second.size()) + " values, this problem needs " +
                               std::to_string(expected));
    return it->second;
  }
  /// The array `name` if the saved state has it (checked as get does), otherwise `expected`
  /// copies of `fallback`: an array added after restart files of an earlier release were written.
  std::vector<double> getOr(const std::string &name, std::size_t expected, double fallback) const {
    return has(name) ? get(name, expected) : std::vector<double>(expected, fallback);
  }
  double getScalar(const std::string &name) const { return get(name, 1)[0]; }
  template <class Int> std::vector<Int> getIntegers(const std::string &name, std::size_t n) const {
    std::vector<Int> out;
    out.reserve(n);
    for (double x : get(name, n))
      out.push_back(static_cast<Int>(static_cast<long long>(x)));
    return out;
  }
  const std::map<std::string, std::vector<double>> &arrays() const { return arrays_; }

  static constexpr std::size_t kAnyLength = static_cast<std::size_t>(-1);

private:
  std::map<std::string, std::vector<double>> arrays_;
};

} // namespace mixcon
