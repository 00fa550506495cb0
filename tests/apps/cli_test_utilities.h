#pragma once
// Runs the plantar program (PLANTAR_BINARY, defined by the test's CMake target) as users do.
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <sstream>
#include <string>
#include <sys/wait.h>

namespace plantar::test {

/// Exit status (-1 if killed) and the merged stdout and stderr of one run.
struct Outcome {
  int status;
  std::string output;
};

/// Runs `plantar ARGUMENTS` through the shell.
inline Outcome run_plantar(const std::string& arguments) {
  const std::string command = std::string(PLANTAR_BINARY) + " " + arguments + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  std::string output;
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe))
    output += buffer.data();
  const int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

/// The whole text of @p path (empty if it cannot be read).
inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The value of row `NAME,value` of a run's summary CSV; a test failure and NaN if absent.
inline double summary_value(const std::filesystem::path& file, const std::string& name) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(name + ",", 0) == 0)
      return std::stod(line.substr(name.size() + 1));
  ADD_FAILURE() << file << " lacks " << name;
  return NAN;
}

} // namespace plantar::test
