#pragma once
/// @file cli.h
/// What every command-line tool does around its work: turn bad input into one line on stderr and
/// exit code 2, an interruption (common/interrupt.h) into one line and exit code 128 + signal
/// (130 for SIGINT, 143 for SIGTERM), other failures into exit code 1, and never let an exception
/// escape as a crash.
#include <cstdio>
#include <exception>
#include <functional>

#include "common/error.h"
#include "common/interrupt.h"

namespace fs {

/// Runs @p body and maps exceptions to exit codes: InputError -> 2, Interrupted -> 128 + signal,
/// anything else -> 1.
inline int runTool(const char* tool, const std::function<int()>& body) {
  try {
    return body();
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s: error: %s\n", tool, e.what());
    return kExitBadInput;
  } catch (const Interrupted& e) {
    std::fprintf(stderr, "%s: %s\n", tool, e.what());
    return e.exitCode();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", tool, e.what());
    return 1;
  }
}

}  // namespace fs
