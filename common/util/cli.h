#pragma once
/// @file cli.h
/// What every command-line tool does around its work: turn bad input into one line on stderr and
/// exit code 2, an interruption (common/util/interrupt.h) into one line and exit code 128 + signal
/// (130 for SIGINT, 143 for SIGTERM), other failures into exit code 1, and never let an exception
/// escape as a crash.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <string>
#include <thread>

#include "common/util/comm.h"
#include "common/util/error.h"
#include "common/util/interrupt.h"
#ifdef FIRSTSHOT_WITH_MPI
#include "common/mpi/mpi_comm.h"
#endif

/// Declares `firstshot::Comm& NAME`, the ranks of this process's run: in a `-mpi` tool (FIRSTSHOT_WITH_MPI)
/// MPI_COMM_WORLD, started here (first thing in main) and finalized at the end of main's scope;
/// otherwise the run of one process.
#ifdef FIRSTSHOT_WITH_MPI
#define FIRSTSHOT_TOOL_COMM(argc, argv, NAME) \
  firstshot::MpiSession NAME##Session(argc, argv);   \
  firstshot::Comm& NAME = NAME##Session.comm()
#else
#define FIRSTSHOT_TOOL_COMM(argc, argv, NAME) firstshot::Comm& NAME = firstshot::serialComm()
#endif

namespace firstshot {

/// Runs @p body and maps exceptions to exit codes: InputError -> 2, Interrupted -> 128 + signal,
/// anything else -> 1.
///
/// In a run of several ranks (@p comm, docs/mpi.md) a failing rank stops the whole job with its exit
/// code (Comm::abort) instead of leaving the others waiting. Rank 0 prints its message at once;
/// another rank waits a second first (leaving silently if the job is ended meanwhile), so that a
/// failure every rank meets alike (bad input) is printed once, by rank 0, and one only that rank
/// meets is printed with its rank.
inline int runTool(const char* tool, Comm& comm, const std::function<int()>& body) {
  int code = 0;
  std::string message;
  try {
    return body();
  } catch (const InputError& e) {
    message = std::string("error: ") + e.what(), code = kExitBadInput;
  } catch (const Interrupted& e) {
    message = e.what(), code = e.exitCode();
  } catch (const std::exception& e) {
    message = std::string("error: ") + e.what(), code = 1;
  }
  if (comm.size() > 1 && !comm.root()) {
    for (int i = 0; i < 20; ++i) {  // Open MPI ends the other ranks of an aborted job with SIGTERM
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      if (interrupted()) std::_Exit(code);
    }
    std::fprintf(stderr, "%s (rank %d of %d): %s\n", tool, comm.rank(), comm.size(), message.c_str());
  } else {
    std::fprintf(stderr, "%s: %s\n", tool, message.c_str());
  }
  if (comm.size() > 1) {
    std::fflush(stderr);
    comm.abort(code);
  }
  return code;
}

/// runTool for a run of one process.
inline int runTool(const char* tool, const std::function<int()>& body) { return runTool(tool, serialComm(), body); }

}  // namespace firstshot
