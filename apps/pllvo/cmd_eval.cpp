// Placeholder until the eval module lands (replaced by the evaluation work).
#include "commands.h"
#include "pllvo/common/error.h"

namespace pllvo::cli {

void add_eval_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("eval", "compare an estimated trajectory with a reference (evo-exact)");
  cmd->callback([] { throw InputError("eval: not implemented yet"); });
}

}  // namespace pllvo::cli
