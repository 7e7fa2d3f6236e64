// Measured boundary displacements of the hybrid mode (io/Measurements.hpp): the CSV reader and
// its errors (file:line), the angular interpolation against exact linear profiles, the
// symmetrization of mirrored halves against a field built from known symmetric and
// antisymmetric parts, and the boundary-distance check.
#include <io/Measurements.hpp>
#include <mesh/Generators.hpp>
#include <mesh/GmshReader.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <sys/stat.h>
#include <unistd.h>

using namespace mixcon;

namespace measurement_tests {

/// A step with points on the circle of radius r at the given angles (degrees) and u = f(theta).
template <class F> MeasuredStep circleStep(const std::vector<double> &degrees, double r, F f) {
  MeasuredStep s{1, 10.0, {}};
  for (double d : degrees) {
    const double t = d * M_PI / 180.0;
    const auto u = f(t);
    s.points.push_back({r * std::cos(t), r * std::sin(t), u[0], u[1], 0});
  }
  return s;
}

std::string errorOf(const std::string &text) {
  try {
    parseMeasurements(text, "m.csv");
  } catch (const InputError &e) {
    return e.what();
  }
  return "";
}

} // namespace measurement_tests
using namespace measurement_tests;

TEST(Measurements, ReadsStepsAndReportsMalformedRowsByLine) {
  const auto steps =
      parseMeasurements("step,load,x,y,ux,uy\n1,10,0.5,0,1e-3,0\n1,10,0,0.5,2e-3,"
                        "1e-4\n# a comment\n2,20,0.5,0,2e-3,0\n2,20,0,0.5,4e-3,2e-4\n",
                        "m.csv");
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[1].step, 2);
  EXPECT_DOUBLE_EQ(steps[1].load, 20.0);
  ASSERT_EQ(steps[0].points.size(), 2u);
  EXPECT_DOUBLE_EQ(steps[0].points[1].ux, 2e-3);
  EXPECT_EQ(steps[1].points[0].line, 5);
  const std::string h = "step,load,x,y,ux,uy\n";
  EXPECT_NE(errorOf("s,l,x,y\n").find("m.csv:1: expected the header"), std::string::npos);
  EXPECT_NE(errorOf(h + "1,10,0.5,0,1e-3\n").find("m.csv:2: expected 6 values"), std::string::npos);
  EXPECT_NE(errorOf(h + "1,10,0.5,0,abc,0\n").find("m.csv:2: value 5 ('abc')"), std::string::npos);
  EXPECT_NE(errorOf(h + "1,10,0,0,0,0\n1,10,1,0,0,0\n3,10,0,0,0,0\n")
                .find("m.csv:4: step 3 out "
                      "of order"),
            std::string::npos);
  EXPECT_NE(errorOf(h + "1,10,0,0,0,0\n1,11,1,0,0,0\n").find("m.csv:3: step 1 has two loads"),
            std::string::npos);
  EXPECT_NE(errorOf("").find("empty measurement file"), std::string::npos);
  EXPECT_NE(errorOf(h + "1,10,0,0,0,0\n").find("fewer than 2"), std::string::npos);
}

// A measurement file that is not a regular file is refused by stat (a device would be read
// forever, a FIFO would block); lines are capped at kMaxInputLine characters; a long value is
// echoed cut to 80 characters.
TEST(Measurements, NonRegularFilesEndlessLinesAndLongValuesAreRefusedShortly) {
  auto errorOfFile = [](const std::string &file) -> std::string {
    try {
      readMeasurements(file);
    } catch (const InputError &e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(errorOfFile("/dev/zero").find("/dev/zero: the measurement file is a device"),
            std::string::npos);
  const auto dir = std::filesystem::temp_directory_path() /
                   ("mixcon-measurements-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  EXPECT_NE(errorOfFile(dir.string()).find("the measurement file is a directory"),
            std::string::npos);
  const auto fifo = dir / "m.csv";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(errorOfFile(fifo.string()).find("m.csv: the measurement file is a FIFO"),
            std::string::npos);
  std::filesystem::remove(fifo);
  {
    std::ofstream out(fifo);
    out << "step,load,x,y,ux,uy\n" << std::string(kMaxInputLine + 1, '1') << "\n";
  }
  EXPECT_NE(errorOfFile(fifo.string()).find("m.csv:2: line longer than 1048576 characters"),
            std::string::npos);
  std::filesystem::remove_all(dir);

  const std::string h = "step,load,x,y,ux,uy\n";
  std::string msg = errorOf(h + "1,10," + std::string(1000, '9') + "q,0,0,0\n");
  EXPECT_NE(msg.find("('" + std::string(77, '9') + "...')"), std::string::npos) << msg;
  msg = errorOf(std::string(1000, 'z') + "\n");
  EXPECT_NE(msg.find("found '" + std::string(77, 'z') + "...'"), std::string::npos) << msg;
  EXPECT_LT(msg.size(), 200u) << msg;
}

// Reproducer found by fuzz/fuzz_measurements.cpp: a step number beyond int's range was converted
// to int (undefined behaviour, UBSan); it is now refused with its line.
TEST(Measurements, FuzzedStepNumbersOutOfRangeAreInputErrors) {
  const std::string h = "step,load,x,y,ux,uy\n";
  EXPECT_NE(errorOf(h + "1777777777777777777777777,10,1,0,0.1,0\n1,10,0,0,0,0.1\n")
                .find("m.csv:2: step must be a positive integer"),
            std::string::npos);
  EXPECT_NE(errorOf(h + "1,10,1,0,0.1,0\n2147483648,10,0,0,0,0.1\n")
                .find("m.csv:3: step must be a positive integer"),
            std::string::npos);
  EXPECT_NE(errorOf(h + "1.5,10,1,0,0.1,0\n").find("m.csv:2: step must be a positive integer"),
            std::string::npos);
}

TEST(Measurements, AngularInterpolationIsExactForLinearProfilesAndWrapsAround) {
  // Half circle 0..180 deg: linear in the angle, reproduced exactly between the points.
  const auto f = [](double t) { return std::array<double, 2>{1e-3 + 2e-3 * t, -5e-4 * t}; };
  const AngularProfile half(circleStep({0, 20, 50, 90, 135, 180}, 0.5, f), {0.0, 0.0});
  EXPECT_FALSE(half.periodic());
  for (double d : {0.0, 7.0, 33.0, 100.0, 179.0}) {
    const double t = d * M_PI / 180.0;
    EXPECT_TRUE(half.covers(t));
    EXPECT_NEAR(half.at(t)[0], f(t)[0], 1e-15);
    EXPECT_NEAR(half.at(t)[1], f(t)[1], 1e-15);
  }
  EXPECT_FALSE(half.covers(-0.5));
  // All around every 30 deg: periodic; across the +-180 deg seam the interpolation is linear
  // between the points at 165 and -165 deg.
  std::vector<double> all;
  for (int d = -165; d <= 165; d += 30)
    all.push_back(d);
  const auto g = [](double t) { return std::array<double, 2>{std::cos(t), std::sin(t)}; };
  const AngularProfile ring(circleStep(all, 0.5, g), {0.0, 0.0});
  EXPECT_TRUE(ring.periodic());
  EXPECT_TRUE(ring.covers(M_PI));
  const double a = 165 * M_PI / 180, b = -165 * M_PI / 180;
  EXPECT_NEAR(ring.at(M_PI)[0], 0.5 * (std::cos(a) + std::cos(b)), 1e-14);
  EXPECT_NEAR(ring.at(M_PI)[1], 0.5 * (std::sin(a) + std::sin(b)), 1e-14);
  EXPECT_NEAR(ring.at(-M_PI)[0], ring.at(M_PI)[0], 1e-14);
}

TEST(Measurements, SymmetrizationAveragesMirroredHalvesAndMeasuresTheAsymmetry) {
  // u = s(theta) + e(theta): s symmetric about y = 0 (ux even, uy odd in theta), e an
  // antisymmetric error (ux odd, uy even). Averaging the mirrored halves leaves s exactly
  // (for fields linear between the measured angles, i.e. at the measured angles).
  const Mesh mesh = pinnedPlateMesh(0.5, 2.0, 4.0, 8.0, 4, 6, 4, 9, ElementType::Quad4, 1.25);
  const auto nodes = mesh.nodesOf("hole");
  const auto s = [](double t) {
    return std::array<double, 2>{-1e-3 * std::cos(t), 2e-4 * std::sin(t)};
  };
  const auto e = [](double t) {
    return std::array<double, 2>{3e-5 * std::sin(t), 1e-5 * std::cos(t)};
  };
  std::vector<double> degrees;
  for (int d = -180; d < 180; d += 15)
    degrees.push_back(d);
  const auto step = circleStep(degrees, 0.5, [&](double t) {
    return std::array<double, 2>{s(t)[0] + e(t)[0], s(t)[1] + e(t)[1]};
  });
  const AngularProfile profile(step, {0.0, 0.0});
  const BoundaryValues v = boundaryValues(mesh, nodes, profile, {0.0, 0.0}, true, 1);
  ASSERT_EQ(v.nodes.size(), nodes.size());
  double largest = 0.0, asym = 0.0;
  for (std::size_t i = 0; i < v.nodes.size(); ++i) {
    const double t = v.theta[i];
    EXPECT_NEAR(v.ux[i], s(t)[0], 1e-15) << t;
    EXPECT_NEAR(v.uy[i], s(t)[1], 1e-15) << t;
    largest = std::max(largest, std::hypot(s(t)[0] + e(t)[0], s(t)[1] + e(t)[1]));
    asym = std::max(asym, 2 * std::hypot(e(t)[0], e(t)[1])); // |u(t) - M u(-t)| = 2 |e(t)|
  }
  EXPECT_NEAR(v.asymmetry, asym / largest, 1e-12);
  // Without symmetrization the measured values are used as they are.
  const BoundaryValues raw = boundaryValues(mesh, nodes, profile, {0.0, 0.0}, false, 1);
  EXPECT_LT(raw.asymmetry, 0.0);
  EXPECT_NEAR(raw.ux[3], s(raw.theta[3])[0] + e(raw.theta[3])[0], 1e-15);
  // Measurements of a quarter only (0..90 deg) do not cover the hole nodes beyond 90 deg.
  const AngularProfile quarter(circleStep({0, 30, 60, 90}, 0.5, s), {0.0, 0.0});
  try {
    boundaryValues(mesh, nodes, quarter, {0.0, 0.0}, true, 3);
    FAIL() << "a node outside the measured range must be refused";
  } catch (const InputError &err) {
    EXPECT_NE(std::string(err.what()).find("step 3: boundary node"), std::string::npos);
    EXPECT_NE(std::string(err.what()).find("outside the measured range"), std::string::npos);
  }
}

TEST(Measurements, PointsFarFromTheBoundaryAreRefusedWithTheirLine) {
  const Mesh mesh = pinnedPlateMesh(0.5, 2.0, 4.0, 8.0, 4, 6, 4, 9, ElementType::Quad8, 1.25);
  auto steps = parseMeasurements("step,load,x,y,ux,uy\n1,1,0.5,0,0,0\n1,1,0,0.5,0,0\n"
                                 "1,1,0,-0.5,0,0\n",
                                 "m.csv");
  EXPECT_NO_THROW(checkNearBoundary(mesh, "hole", steps, 1e-2, "m.csv", true, 0.0));
  try {
    checkNearBoundary(mesh, "hole", steps, 1e-2, "m.csv");
    FAIL() << "the lower point lies on the other half: refused without mirroring";
  } catch (const InputError &err) {
    EXPECT_NE(std::string(err.what()).find("m.csv:4: the measured point"), std::string::npos);
  }
  steps[0].points[1].x = 0.2; // 0.3 inside the hole
  EXPECT_THROW(checkNearBoundary(mesh, "hole", steps, 1e-2, "m.csv", true, 0.0), InputError);
}
