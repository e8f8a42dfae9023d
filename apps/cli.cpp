#include <cstdio>
#include <vector>

#include "apps/commands.h"

namespace relief::cli {

int fail(const std::string& message, int exit_code) {
  std::fprintf(stderr, "relief: %s\n", message.c_str());
  return exit_code;
}

int run(int argc, char** argv) {
  CLI::App app{"relief: per-fragment displacement (relief) mapping renderer"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Show help for every subcommand");
  std::vector<Action> actions(8);
  register_render(app, actions[0]);
  register_techniques(app, actions[1]);
  register_scenes(app, actions[2]);
  register_compare(app, actions[3]);
  register_info(app, actions[4]);
  register_bake(app, actions[5]);
  register_export(app, actions[6]);
  register_bench(app, actions[7]);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, usage exit code.
    return fail(e.what(), 2);
  }
  for (auto& a : actions)
    if (a) return a();
  return fail("no subcommand given (try --help)", 2);
}

}  // namespace relief::cli
