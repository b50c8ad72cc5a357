#pragma once
/// @file mpi_comm.h
/// The MPI job a `-mpi` tool runs in (Open MPI): the one file of the project that includes mpi.h
/// is mpi_comm.cpp. Built only with -DFIRSTSHOT_MPI=ON (docs/mpi.md).
#include <memory>

#include "common/util/comm.h"

namespace firstshot {

/// MPI_Init_thread on construction (MPI_THREAD_SERIALIZED: exchanges may come from any thread, one
/// at a time), MPI_Finalize on destruction. One per process, made first thing in main().
class MpiSession {
 public:
  /// Exits with code 1 and a message if MPI cannot start or lacks the thread level.
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  /// MPI_COMM_WORLD as a Comm.
  Comm& comm();

 private:
  std::unique_ptr<Comm> comm_;
};

}  // namespace firstshot
