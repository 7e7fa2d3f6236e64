// The `mixcon` command-line program: `mixcon run problem.yaml [--output DIR] [--restart DIR]
// [-v | -q]`.
// Exit codes: 0 success, 1 runtime failure or failed verification, 2 invalid input,
// 3 non-convergence.
#include <apps/Analysis.hpp>
#include <solver/Environment.hpp>

#include <mixcon_version.hpp>

#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char **argv) {
  CLI::App app{"mixcon: nonlinear contact stress analysis with displacement and mixed "
               "(Hellinger-Reissner) finite elements",
               "mixcon"};
  app.set_version_flag("--version", std::string("mixcon ") + MIXCON_VERSION_STRING);
  app.require_subcommand(1);
  auto *run = app.add_subcommand("run", "Run the analysis a YAML problem file describes");
  std::string problemFile, output;
  run->add_option("problem", problemFile, "Problem file (YAML), see docs/problem-format.md")
      ->required();
  run->add_option("-o,--output", output, "Output directory (overrides output.directory)");
  std::string restart;
  run->add_option("--restart", restart,
                  "Continue the nonlinear or contact run whose output folder this is from its last "
                  "converged step (the results go on there unless --output names another folder)");
  bool quiet = false, verbose = false;
  auto *quietFlag =
      run->add_flag("-q,--quiet", quiet, "Only warnings and errors (on stderr), no progress lines");
  run->add_flag("-v,--verbose", verbose,
                "Every Newton iteration and contact status change besides the step lines")
      ->excludes(quietFlag);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError &e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }

  mixcon::Environment env(argc, argv);
  try {
    const mixcon::Problem problem = mixcon::readProblem(problemFile);
    for (const auto &w : problem.mesh.warnings)
      std::cerr << "mixcon: warning: " << w << "\n";
    mixcon::RunOptions options;
    options.outputDirectory = output.empty() ? restart : output;
    options.restartDirectory = restart;
    // Default: start-up lines, one line per step, warnings and the files written.
    options.verbosity = quiet     ? mixcon::Verbosity::Quiet
                        : verbose ? mixcon::Verbosity::Verbose
                                  : mixcon::Verbosity::Normal;
    options.log = quiet ? &std::cerr : &std::cout;
    const auto result = mixcon::runAnalysis(problem, options, MPI_COMM_WORLD);
    if (!result.converged) {
      std::cerr << "mixcon: error: " << problemFile
                << ": the analysis did not converge; results of the converged steps are in "
                << result.outputDirectory << "\n";
      return 3;
    }
    if (result.verification && !result.verification->passed) {
      std::cerr << "mixcon: error: verification against the closed form failed\n";
      return 1;
    }
  } catch (const mixcon::InputError &e) {
    std::cerr << "mixcon: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception &e) {
    std::cerr << "mixcon: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
