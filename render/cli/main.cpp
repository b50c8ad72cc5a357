// firstshot-render: scene [+ first-shot table] -> image, with the Embree path tracer
// (the command line's steps: render/cli/render_command.h).
#include "common/util/cli.h"
#include "render/cli/render_command.h"

int main(int argc, char** argv) {
  FIRSTSHOT_TOOL_COMM(argc, argv, comm);  // MPI_COMM_WORLD in firstshot-render-mpi (docs/mpi.md)
  return firstshot::runTool("firstshot-render", comm, [&] { return firstshot::RenderCommand(comm).run(argc, argv); });
}
