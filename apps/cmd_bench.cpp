// `relief bench`: the accuracy/cost sweep (sweep/sweep.h) from the command line.
#include "apps/commands.h"

namespace relief::cli {

void register_bench(CLI::App& app, Action& action) {
  auto* sub = app.add_subcommand("bench", "Accuracy/cost sweep of the relief techniques");
  sub->callback([&action] { action = [] { return fail("bench: not built yet", 1); }; });
}

}  // namespace relief::cli
