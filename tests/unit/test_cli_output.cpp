// The `mixcon run` program's console output (apps/main.cpp, the logging of apps/Analysis.cpp and
// of the LoadStepper): by default one progress line per step plus the start-up lines and the
// warnings; --verbose adds every Newton iteration and contact status change; --quiet prints
// warnings and errors only. Runs the shipped frictional pin-loaded plate (contact) in 4 steps.
#include <support/Program.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct ProgramRun {
  int exitCode = -1;
  std::vector<std::string> lines; ///< stdout and stderr
};

/// Runs `mixcon run <problem> --output <dir>/out <flags>`; fills the output lines.
ProgramRun runProblem(const fs::path &problem, const fs::path &dir, const std::string &flags) {
  std::string output;
  ProgramRun r;
  r.exitCode = mixcon::test::runMixcon(
      "run " + problem.string() + " --output " + (dir / "out").string() + " " + flags, output, dir);
  std::istringstream in(output);
  for (std::string line; std::getline(in, line);)
    r.lines.push_back(line);
  return r;
}

int countContaining(const ProgramRun &r, const std::string &text) {
  int n = 0;
  for (const auto &l : r.lines)
    n += l.find(text) != std::string::npos;
  return n;
}

int countStarting(const ProgramRun &r, const std::string &text) {
  int n = 0;
  for (const auto &l : r.lines)
    n += l.rfind(text, 0) == 0;
  return n;
}

std::string joined(const ProgramRun &r) {
  std::ostringstream s;
  for (const auto &l : r.lines)
    s << l << "\n";
  return s.str();
}

using mixcon::test::ScratchDir;

} // namespace

TEST(CliOutput, OneLinePerStepByDefaultDetailWithVerboseWarningsOnlyWithQuiet) {
  // The report's wood plate (force-driven pin, friction 0.7), its 18 increments cut to 4.
  const int nsteps = 4;
  std::ifstream in(std::string(MIXCON_SOURCE_DIR) + "/examples/wood_plate/report.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const std::string increments = "increments: 18";
  const auto at = yaml.find(increments);
  ASSERT_NE(at, std::string::npos) << yaml;
  yaml.replace(at, increments.size(), "increments: " + std::to_string(nsteps));
  ScratchDir normalDir("normal"), verboseDir("verbose"), quietDir("quiet");
  const fs::path problem = normalDir.path() / "plate.yaml";
  std::ofstream(problem) << yaml;
  const ProgramRun normal = runProblem(problem, normalDir.path(), "");
  const ProgramRun verbose = runProblem(problem, verboseDir.path(), "--verbose");
  const ProgramRun quiet = runProblem(problem, quietDir.path(), "--quiet");
  ASSERT_EQ(normal.exitCode, 0) << joined(normal);
  ASSERT_EQ(verbose.exitCode, 0) << joined(verbose);
  ASSERT_EQ(quiet.exitCode, 0) << joined(quiet);

  // Default: each step's line once, the contact summary on it, nothing per iteration.
  for (int k = 1; k <= nsteps; ++k) {
    const std::string step = "step " + std::to_string(k) + "/" + std::to_string(nsteps) + " ";
    EXPECT_EQ(countStarting(normal, step), 1) << step << "\n" << joined(normal);
    EXPECT_EQ(countStarting(verbose, step), 1) << step << "\n" << joined(verbose);
  }
  EXPECT_EQ(countContaining(normal, " nodes closed ("), nsteps)
      << "contact summary on the step line";
  EXPECT_EQ(countContaining(normal, "contact: node"), 0) << joined(normal);
  EXPECT_EQ(countContaining(normal, "  iteration "), 0) << joined(normal);
  EXPECT_LE(static_cast<int>(normal.lines.size()), 2 * nsteps + 4) << joined(normal);
  EXPECT_EQ(countStarting(normal, "mixcon: wrote "), 1) << joined(normal);

  // Verbose: every Newton iteration and contact status change besides the step lines.
  EXPECT_GE(countContaining(verbose, "contact: node"), nsteps) << joined(verbose);
  EXPECT_GE(countContaining(verbose, "  iteration "), nsteps) << joined(verbose);
  EXPECT_GT(verbose.lines.size(), 4 * normal.lines.size());

  // Quiet: no progress at all; whatever it prints (warnings) the default output prints too.
  EXPECT_EQ(countStarting(quiet, "step "), 0) << joined(quiet);
  EXPECT_EQ(countStarting(quiet, "mixcon: "), 0) << joined(quiet);
  const std::string all = joined(normal);
  for (const auto &l : quiet.lines)
    EXPECT_NE(all.find(l), std::string::npos) << "quiet printed '" << l << "'";

  // The per-step record is complete whatever the console shows.
  for (const auto *dir : {&normalDir, &quietDir}) {
    std::ifstream js(dir->path() / "out" / "summary.json");
    std::stringstream s;
    s << js.rdbuf();
    EXPECT_NE(s.str().find("\"step\": " + std::to_string(nsteps)), std::string::npos) << s.str();
  }
}
