// libFuzzer target: YAML problem files (io/Problem.cpp: grammar, generators, materials, loads,
// contact, hybrid mode, steps, solver). Inputs stay inside the scratch folder: an input holding a
// '/' is skipped, so a mesh or measurement file can only be one of the fixtures copied there
// (mesh.msh, measured.csv) or the input itself. A rejection must be an InputError; anything else
// escaping is a bug.
#include "FuzzSupport.hpp"

#include <io/Problem.hpp>

#include <cstring>

#ifndef MIXCON_SOURCE_DIR
#error "MIXCON_SOURCE_DIR: the repository root (fixtures come from fuzz/corpus and examples)"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size) {
  static const bool ready = [] {
    mixcon::fuzz::initialize();
    mixcon::fuzz::copyFixture(MIXCON_SOURCE_DIR "/fuzz/corpus/gmsh/quad4.msh", "mesh.msh");
    mixcon::fuzz::copyFixture(MIXCON_SOURCE_DIR "/examples/hybrid/measured.csv", "measured.csv");
    return true;
  }();
  (void)ready;
  if (std::memchr(data, '/', size))
    return -1; // paths outside the scratch folder (/dev/zero, /dev/stdin...): not added to corpus
  const std::string path = mixcon::fuzz::writeInput("problem.yaml", data, size);
  try {
    (void)mixcon::readProblem(path);
  } catch (const mixcon::InputError &) {
  }
  return 0;
}
