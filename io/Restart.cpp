// readRestart: the index results.h5 and its step files read back with the HDF5 C API (only calls
// that are the same in HDF5 1.10, 1.12 and 1.14).
#include <io/Restart.hpp>

#include <hdf5.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace mixcon {

namespace fs = std::filesystem;

namespace {

/// Reads a double attribute (or an int one) of an HDF5 object; `fallback` when absent.
template <class T> T readAttribute(hid_t loc, const char *name, hid_t type, T fallback) {
  if (H5Aexists(loc, name) <= 0)
    return fallback;
  const hid_t a = H5Aopen(loc, name, H5P_DEFAULT);
  T value = fallback;
  if (a < 0 || H5Aread(a, type, &value) < 0)
    value = fallback;
  if (a >= 0)
    H5Aclose(a);
  return value;
}

std::string readStringAttribute(hid_t loc, const char *name) {
  if (H5Aexists(loc, name) <= 0)
    return {};
  const hid_t a = H5Aopen(loc, name, H5P_DEFAULT);
  const hid_t type = H5Aget_type(a);
  std::string value(H5Tget_size(type), '\0');
  const hid_t mem = H5Tcopy(H5T_C_S1);
  H5Tset_size(mem, value.size());
  if (H5Aread(a, mem, value.data()) < 0)
    value.clear();
  H5Tclose(mem);
  H5Tclose(type);
  H5Aclose(a);
  while (!value.empty() && value.back() == '\0')
    value.pop_back();
  return value;
}

/// A dataset of doubles (any rank) as a flat vector; its first dimension in `rows`.
std::vector<double> readDoubles(hid_t loc, const char *name, hsize_t *rows = nullptr) {
  const hid_t set = H5Dopen2(loc, name, H5P_DEFAULT);
  if (set < 0)
    throw std::runtime_error(std::string("no dataset ") + name);
  const hid_t space = H5Dget_space(set);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  hsize_t dims[8] = {};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  std::vector<double> v(static_cast<std::size_t>(std::max<hssize_t>(n, 0)));
  const herr_t rc =
      v.empty() ? 0 : H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(space);
  H5Dclose(set);
  if (rc < 0)
    throw std::runtime_error(std::string("cannot read dataset ") + name);
  if (rows)
    *rows = dims[0];
  return v;
}

/// The names of a group's links (an API that is the same in HDF5 1.10, 1.12 and 1.14).
std::vector<std::string> linkNames(hid_t group) {
  std::vector<std::string> names;
  H5G_info_t info;
  if (H5Gget_info(group, &info) < 0)
    return names;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t size =
        H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (size <= 0)
      continue;
    std::string name(static_cast<std::size_t>(size) + 1, '\0');
    H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(),
                       H5P_DEFAULT);
    name.resize(static_cast<std::size_t>(size));
    names.push_back(name);
  }
  return names;
}

/// Paths (relative to `group`) of every dataset below it.
void collectDatasets(hid_t group, const std::string &prefix, std::vector<std::string> &out) {
  for (const auto &name : linkNames(group)) {
    const hid_t o = H5Oopen(group, name.c_str(), H5P_DEFAULT);
    if (o < 0)
      continue;
    if (H5Iget_type(o) == H5I_GROUP)
      collectDatasets(o, prefix + name + "/", out);
    else if (H5Iget_type(o) == H5I_DATASET)
      out.push_back(prefix + name);
    H5Oclose(o);
  }
}

} // namespace

RestartPoint readRestart(const std::string &directory) {
  const std::string path = directory + "/results.h5";
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw InputError(path + ": no results to restart from (is it the output folder of a run?)");
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0)
    throw InputError(path + ": cannot be opened as HDF5");
  RestartPoint point;
  point.directory = directory;
  try {
    hsize_t rows = 0;
    point.nodes = readDoubles(file, "/mesh/nodes", &rows);
    point.numNodes = static_cast<long>(rows);
    const hid_t elements = H5Dopen2(file, "/mesh/elements", H5P_DEFAULT);
    if (elements >= 0) {
      const hid_t space = H5Dget_space(elements);
      hsize_t dims[2] = {};
      H5Sget_simple_extent_dims(space, dims, nullptr);
      point.numElements = static_cast<long>(dims[0]);
      H5Sclose(space);
      H5Dclose(elements);
    }
    std::vector<std::string> names;
    const hid_t steps = H5Gopen2(file, "/steps", H5P_DEFAULT);
    if (steps >= 0) {
      names = linkNames(steps);
      H5Gclose(steps);
    }
    std::vector<int> numbers;
    for (const auto &n : names)
      numbers.push_back(std::atoi(n.c_str()));
    std::sort(numbers.begin(), numbers.end());
    // Steps in order up to the first that is missing, unreadable or not converged; the restart
    // point is the last of them with a saved state.
    std::vector<WrittenStep> written;
    std::size_t withState = 0; // steps up to the restart point
    int expected = 1;
    for (int k : numbers) {
      if (k != expected++)
        break;
      const std::string name = "/steps/" + std::to_string(k);
      const hid_t g = H5Gopen2(file, name.c_str(), H5P_DEFAULT);
      if (g < 0)
        break;
      StepRecord r;
      r.step = k;
      r.converged = readAttribute<int>(g, "converged", H5T_NATIVE_INT, 0) != 0;
      r.loadFactor = readAttribute<double>(g, "load_factor", H5T_NATIVE_DOUBLE, 0.0);
      r.stage = readAttribute<int>(g, "stage", H5T_NATIVE_INT, 1);
      r.time = readAttribute<double>(g, "time", H5T_NATIVE_DOUBLE, r.loadFactor);
      r.stageName = readStringAttribute(g, "stage_name");
      r.iterations = readAttribute<int>(g, "iterations", H5T_NATIVE_INT, 0);
      r.linearIterations = readAttribute<int>(g, "linear_iterations", H5T_NATIVE_INT, 0);
      r.residual = readAttribute<double>(g, "residual", H5T_NATIVE_DOUBLE, 0.0);
      r.contactClosed = readAttribute<int>(g, "contact_closed", H5T_NATIVE_INT, -1);
      const bool hasState = H5Lexists(g, "restart", H5P_DEFAULT) > 0;
      const std::string summary = readStringAttribute(g, "summary");
      if (!r.converged) {
        H5Gclose(g);
        break;
      }
      written.push_back({r,
                         summary,
                         {H5Lexists(g, "reaction", H5P_DEFAULT) > 0,
                          H5Lexists(g, "contact_nodal", H5P_DEFAULT) > 0,
                          H5Lexists(g, "hybrid_nodal", H5P_DEFAULT) > 0}});
      if (hasState)
        withState = written.size();
      H5Gclose(g);
    }
    if (withState == 0)
      throw std::runtime_error("no converged step with a saved state to restart from");
    const std::string name =
        "/steps/" + std::to_string(written[withState - 1].record.step) + "/restart";
    const hid_t st = H5Gopen2(file, name.c_str(), H5P_DEFAULT);
    std::vector<std::string> sets;
    collectDatasets(st, "", sets);
    for (const auto &set : sets)
      point.state.put(set, readDoubles(st, set.c_str()));
    H5Gclose(st);
    written.resize(withState);
    point.steps = std::move(written);
  } catch (const std::runtime_error &e) {
    H5Fclose(file);
    throw InputError(path + ": " + e.what());
  }
  H5Fclose(file);
  return point;
}

} // namespace mixcon
