#include "fem/mesh_generator.h"

#include <array>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

namespace plantar::fem {
namespace {

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw std::runtime_error("mesh: cannot read .geo file '" + file.string() + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// FNV-1a, 64 bit: a stable cache key (not a security hash).
std::string hash_hex(const std::string& text) {
  std::uint64_t hash = 1469598103934665603ull;
  for (const unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  std::ostringstream out;
  out << std::hex << std::setw(16) << std::setfill('0') << hash;
  return out.str();
}

std::string shell_quote(const std::string& s) {
  std::string quoted = "'";
  for (const char c : s)
    quoted += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// Runs a command, returns its exit status and combined output.
int run_command(const std::string& command, std::string& output) {
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr)
    throw std::runtime_error("mesh: cannot start '" + command + "'");
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr)
    output += buffer.data();
  return ::pclose(pipe);
}

} // namespace

std::filesystem::path generate_mesh(const MeshRequest& request) {
  const std::string geo_text = read_text(request.geo_file);
  std::ostringstream key;
  key << geo_text << '\n' << request.gmsh_executable;
  std::ostringstream setnumbers;
  for (const auto& [name, value] : request.numbers) {
    key << '\n' << name << '=' << std::setprecision(17) << value;
    setnumbers << " -setnumber " << shell_quote(name) << ' ' << std::setprecision(17) << value;
  }
  const std::filesystem::path msh = request.cache_directory / (request.geo_file.stem().string() +
                                                               "-" + hash_hex(key.str()) + ".msh");
  if (std::filesystem::exists(msh))
    return msh;

  std::filesystem::create_directories(request.cache_directory);
  const std::filesystem::path tmp = msh.string() + ".tmp-" + std::to_string(::getpid()) + ".msh";
  std::ostringstream limit;
  limit << "timeout -s KILL " << request.time_limit << " ";
  const std::string command = limit.str() + shell_quote(request.gmsh_executable) + " " +
                              shell_quote(request.geo_file.string()) + " -3 -format msh22 -v 2" +
                              setnumbers.str() + " -o " + shell_quote(tmp.string());
  std::string output;
  const int status = run_command(command, output);
  // gmsh reports .geo syntax errors but may still exit 0: treat "Error" lines as failure.
  const bool has_error = output.find("Error") != std::string::npos;
  std::error_code ignored;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGKILL) {
    std::filesystem::remove(tmp, ignored);
    std::ostringstream msg;
    msg << "mesh: gmsh did not finish '" << request.geo_file.string() << "' within "
        << request.time_limit
        << " s: are its dimensions far larger than its mesh sizes (a .geo in mm, not m)?";
    throw std::runtime_error(msg.str());
  }
  if (status != 0 || has_error || !std::filesystem::exists(tmp)) {
    std::filesystem::remove(tmp, ignored);
    throw std::runtime_error("mesh: gmsh failed on '" + request.geo_file.string() +
                             "' (exit status " + std::to_string(status) + "):\n" + output);
  }
  std::filesystem::rename(tmp, msh);
  return msh;
}

} // namespace plantar::fem
