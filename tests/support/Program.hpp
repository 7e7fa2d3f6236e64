// Running the `mixcon` program from tests as a user runs it: a scratch folder of its own per test
// and the program's exit code with its output. MIXCON_APP (the program) is defined for the unit
// tests by tests/CMakeLists.txt.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace mixcon::test {

/// A new empty folder under the system's temporary directory, removed with its contents.
class ScratchDir {
public:
  explicit ScratchDir(const std::string &name = "test") {
    std::string pattern =
        (std::filesystem::temp_directory_path() / ("mixcon-" + name + "-XXXXXX")).string();
    if (::mkdtemp(pattern.data()) == nullptr)
      throw std::runtime_error("cannot create a scratch folder " + pattern);
    path_ = pattern;
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir &) = delete;
  ScratchDir &operator=(const ScratchDir &) = delete;
  const std::filesystem::path &path() const { return path_; }

private:
  std::filesystem::path path_;
};

#ifdef MIXCON_APP
/// Runs `mixcon <args>` (through the shell); returns its exit code (-1 when it did not exit) and
/// fills `output` with its stdout and stderr, kept in `dir`/log.txt.
inline int runMixcon(const std::string &args, std::string &output,
                     const std::filesystem::path &dir) {
  const std::filesystem::path log = dir / "log.txt";
  const std::string cmd = std::string(MIXCON_APP) + " " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream in(log);
  std::stringstream s;
  s << in.rdbuf();
  output = s.str();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
#endif

} // namespace mixcon::test
