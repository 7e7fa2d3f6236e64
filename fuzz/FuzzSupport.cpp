// Kokkos start-up and the per-process scratch folder of the fuzz targets.
#include "FuzzSupport.hpp"

#include <Kokkos_Core.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace mixcon::fuzz {

namespace {
std::string scratchDir;

void cleanUp() {
  if (Kokkos::is_initialized())
    Kokkos::finalize();
  if (!scratchDir.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(scratchDir, ignored);
  }
}
} // namespace

void initialize() {
  if (!scratchDir.empty())
    return;
  if (!Kokkos::is_initialized()) {
    Kokkos::InitArguments args;
    args.num_threads = 1;
    args.disable_warnings = true;
    Kokkos::initialize(args);
  }
  std::string pattern = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
  pattern += "/mixcon-fuzz-XXXXXX";
  if (!mkdtemp(pattern.data()))
    throw std::runtime_error("mixcon fuzz: cannot create a scratch folder " + pattern);
  scratchDir = pattern;
  std::atexit(cleanUp);
}

const std::string &scratch() { return scratchDir; }

std::string writeInput(const std::string &name, const std::uint8_t *data, std::size_t size) {
  const std::string path = scratchDir + "/" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char *>(data), static_cast<std::streamsize>(size));
  if (!out)
    throw std::runtime_error("mixcon fuzz: cannot write " + path);
  return path;
}

void copyFixture(const std::string &from, const std::string &name) {
  std::filesystem::copy_file(from, scratchDir + "/" + name,
                             std::filesystem::copy_options::overwrite_existing);
}

} // namespace mixcon::fuzz
