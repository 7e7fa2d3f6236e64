// libFuzzer target: hybrid-mode measurement CSVs (io/Measurements.cpp), read and turned into the
// angular profile of each step. A rejection must be an InputError; anything else escaping is a bug.
#include "FuzzSupport.hpp"

#include <io/Measurements.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size) {
  mixcon::fuzz::initialize();
  const std::string path = mixcon::fuzz::writeInput("input.csv", data, size);
  try {
    for (const auto &step : mixcon::readMeasurements(path)) {
      const mixcon::AngularProfile profile(step, {0.0, 0.0});
      for (double theta : {-3.0, -1.0, 0.0, 0.5, 3.1})
        if (profile.covers(theta))
          (void)profile.at(theta);
    }
  } catch (const mixcon::InputError &) {
  }
  return 0;
}
