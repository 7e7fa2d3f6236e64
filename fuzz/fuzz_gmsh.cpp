// libFuzzer target: Gmsh 4.1 ASCII meshes (mesh/GmshReader.cpp) followed by the mesh validation a
// problem file applies to them. A rejection must be an InputError; anything else escaping
// (another exception, a crash, a sanitizer report, a hang) is a bug in the reader.
#include "FuzzSupport.hpp"

#include <mesh/GmshReader.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size) {
  mixcon::fuzz::initialize();
  const std::string path = mixcon::fuzz::writeInput("input.msh", data, size);
  try {
    const mixcon::Mesh mesh = mixcon::readGmsh(path);
    mixcon::validateMesh(mesh);
    for (const auto &[name, edges] : mesh.boundaries)
      (void)mesh.nodesOf(name);
  } catch (const mixcon::InputError &) {
  }
  return 0;
}
