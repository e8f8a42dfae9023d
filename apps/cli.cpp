#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "apps/commands.h"

namespace relief::cli {

int fail(const std::string& message, int exit_code) {
  std::fprintf(stderr, "relief: %s\n", message.c_str());
  return exit_code;
}

namespace {

// Newlines (CLI11 and library messages can hold some) become "; ".
std::string one_line(std::string s) {
  for (size_t i = s.find('\n'); i != std::string::npos; i = s.find('\n', i))
    s.replace(i, 1, i + 1 < s.size() ? "; " : "");
  return s;
}

}  // namespace

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
    // One line, usage exit code; a first word that is no subcommand is named.
    if (argc > 1 && argv[1][0] != '-' && app.get_subcommands().empty())
      return fail(std::string("unknown command '") + argv[1] + "' (try --help)", 2);
    return fail(one_line(e.what()), 2);
  }
  try {
    for (auto& a : actions)
      if (a) return a();
  } catch (const std::bad_alloc&) {  // a request the limits let through but memory does not hold
    return fail("out of memory (see docs/errors.md, \"Limits\")", 1);
  } catch (const std::exception& e) {
    return fail(one_line(e.what()), 1);
  }
  return fail("no subcommand given (try --help)", 2);
}

}  // namespace relief::cli
