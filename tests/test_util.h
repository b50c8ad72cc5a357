#pragma once
/// @file test_util.h
/// Helpers shared by the tests: running the command-line tools, temporary files.
#include <string>
#include <vector>

/// True in the ASan+UBSan build (gcc and clang).
#if defined(__SANITIZE_ADDRESS__)
#define FIRSTSHOT_UNDER_SANITIZERS 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FIRSTSHOT_UNDER_SANITIZERS 1
#endif
#endif

/// Marks a statistical test on a large scene that runs in the optimised build only. Under ASan+UBSan such a test
/// takes minutes and checks an estimator's accuracy, not memory or UB; the sanitizers still run the code it uses
/// through the smaller test named in @p coveredBy. The skip is reported by ctest, with that name.
#ifdef FIRSTSHOT_UNDER_SANITIZERS
#define FIRSTSHOT_STATISTICS_ONLY(coveredBy) \
  GTEST_SKIP() << "statistics only, run in the Release build; under the sanitizers the code runs in " coveredBy
#else
#define FIRSTSHOT_STATISTICS_ONLY(coveredBy) static_cast<void>(0)
#endif

namespace firstshot::test {

struct CommandResult {
  int exitCode = -1;
  std::string output;  ///< stdout and stderr together
};

/// Runs a shell command, capturing stdout+stderr and the exit code.
CommandResult run(const std::string& command);

/// A fresh, empty temporary directory for this test (removed at exit of the process is not needed).
std::string tempDir();

/// The whole content of the file at @p path, byte for byte ("" if it cannot be read).
std::string readFile(const std::string& path);

/// Writes @p text to @p path (creating parent directories).
void writeText(const std::string& path, const std::string& text);

/// Path of a file in the source tree, e.g. source("scenes/cornell.json").
std::string source(const std::string& relative);

/// The first match of the ECMAScript regular expression @p pattern in @p text: the whole match, then each group; empty
/// if none. (std::regex is compiled here once: it costs a test file 4 s to compile, 11 s under the sanitizers.)
std::vector<std::string> regexSearch(const std::string& text, const std::string& pattern);
/// The same for a match of the whole of @p text.
std::vector<std::string> regexMatch(const std::string& text, const std::string& pattern);

}  // namespace firstshot::test
