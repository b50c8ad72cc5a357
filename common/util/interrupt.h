#pragma once
/// @file interrupt.h
/// Interruption by SIGINT / SIGTERM without loss. installInterruptHandlers() makes the first such
/// signal only set a flag (async-signal-safe: one lock-free atomic store); the long loops poll it
/// (interrupted(), or interruptFlag() as RenderOptions::cancel) and stop by throwing Interrupted,
/// which runTool (common/util/cli.h) turns into one line on stderr and exit code 128 + signal
/// (130 for SIGINT, 143 for SIGTERM). A second signal at least 0.5 s after the first terminates
/// the process at once with the default action (an earlier one is taken for the same signal
/// delivered twice, as timeout(1) does: to the process, then to its group). Outputs written through
/// writeAtomically (common/util/atomic_file.h) are not renamed into place once the flag is set.
#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace firstshot {

/// Installs the SIGINT and SIGTERM handlers (idempotent). Call early in main().
void installInterruptHandlers();

/// The signal number received (SIGINT, SIGTERM), or 0.
int interruptSignal();
inline bool interrupted() { return interruptSignal() != 0; }
/// The flag set by the handler, for loops that take a `const std::atomic<bool>*` cancel flag.
const std::atomic<bool>& interruptFlag();
/// Sets the flag as if signal @p signal had arrived (for tests and in-process cancellation).
void requestInterrupt(int signal);
/// Clears the flag (tests).
void clearInterrupt();

/// "SIGINT", "SIGTERM" or "signal N".
std::string signalName(int signal);

/// Thrown by an interrupted loop; carries the signal and what was (not) saved.
class Interrupted : public std::runtime_error {
 public:
  /// @param detail what the run leaves behind, e.g. "no output written"
  Interrupted(int signal, const std::string& detail)
      : std::runtime_error("interrupted by " + signalName(signal) + "; " + detail), signal_(signal) {}
  int signal() const { return signal_; }
  /// The process exit code: 128 + signal (130 for SIGINT, 143 for SIGTERM).
  int exitCode() const { return 128 + signal_; }

 private:
  int signal_;
};

/// Throws Interrupted(interruptSignal(), @p detail) if a signal has arrived.
void throwIfInterrupted(const std::string& detail = "no output written");

/// Testing aid: if the environment variable FIRSTSHOT_TEST_INTERRUPT equals @p point, or is
/// "@p point:TERM", the process raises SIGINT (or SIGTERM) to itself here, through the installed
/// handler. Points: "render-pass-K" (K render passes done), "write-NAME" (the temporary file of
/// output NAME written, before its rename). Does nothing when the variable is unset.
void testInterruptPoint(const std::string& point);

}  // namespace firstshot
