#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <regex>
#include <vector>

namespace firstshot::test {

CommandResult run(const std::string& command) {
  CommandResult r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

namespace {
/// The folders tempDir() made, removed when the test program ends unless a test failed (they are then kept, and
/// named, for a look at what it wrote). Constructed at the first tempDir(), after gtest's UnitTest, so destroyed first.
struct TempDirs {
  std::vector<std::filesystem::path> made;
  ~TempDirs() {
    const bool failed = ::testing::UnitTest::GetInstance()->Failed();
    for (const auto& dir : made) {
      std::error_code ec;
      if (failed)
        std::fprintf(stderr, "kept %s\n", dir.c_str());
      else
        std::filesystem::remove_all(dir, ec);
    }
  }
};
TempDirs& tempDirs() {
  static TempDirs dirs;
  return dirs;
}
}  // namespace

std::string tempDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "_" + info->name() : "firstshot";
  for (char& c : name)
    if (c == '/') c = '_';
  std::random_device rd;
  auto dir = std::filesystem::temp_directory_path() / ("fs_test_" + name + "_" + std::to_string(rd()));
  std::filesystem::create_directories(dir);
  tempDirs().made.push_back(dir);
  return dir.string();
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void writeText(const std::string& path, const std::string& text) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

std::string source(const std::string& relative) { return std::string(FIRSTSHOT_SOURCE_DIR) + "/" + relative; }

namespace {
std::vector<std::string> groups(const std::smatch& m) {
  std::vector<std::string> g;
  for (const auto& sub : m) g.push_back(sub.str());
  return g;
}
}  // namespace

std::vector<std::string> regexSearch(const std::string& text, const std::string& pattern) {
  std::smatch m;
  return std::regex_search(text, m, std::regex(pattern)) ? groups(m) : std::vector<std::string>{};
}

std::vector<std::string> regexMatch(const std::string& text, const std::string& pattern) {
  std::smatch m;
  return std::regex_match(text, m, std::regex(pattern)) ? groups(m) : std::vector<std::string>{};
}

}  // namespace firstshot::test
