// The `relief` CLI: each subcommand registers itself on the CLI11 app from its own file
// (apps/cmd_<name>.cpp) and returns the exit code through CommandResult once run.
#pragma once

#include <functional>
#include <string>

#include <CLI/CLI.hpp>

namespace relief::cli {

// A subcommand's action; returns the process exit code (0 ok, 1 input error, 2 usage error).
using Action = std::function<int()>;

// Each registers a subcommand on `app` and stores the action to run when it is chosen.
void register_render(CLI::App& app, Action& action);
void register_techniques(CLI::App& app, Action& action);
void register_scenes(CLI::App& app, Action& action);
void register_compare(CLI::App& app, Action& action);
void register_info(CLI::App& app, Action& action);
void register_bake(CLI::App& app, Action& action);
void register_export(CLI::App& app, Action& action);
void register_bench(CLI::App& app, Action& action);
void register_version(CLI::App& app, Action& action);  // apps/cmd_info.cpp

// Prints "relief: <message>" to stderr as one line and returns the exit code for `kind`.
int fail(const std::string& message, int exit_code = 1);

// Runs the CLI on argv; the testable entry point of main().
int run(int argc, char** argv);

}  // namespace relief::cli
