// Shared pieces of the libFuzzer targets (fuzz_*.cpp): Kokkos start-up (mesh validation runs a
// Kokkos reduction) and a private scratch folder per fuzzing process, since the readers take paths.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace mixcon::fuzz {

/// Starts Kokkos (one thread) and creates the scratch folder (under /dev/shm when it exists), both
/// released at exit. Idempotent.
void initialize();

/// The scratch folder of this process.
const std::string &scratch();

/// Writes `size` bytes to scratch()/name and returns the path.
std::string writeInput(const std::string &name, const std::uint8_t *data, std::size_t size);

/// Copies the file `from` to scratch()/name (fixtures an input may reference by relative path).
void copyFixture(const std::string &from, const std::string &name);

} // namespace mixcon::fuzz
