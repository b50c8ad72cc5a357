#pragma once
/// @file test_util.h
/// Helpers shared by the tests: running the command-line tools, temporary files.
#include <string>

namespace fs::test {

struct CommandResult {
  int exitCode = -1;
  std::string output;  ///< stdout and stderr together
};

/// Runs a shell command, capturing stdout+stderr and the exit code.
CommandResult run(const std::string& command);

/// A fresh, empty temporary directory for this test (removed at exit of the process is not needed).
std::string tempDir();

/// Writes @p text to @p path (creating parent directories).
void writeText(const std::string& path, const std::string& text);

/// Path of a file in the source tree, e.g. source("scenes/cornell.json").
std::string source(const std::string& relative);

}  // namespace fs::test
