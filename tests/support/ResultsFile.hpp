// Reading a run's results.h5 in tests: its step numbers and one dataset of a step (compared with
// support/Differences.hpp).
#pragma once
#include <support/Differences.hpp>

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace mixcon::test {

/// The step numbers of results.h5 and one dataset of a step (empty when it cannot be read).
inline std::vector<int> stepsOf(const std::filesystem::path &dir) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); // missing steps are expected, not diagnostics
  std::vector<int> steps;
  const hid_t f = H5Fopen((dir / "results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0)
    return steps;
  const hid_t g = H5Gopen2(f, "/steps", H5P_DEFAULT);
  H5G_info_t info;
  if (g >= 0 && H5Gget_info(g, &info) >= 0)
    for (hsize_t i = 0; i < info.nlinks; ++i) {
      char name[32] = {};
      H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT);
      steps.push_back(std::atoi(name));
    }
  if (g >= 0)
    H5Gclose(g);
  H5Fclose(f);
  std::sort(steps.begin(), steps.end());
  return steps;
}

inline std::vector<double> readStep(const std::filesystem::path &dir, int step,
                                    const std::string &name) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  std::vector<double> v;
  const hid_t f = H5Fopen((dir / "results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0)
    return v;
  const std::string path = "/steps/" + std::to_string(step) + "/" + name;
  const hid_t d = H5Dopen2(f, path.c_str(), H5P_DEFAULT);
  if (d >= 0) {
    const hid_t space = H5Dget_space(d);
    v.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    if (H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
      v.clear();
    H5Sclose(space);
    H5Dclose(d);
  }
  H5Fclose(f);
  return v;
}

} // namespace mixcon::test
