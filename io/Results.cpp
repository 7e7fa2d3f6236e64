// HDF5 (C API), XDMF 3 and JSON writers.
#include <io/OutputLayout.hpp>
#include <io/Restart.hpp>
#include <io/Results.hpp>
#include <solver/Nonlinear.hpp>

#include <mixcon_version.hpp>

#include <hdf5.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace mixcon {

namespace {

namespace fs = std::filesystem;

/// The system's reason for the last failed call ("No space left on device", ...).
std::string systemReason() { return errno != 0 ? std::strerror(errno) : "unknown reason"; }

void writeDataset(hid_t loc, const std::string &name, const void *data, hid_t type, hsize_t rows,
                  hsize_t cols) {
  const hsize_t dims[2] = {rows, cols};
  const hid_t space = H5Screate_simple(cols > 0 ? 2 : 1, dims, nullptr);
  errno = 0;
  const hid_t set =
      H5Dcreate2(loc, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (set < 0) {
    H5Sclose(space);
    throw std::runtime_error("HDF5: cannot create dataset " + name + ": " + systemReason());
  }
  const herr_t written = rows > 0 ? H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : 0;
  const herr_t closed = H5Dclose(set);
  H5Sclose(space);
  if (written < 0 || closed < 0)
    throw std::runtime_error("HDF5: cannot write dataset " + name + ": " + systemReason());
}

/// An HDF5 file created at `path` (truncated); close() reports a failed flush, the destructor
/// closes silently (after an error, with every object still open in it).
class NewH5File {
public:
  explicit NewH5File(const std::string &path) : path_(path) {
    const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    H5Pset_fclose_degree(fapl, H5F_CLOSE_STRONG);
    errno = 0;
    id_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
    H5Pclose(fapl);
    if (id_ < 0)
      throw std::runtime_error("cannot create it: " + systemReason());
  }
  ~NewH5File() {
    if (id_ >= 0)
      H5Fclose(id_);
  }
  NewH5File(const NewH5File &) = delete;
  NewH5File &operator=(const NewH5File &) = delete;
  hid_t id() const { return id_; }
  void close() {
    errno = 0;
    const herr_t rc = H5Fclose(id_);
    id_ = -1;
    if (rc < 0)
      throw std::runtime_error(systemReason());
  }

private:
  std::string path_;
  hid_t id_ = -1;
};

/// Moves a completely written temporary file into place (atomic on one file system).
void replaceFile(const std::string &tmp, const std::string &path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec)
    throw std::runtime_error("cannot write " + path + ": " + ec.message());
}

/// Writes an HDF5 file through a temporary one that `body(file)` fills and that is renamed into
/// place when complete; a failure removes the temporary and is reported naming `path`.
template <class Body> void writeHdf5File(const std::string &path, Body &&body) {
  const std::string tmp = path + ".tmp";
  try {
    NewH5File file(tmp);
    body(file.id());
    file.close();
  } catch (const std::exception &e) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot write " + path + ": " + e.what());
  }
  replaceFile(tmp, path);
}

/// Flushes and closes a written stream; throws naming `path` and the system's reason when any
/// write failed (full device, I/O error).
void closeChecked(std::ofstream &out, const std::string &path) {
  errno = 0;
  out.flush();
  const bool good = static_cast<bool>(out);
  out.close();
  if (!good || !out)
    throw std::runtime_error("cannot write " + path + ": " + systemReason());
}

/// Writes `text` to `path` through a temporary file: a reader never sees a half-written file,
/// and a failed write (full device, a directory in the way) is reported, not ignored.
void writeTextFile(const std::string &path, const std::string &text) {
  const std::string tmp = path + ".tmp";
  errno = 0;
  std::ofstream out(tmp, std::ios::trunc);
  if (!out)
    throw std::runtime_error("cannot write " + path + ": " + systemReason());
  out << text;
  closeChecked(out, path);
  replaceFile(tmp, path);
}

/// The file of one step's HDF5 data, relative to the output folder.
std::string stepFileName(int step) {
  char name[64];
  std::snprintf(name, sizeof name, "results.d/step-%06d.h5", step);
  return name;
}

constexpr const char *kOutputFiles[] = {"results.h5", "results.xdmf", "summary.json", "contact.csv",
                                        "hybrid.csv"};

template <class T> void writeAttribute(hid_t loc, const char *name, T value, hid_t type) {
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, type, &value);
  H5Aclose(a);
  H5Sclose(space);
}

void writeStringAttribute(hid_t loc, const char *name, const std::string &value) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.empty() ? 1 : value.size());
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, type, value.empty() ? "" : value.c_str());
  H5Aclose(a);
  H5Sclose(space);
  H5Tclose(type);
}

/// A 1-D attribute of fixed-length strings (h5py reads it as an array of bytes).
void writeStringListAttribute(hid_t loc, const char *name, const std::vector<std::string> &values) {
  std::size_t width = 1;
  for (const auto &v : values)
    width = std::max(width, v.size());
  std::vector<char> packed(width * values.size(), '\0');
  for (std::size_t i = 0; i < values.size(); ++i)
    values[i].copy(&packed[i * width], values[i].size());
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, width);
  H5Tset_strpad(type, H5T_STR_NULLPAD);
  const hsize_t n = values.size();
  const hid_t space = H5Screate_simple(1, &n, nullptr);
  const hid_t a = H5Acreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, type, packed.data());
  H5Aclose(a);
  H5Sclose(space);
  H5Tclose(type);
}

/// Writes a (points x components) stress dataset and names its columns in the attribute
/// `components` (the Voigt names of the output table's row, io/OutputLayout.hpp).
void writeStressDataset(hid_t loc, const std::string &name, const std::vector<double> &stress,
                        const std::vector<std::string> &components) {
  const std::size_t width = components.size();
  writeDataset(loc, name, stress.data(), H5T_NATIVE_DOUBLE, stress.size() / width, width);
  const hid_t set = H5Dopen2(loc, name.c_str(), H5P_DEFAULT);
  writeStringListAttribute(set, "components", components);
  H5Dclose(set);
}

/// The rows of a (points x columns.size()) array whose column j is column columns[j] of `values`
/// (rows of `width` entries): the stress in the XDMF's order (io/OutputLayout.hpp).
std::vector<double> selectColumns(const std::vector<double> &values, std::size_t width,
                                  const std::vector<int> &columns) {
  const std::size_t n = values.size() / width, m = columns.size();
  std::vector<double> out(n * m);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < m; ++j)
      out[m * i + j] = values[width * i + static_cast<std::size_t>(columns[j])];
  return out;
}

/// Columns of a nodal vector dataset in either dimension: ParaView's vector filters (Warp By
/// Vector, Glyph) take 3 components.
constexpr int kVectorColumns = 3;

/// Vectors of `dim` components per row as N x 3 (z = 0 in 2D).
std::vector<double> withZeroZ(const std::vector<double> &v, std::size_t dim) {
  const std::size_t n = v.size() / dim;
  std::vector<double> out(kVectorColumns * n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t c = 0; c < dim; ++c)
      out[kVectorColumns * i + c] = v[dim * i + c];
  return out;
}

std::string number(double v) {
  if (!std::isfinite(v))
    return "null";
  std::ostringstream s;
  s << std::setprecision(10) << v;
  return s.str();
}

/// One step's entry of summary.json (also kept in the step's HDF5 group for a restart).
std::string stepSummary(const StepRecord &s) {
  std::ostringstream j;
  j << "{\"step\": " << s.step << ", \"stage\": " << s.stage;
  if (!s.stageName.empty())
    j << ", \"stage_name\": " << jsonString(s.stageName);
  j << ", \"time\": " << number(s.time) << ", \"load_factor\": " << number(s.loadFactor)
    << ", \"iterations\": " << s.iterations << ", \"linear_iterations\": " << s.linearIterations
    << ", \"residual\": " << number(s.residual) << ", \"setup_seconds\": " << number(s.setupSeconds)
    << ", \"solve_seconds\": " << number(s.solveSeconds)
    << ", \"total_seconds\": " << number(s.totalSeconds)
    << ", \"converged\": " << (s.converged ? "true" : "false");
  if (!s.residualHistory.empty()) {
    auto list = [&](const char *key, const std::vector<double> &v) {
      j << ", \"" << key << "\": [";
      for (std::size_t k = 0; k < v.size(); ++k)
        j << (k ? ", " : "") << number(v[k]);
      j << "]";
    };
    list("residuals", s.residualHistory);
    list("increments", s.incrementHistory);
    list("convergence_orders", convergenceOrders(s.residualHistory));
    j << ", \"cuts\": " << s.cuts;
  }
  if (!std::isnan(s.measuredLoad))
    j << ", \"hybrid\": {\"measured_load\": " << number(s.measuredLoad)
      << ", \"asymmetry\": " << number(s.asymmetry) << "}";
  if (s.contactClosed >= 0) {
    j << ", \"contact\": {\"closed\": " << s.contactClosed << ", \"stick\": " << s.contactStick
      << ", \"slip\": " << s.contactSlip << ", \"status_updates\": " << s.contactIterations
      << ", \"cycled\": " << (s.contactCycled ? "true" : "false")
      << ", \"arc_min\": " << number(s.contactArcMin)
      << ", \"arc_max\": " << number(s.contactArcMax) << ", \"obstacle_motion\": [";
    for (std::size_t o = 0; 2 * o + 1 < s.obstacleMotion.size(); ++o) // 2D-only: (x, y)
      j << (o ? ", " : "") << "[" << number(s.obstacleMotion[2 * o]) << ", "
        << number(s.obstacleMotion[2 * o + 1]) << "]";
    j << "]}";
  }
  j << "}";
  return j.str();
}

} // namespace

std::string jsonString(const std::string &s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
    case '"':
      out += "\\\"";
      break;
    case '\\':
      out += "\\\\";
      break;
    case '\n':
      out += "\\n";
      break;
    case '\t':
      out += "\\t";
      break;
    default:
      if (static_cast<unsigned char>(c) < 0x20) {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\u%04x", c);
        out += buf;
      } else {
        out += c;
      }
    }
  }
  return out + "\"";
}

namespace {

/// Takes the folder's lock (a file `.mixcon.lock` holding the owner's pid) or throws naming the
/// run that holds it. The lock ends with the process, however it ends.
int lockFolder(const std::string &directory) {
  const std::string path = directory + "/.mixcon.lock";
  errno = 0;
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0)
    throw std::runtime_error("cannot create " + path + ": " + systemReason());
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    char pid[32] = {};
    const ssize_t n = ::pread(fd, pid, sizeof pid - 1, 0);
    ::close(fd);
    throw std::runtime_error(
        "the output folder '" + directory + "' is in use by another mixcon run" +
        (n > 0 ? " (process " + std::string(pid, static_cast<std::size_t>(n)) + ")"
               : std::string()) +
        "; choose another folder with --output");
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) < 0) {
    // The lock holds without the pid; the pid only makes the message of a second run clearer.
  }
  return fd;
}

} // namespace

ResultsWriter::ResultsWriter(std::string directory, const Mesh &mesh, bool hdf5,
                             std::string problemFile, const RestartPoint *resume)
    : directory_(std::move(directory)), problemFile_(std::move(problemFile)), mesh_(mesh),
      hdf5_(hdf5) {
  std::error_code ec;
  fs::create_directories(directory_, ec);
  if (ec)
    throw std::runtime_error("cannot create output directory '" + directory_ +
                             "': " + ec.message());
  lock_ = lockFolder(directory_);
  try {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); // errors are reported by return codes
    if (resume) {
      resumeFrom(*resume);
    } else {
      // A new run: nothing of an earlier run stays beside its results (no stale contact.csv).
      for (const char *name : kOutputFiles)
        fs::remove(directory_ + "/" + name, ec);
      fs::remove_all(directory_ + "/results.d", ec);
      if (hdf5_) {
        fs::create_directories(directory_ + "/results.d", ec);
        if (ec)
          throw std::runtime_error("cannot create '" + directory_ + "/results.d': " + ec.message());
        writeMesh();
        writeIndex();
      }
    }
    writeSummary();
  } catch (...) {
    ::close(lock_);
    throw;
  }
}

ResultsWriter::~ResultsWriter() {
  if (std::uncaught_exceptions() > uncaught_ && status_ == "running") {
    // Left by an error (a failed write, a failure in a solve): summary.json says so if it can.
    status_ = "failed";
    message_ = "the run stopped on an error (the program's message names it); the steps listed "
               "here were written";
    try {
      writeSummary();
    } catch (...) {
      // Nothing more to report where nothing can be written.
    }
  }
  if (lock_ >= 0)
    ::close(lock_);
}

void ResultsWriter::writeMesh() const {
  writeHdf5File(directory_ + "/results.d/mesh.h5", [&](hid_t file) {
    const Mesh &mesh = mesh_;
    const hid_t m = H5Gcreate2(file, "mesh", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    writeDataset(m, "nodes", mesh.coordinates.data(), H5T_NATIVE_DOUBLE, mesh.numNodes(),
                 mesh.dim());
    writeDataset(m, "elements", mesh.connectivity.data(), H5T_NATIVE_INT, mesh.numElements(),
                 mesh.nodesPerElement);
    writeDataset(m, "element_region", mesh.elementRegion.data(), H5T_NATIVE_INT, mesh.numElements(),
                 0);
    writeDataset(m, "node_ids", mesh.nodeIds.data(), H5T_NATIVE_LONG, mesh.numNodes(), 0);
    writeDataset(m, "element_ids", mesh.elementIds.data(), H5T_NATIVE_LONG, mesh.numElements(), 0);
    writeAttribute(m, "nodes_per_element", mesh.nodesPerElement, H5T_NATIVE_INT);
    H5Gclose(m);
  });
}

void ResultsWriter::writeIndex() const {
  writeHdf5File(directory_ + "/results.h5", [&](hid_t root) {
    writeStringAttribute(root, "mixcon_version", MIXCON_VERSION_STRING);
    writeStringAttribute(root, "layout",
                         "/mesh and /steps/<k> are links into results.d/ (docs/output-format.md)");
    if (H5Lcreate_external("results.d/mesh.h5", "/mesh", root, "mesh", H5P_DEFAULT, H5P_DEFAULT) <
        0)
      throw std::runtime_error("HDF5: cannot link the mesh");
    const hid_t steps = H5Gcreate2(root, "steps", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    for (const WrittenStep &w : steps_) {
      const int step = w.record.step;
      const std::string name = std::to_string(step), target = "/steps/" + name;
      if (H5Lcreate_external(stepFileName(step).c_str(), target.c_str(), steps, name.c_str(),
                             H5P_DEFAULT, H5P_DEFAULT) < 0)
        throw std::runtime_error("HDF5: cannot link step " + name);
    }
    H5Gclose(steps);
  });
}

void ResultsWriter::writeStep(const StepRecord &r, const StepFields &f, const Checkpoint *state) {
  steps_.push_back(
      {r, stepSummary(r), {!f.reaction.empty(), !f.contact.node.empty(), !f.hybrid.node.empty()}});
  if (hdf5_) {
    // The step's own file, complete before it is renamed into place and linked from results.h5.
    writeHdf5File(directory_ + "/" + stepFileName(r.step), [&](hid_t file) {
      const std::string name = "/steps/" + std::to_string(r.step);
      const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
      H5Pset_create_intermediate_group(lcpl, 1);
      const hid_t g = H5Gcreate2(file, name.c_str(), lcpl, H5P_DEFAULT, H5P_DEFAULT);
      H5Pclose(lcpl);
      if (g < 0)
        throw std::runtime_error("HDF5: cannot create group " + name);
      const OutputNames &names = outputNames(mesh_);
      const std::size_t dim = names.vectorComponents.size();
      const hsize_t nn = mesh_.numNodes();
      writeDataset(g, "displacement", withZeroZ(f.displacement, dim).data(), H5T_NATIVE_DOUBLE, nn,
                   kVectorColumns);
      writeStressDataset(g, "stress", f.stress, names.stressComponents);
      if (names.xdmfStressDataset != "stress") // 3D: the XDMF's copy in ParaView's column order
        writeStressDataset(
            g, names.xdmfStressDataset,
            selectColumns(f.stress, names.stressComponents.size(), xdmfStressColumns(names)),
            names.xdmfStressComponents);
      if (!f.reaction.empty())
        writeDataset(g, "reaction", withZeroZ(f.reaction, dim).data(), H5T_NATIVE_DOUBLE, nn,
                     kVectorColumns);
      const hsize_t nq = f.gaussStress.size() / names.stressComponents.size();
      const hid_t gp = H5Gcreate2(g, "gauss_points", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      writeDataset(gp, "coordinates", f.gaussCoordinates.data(), H5T_NATIVE_DOUBLE, nq, dim);
      writeStressDataset(gp, "stress", f.gaussStress, names.stressComponents);
      writeAttribute(gp, "points_per_element", f.pointsPerElement, H5T_NATIVE_INT);
      writeStringAttribute(gp, "stress_source", f.gaussStressSource);
      if (!f.gaussGradient.empty()) {
        writeDataset(gp, "displacement_gradient", f.gaussGradient.data(), H5T_NATIVE_DOUBLE, nq,
                     dim * dim);
        writeDataset(gp, "current_coordinates", f.gaussCurrentCoordinates.data(), H5T_NATIVE_DOUBLE,
                     nq, dim);
      }
      if (!f.gaussInterpolatedStress.empty())
        writeStressDataset(gp, "interpolated_stress", f.gaussInterpolatedStress,
                           names.stressComponents);
      H5Gclose(gp);
      writeStringAttribute(g, "stress_source", f.stressSource);
      if (!f.contact.node.empty())
        writeContact(g, r, f.contact);
      if (!f.hybrid.node.empty())
        writeHybrid(g, r, f.hybrid);
      writeAttribute(g, "load_factor", r.loadFactor, H5T_NATIVE_DOUBLE);
      writeAttribute(g, "stage", r.stage, H5T_NATIVE_INT);
      writeAttribute(g, "time", r.time, H5T_NATIVE_DOUBLE);
      if (!r.stageName.empty())
        writeStringAttribute(g, "stage_name", r.stageName);
      writeAttribute(g, "iterations", r.iterations, H5T_NATIVE_INT);
      writeAttribute(g, "linear_iterations", r.linearIterations, H5T_NATIVE_INT);
      writeAttribute(g, "residual", r.residual, H5T_NATIVE_DOUBLE);
      writeAttribute(g, "converged", static_cast<int>(r.converged), H5T_NATIVE_INT);
      writeAttribute(g, "contact_closed", r.contactClosed, H5T_NATIVE_INT);
      writeStringAttribute(g, "summary", steps_.back().summary);
      if (state)
        writeState(g, *state);
      H5Gclose(g);
    });
    writeIndex();
    writeXdmf();
  } else {
    if (!f.contact.node.empty())
      writeContact(-1, r, f.contact);
    if (!f.hybrid.node.empty())
      writeHybrid(-1, r, f.hybrid);
  }
  writeSummary();
}

std::ofstream ResultsWriter::appendCsv(const std::string &name, bool &started,
                                       const char *header) const {
  const std::string path = directory_ + "/" + name;
  errno = 0;
  std::ofstream csv(path, started ? std::ios::app : std::ios::trunc);
  if (!csv)
    throw std::runtime_error("cannot write " + path + ": " + systemReason());
  if (!started)
    csv << header << "\n";
  started = true;
  csv << std::setprecision(10);
  return csv;
}

void ResultsWriter::writeHybrid(long long group, const StepRecord &r, const HybridFields &h) {
  const hsize_t n = h.node.size();
  if (group >= 0) {
    const hid_t g = static_cast<hid_t>(group);
    const hid_t hg = H5Gcreate2(g, "hybrid", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    writeDataset(hg, "node_id", h.node.data(), H5T_NATIVE_LONG, n, 0);
    const std::pair<const char *, const std::vector<double> *> sets[] = {
        {"angle", &h.angle},
        {"ux", &h.ux},
        {"uy", &h.uy},
        {"sigma_rr", &h.sigmaRR},
        {"tau_rt", &h.tauRT},
        {"mu_stress", &h.muStress},
        {"traction_n", &h.tractionN},
        {"traction_t", &h.tractionT},
        {"mu_force", &h.muForce}};
    for (const auto &[name, v] : sets)
      writeDataset(hg, name, v->data(), H5T_NATIVE_DOUBLE, n, 0);
    writeAttribute(hg, "measured_load", r.measuredLoad, H5T_NATIVE_DOUBLE);
    writeAttribute(hg, "asymmetry", r.asymmetry, H5T_NATIVE_DOUBLE);
    writeStringAttribute(hg, "undetermined",
                         "mu_stress / mu_force are NaN where |sigma_rr| / "
                         "the normal traction is below the threshold");
    H5Gclose(hg);
    // The same per node of the mesh (NaN off the measured boundary), for the XDMF index.
    if (h.nodeIndex.size() != h.node.size())
      throw std::logic_error("HybridFields: nodeIndex must give every node's index");
    const hid_t ng = H5Gcreate2(g, "hybrid_nodal", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const std::size_t nn = mesh_.numNodes();
    for (const auto &[name, v] : sets) {
      if (v == &h.angle || v == &h.ux || v == &h.uy)
        continue; // the mesh's own coordinates and displacement
      std::vector<double> nodal(nn, std::numeric_limits<double>::quiet_NaN());
      for (hsize_t k = 0; k < n; ++k)
        nodal[static_cast<std::size_t>(h.nodeIndex[k])] = (*v)[k];
      writeDataset(ng, name, nodal.data(), H5T_NATIVE_DOUBLE, nn, 0);
    }
    H5Gclose(ng);
  }
  // hybrid.csv: one row per boundary node and step, appended (valid after each step).
  std::ofstream csv = appendCsv("hybrid.csv", hybridCsvStarted_,
                                "step,load,node_id,angle_deg,ux,uy,sigma_rr,tau_rt,mu_stress,"
                                "traction_n,traction_t,mu_force");
  for (hsize_t k = 0; k < n; ++k)
    csv << r.step << "," << r.measuredLoad << "," << h.node[k] << "," << h.angle[k] * 180.0 / M_PI
        << "," << h.ux[k] << "," << h.uy[k] << "," << h.sigmaRR[k] << "," << h.tauRT[k] << ","
        << h.muStress[k] << "," << h.tractionN[k] << "," << h.tractionT[k] << "," << h.muForce[k]
        << "\n";
  closeChecked(csv, directory_ + "/hybrid.csv");
}

void ResultsWriter::writeContact(long long group, const StepRecord &r, const ContactFields &c) {
  const hsize_t n = c.node.size();
  if (group >= 0) {
    const hid_t g = static_cast<hid_t>(group);
    const hid_t cg = H5Gcreate2(g, "contact", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    std::vector<int> obstacleNumber(c.obstacle); // 1-based, as the problem's `contact:` list
    for (int &o : obstacleNumber)
      ++o;
    writeDataset(cg, "obstacle", obstacleNumber.data(), H5T_NATIVE_INT, n, 0);
    writeDataset(cg, "node_id", c.node.data(), H5T_NATIVE_LONG, n, 0);
    writeDataset(cg, "status", c.status.data(), H5T_NATIVE_INT, n, 0);
    writeDataset(cg, "gap", c.gap.data(), H5T_NATIVE_DOUBLE, n, 0);
    writeDataset(cg, "normal_force", c.normalForce.data(), H5T_NATIVE_DOUBLE, n, 0);
    writeDataset(cg, "tangential_force", c.tangentForce.data(), H5T_NATIVE_DOUBLE, n, 0);
    writeDataset(cg, "normal_stress", c.normalStress.data(), H5T_NATIVE_DOUBLE, n, 0);
    writeDataset(cg, "tangential_stress", c.tangentStress.data(), H5T_NATIVE_DOUBLE, n, 0);
    writeDataset(cg, "sigma_nn", c.sigmaNN.data(), H5T_NATIVE_DOUBLE, n, 0);
    writeDataset(cg, "tau_nt", c.tauNT.data(), H5T_NATIVE_DOUBLE, n, 0);
    writeDataset(cg, "angle", c.angle.data(), H5T_NATIVE_DOUBLE, n, 0);
    writeDataset(cg, "arc", c.arc.data(), H5T_NATIVE_DOUBLE, n, 0);
    if (!r.obstacleMotion.empty()) // 2D-only: rigid obstacles move in the plane (x, y)
      writeDataset(cg, "obstacle_motion", r.obstacleMotion.data(), H5T_NATIVE_DOUBLE,
                   r.obstacleMotion.size() / 2, 2);
    writeStringAttribute(cg, "status_codes", "0 open, 1 stick, 2 slip");
    H5Gclose(cg);
    writeContactNodal(g, c);
  }
  // contact.csv: one row per candidate and step, appended (the file stays valid after each step).
  std::ofstream csv = appendCsv("contact.csv", contactCsvStarted_,
                                "step,load_factor,obstacle,node_id,status,gap,normal_force,"
                                "tangential_force,angle_deg,arc,x,y,normal_stress,"
                                "tangential_stress,sigma_nn,tau_nt,stage,time");
  static const char *names[] = {"open", "stick", "slip"};
  for (hsize_t k = 0; k < n; ++k)
    csv << r.step << "," << r.loadFactor << "," << c.obstacle[k] + 1 << "," << c.node[k] << ","
        << names[c.status[k]] << "," << c.gap[k] << "," << c.normalForce[k] << ","
        << c.tangentForce[k] << "," << c.angle[k] * 180.0 / M_PI << "," << c.arc[k] << "," << c.x[k]
        << "," << c.y[k] << "," << c.normalStress[k] << "," << c.tangentStress[k] << ","
        << c.sigmaNN[k] << "," << c.tauNT[k] << "," << r.stage << "," << r.time << "\n";
  closeChecked(csv, directory_ + "/contact.csv");
}

void ResultsWriter::writeContactNodal(long long group, const ContactFields &c) const {
  // Per node of the mesh: the candidate closest to contact (highest status, then smallest gap)
  // of the node's candidates gives the values; -1 / NaN / 0 where the node is no candidate.
  const std::size_t nn = mesh_.numNodes();
  if (c.nodeIndex.size() != c.node.size())
    throw std::logic_error("ContactFields: nodeIndex must give every candidate's node index");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<int> status(nn, -1);
  std::vector<double> gap(nn, nan), normal(nn, 0.0), tangential(nn, 0.0);
  for (std::size_t k = 0; k < c.node.size(); ++k) {
    const auto i = static_cast<std::size_t>(c.nodeIndex[k]);
    if (c.status[k] < status[i] || (c.status[k] == status[i] && !(c.gap[k] < gap[i])))
      continue;
    status[i] = c.status[k];
    gap[i] = c.gap[k];
    normal[i] = c.normalStress[k];
    tangential[i] = c.tangentStress[k];
  }
  const hid_t ng =
      H5Gcreate2(static_cast<hid_t>(group), "contact_nodal", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  writeDataset(ng, "status", status.data(), H5T_NATIVE_INT, nn, 0);
  writeDataset(ng, "gap", gap.data(), H5T_NATIVE_DOUBLE, nn, 0);
  writeDataset(ng, "normal_traction", normal.data(), H5T_NATIVE_DOUBLE, nn, 0);
  writeDataset(ng, "tangential_traction", tangential.data(), H5T_NATIVE_DOUBLE, nn, 0);
  writeStringAttribute(ng, "status_codes", "-1 no candidate, 0 open, 1 stick, 2 slip");
  H5Gclose(ng);
}

void ResultsWriter::setSummaryExtra(const std::string &key, const std::string &jsonValue) {
  extra_.emplace_back(key, jsonValue);
  writeSummary();
}

void ResultsWriter::finish(bool success, const std::string &message) {
  status_ = success ? "completed" : "failed";
  message_ = message;
  writeSummary();
}

void ResultsWriter::writeXdmf() const {
  // Vectors are N x 3 in results.h5 (z = 0 in 2D), as Warp By Vector needs. ParaView labels the
  // stress columns by position (X Y Z in 2D; XX YY ZZ XY YZ XZ, VTK's symmetric-tensor order, in
  // 3D) whatever the AttributeType, and its Xdmf3 reader (5.11) skips HyperSlab and Function data
  // items ("unrecognized array type": their type is unknown until read), so the XDMF cannot
  // reorder columns: it points at a dataset in ParaView's order, "stress" itself in 2D (xx yy xy),
  // its copy "stress_vtk" in 3D (the Voigt "stress" is xx yy zz yz xz xy). Topology, geometry,
  // widths and that dataset are the mesh's row of the output table (io/OutputLayout.hpp).
  const OutputNames &names = outputNames(mesh_);
  const auto ne = mesh_.numElements(), nn = mesh_.numNodes();
  std::ostringstream x;
  auto item = [&](const std::string &path, std::size_t rows, int cols, bool isInt) {
    x << "        <DataItem Dimensions=\"" << rows;
    if (cols > 0)
      x << " " << cols;
    x << "\" NumberType=\"" << (isInt ? "Int\" Precision=\"4" : "Float\" Precision=\"8")
      << "\" Format=\"HDF\">results.h5:" << path << "</DataItem>\n";
  };
  auto nodeArray = [&](const std::string &name, const std::string &path, int cols, bool isInt) {
    x << "      <Attribute Name=\"" << name << "\" AttributeType=\""
      << (cols > 0 ? "Vector" : "Scalar") << "\" Center=\"Node\">\n";
    item(path, nn, cols, isInt);
    x << "      </Attribute>\n";
  };
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
    << "    <Grid Name=\"mixcon\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const WrittenStep &w : steps_) {
    const StepRecord &s = w.record;
    const StepArrays &has = w.arrays;
    const std::string base = "/steps/" + std::to_string(s.step);
    x << "     <Grid Name=\"step " << s.step << "\" GridType=\"Uniform\">\n"
      << "      <Time Value=\"" << number(s.time) << "\"/>\n"
      << "      <Topology TopologyType=\"" << names.topology << "\" NumberOfElements=\"" << ne
      << "\">\n";
    item("/mesh/elements", ne, mesh_.nodesPerElement, true);
    x << "      </Topology>\n      <Geometry GeometryType=\"" << names.geometry << "\">\n";
    item("/mesh/nodes", nn, static_cast<int>(names.vectorComponents.size()), false);
    x << "      </Geometry>\n";
    nodeArray("displacement", base + "/displacement", kVectorColumns, false);
    if (has.reaction)
      nodeArray("reaction", base + "/reaction", kVectorColumns, false);
    x << "      <Attribute Name=\"stress\" AttributeType=\"" << names.stressAttribute
      << "\" Center=\"Node\">\n";
    item(base + "/" + names.xdmfStressDataset, nn,
         static_cast<int>(names.xdmfStressComponents.size()), false);
    x << "      </Attribute>\n";
    if (has.contact) {
      nodeArray("contact_status", base + "/contact_nodal/status", 0, true);
      nodeArray("contact_gap", base + "/contact_nodal/gap", 0, false);
      nodeArray("contact_normal_traction", base + "/contact_nodal/normal_traction", 0, false);
      nodeArray("contact_tangential_traction", base + "/contact_nodal/tangential_traction", 0,
                false);
    }
    if (has.hybrid)
      for (const char *name :
           {"sigma_rr", "tau_rt", "traction_n", "traction_t", "mu_stress", "mu_force"})
        nodeArray(std::string("hybrid_") + name, base + "/hybrid_nodal/" + name, 0, false);
    x << "      <Attribute Name=\"region\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
    item("/mesh/element_region", ne, 0, true);
    x << "      </Attribute>\n     </Grid>\n";
  }
  x << "    </Grid>\n  </Domain>\n</Xdmf>\n";
  writeTextFile(directory_ + "/results.xdmf", x.str());
}

void ResultsWriter::writeSummary() const {
  std::ostringstream j;
  j << "{\n  \"mixcon_version\": " << jsonString(MIXCON_VERSION_STRING)
    << ",\n  \"problem\": " << jsonString(problemFile_)
    << ",\n  \"status\": " << jsonString(status_);
  if (!message_.empty())
    j << ",\n  \"message\": " << jsonString(message_);
  j << ",\n  \"nodes\": " << mesh_.numNodes() << ",\n  \"elements\": " << mesh_.numElements()
    << ",\n  \"converged\": "
    << ((status_ == "completed" && !steps_.empty() && steps_.back().record.converged) ? "true"
                                                                                      : "false")
    << ",\n  \"steps\": [";
  for (std::size_t i = 0; i < steps_.size(); ++i)
    j << (i ? "," : "") << "\n    " << steps_[i].summary;
  j << "\n  ]";
  for (const auto &[k, v] : extra_)
    j << ",\n  " << jsonString(k) << ": " << v;
  j << "\n}\n";
  writeTextFile(directory_ + "/summary.json", j.str());
}

void ResultsWriter::writeState(long long group, const Checkpoint &state) const {
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  const hid_t g = H5Gcreate2(static_cast<hid_t>(group), "restart", lcpl, H5P_DEFAULT, H5P_DEFAULT);
  H5Pclose(lcpl);
  if (g < 0)
    throw std::runtime_error("HDF5: cannot create the restart group");
  writeStringAttribute(g, "description",
                       "the committed state after this step, read by mixcon run --restart");
  for (const auto &[name, values] : state.arrays()) {
    // "model/displacement" -> group model, dataset displacement
    const auto slash = name.rfind('/');
    hid_t parent = g;
    if (slash != std::string::npos) {
      const std::string dir = name.substr(0, slash);
      parent = H5Lexists(g, dir.c_str(), H5P_DEFAULT) > 0
                   ? H5Gopen2(g, dir.c_str(), H5P_DEFAULT)
                   : H5Gcreate2(g, dir.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    }
    writeDataset(parent, slash == std::string::npos ? name : name.substr(slash + 1), values.data(),
                 H5T_NATIVE_DOUBLE, values.size(), 0);
    if (parent != g)
      H5Gclose(parent);
  }
  H5Gclose(g);
}

void ResultsWriter::resumeFrom(const RestartPoint &point) {
  steps_ = point.steps;
  const int last = point.lastStep();
  std::error_code ec;
  if (!fs::equivalent(point.directory, directory_, ec)) {
    // Restarting into another folder: the earlier run's files are copied, then continued.
    for (const char *name : kOutputFiles)
      fs::remove(directory_ + "/" + name, ec);
    fs::remove_all(directory_ + "/results.d", ec);
    ec.clear();
    fs::copy(point.directory + "/results.d", directory_ + "/results.d", fs::copy_options::recursive,
             ec);
    for (const char *name : {"contact.csv", "hybrid.csv"})
      if (!ec && fs::exists(point.directory + "/" + name))
        fs::copy_file(point.directory + "/" + name, directory_ + "/" + name, ec);
    if (ec)
      throw std::runtime_error("cannot copy the results of " + point.directory + " to " +
                               directory_ + ": " + ec.message());
  }
  // Steps after the restart point (written by the interrupted run) and unfinished files go.
  for (fs::directory_iterator it(directory_ + "/results.d", ec), end; !ec && it != end;
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    int step = 0;
    const bool stepFile = std::sscanf(name.c_str(), "step-%d.h5", &step) == 1;
    if ((stepFile && step > last) || (name.size() > 4 && name.substr(name.size() - 4) == ".tmp"))
      fs::remove(it->path(), ec);
  }
  if (hdf5_)
    writeIndex();
  // CSV rows of later steps go too; the files then grow from the restart point.
  for (auto [name, started] : {std::pair<const char *, bool *>{"contact.csv", &contactCsvStarted_},
                               {"hybrid.csv", &hybridCsvStarted_}}) {
    const std::string path = directory_ + "/" + name;
    std::ifstream in(path);
    *started = static_cast<bool>(in);
    if (!in)
      continue;
    std::string line, kept;
    for (bool header = true; std::getline(in, line); header = false)
      if (header || std::atoi(line.c_str()) <= last)
        kept += line + "\n";
    writeTextFile(path, kept);
  }
  if (hdf5_)
    writeXdmf();
}

} // namespace mixcon
