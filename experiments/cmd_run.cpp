// Placeholder until its issue lands: registers the subcommand and says so, never fakes output.
#include "experiments/commands.h"
#include "solvers/error.h"

namespace bivo::experiments {

void add_run_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("run", "(not built yet)");
  cmd->allow_extras();
  cmd->callback([] { throw Error("'bivo run' is not implemented in this build yet"); });
}

}  // namespace bivo::experiments
