// libFuzzer target: the CLI's argument parsing. The input is an argument list, one argument per
// line. Every subcommand is registered on a CLI11 app exactly as `relief` does (apps/cli.cpp) and
// the list is parsed, but no action runs (nothing is rendered or written). Each argument is also
// given to parse_size (--size WxH) and, when it looks like key=value, to resolve_params of every
// registered plugin (what --param does). Any input must parse or give a one-line error.
#include <map>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "apps/output.h"
#include "plugins/registry.h"

namespace {

void one_line(const std::string& message) {
  if (message.find('\n') != std::string::npos) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 4096) return 0;
  std::vector<std::string> args{"relief"};
  std::string cur;
  for (size_t i = 0; i < size; ++i) {
    if (data[i] == '\n') {
      args.push_back(cur);
      cur.clear();
    } else {
      cur.push_back(static_cast<char>(data[i]));
    }
  }
  if (!cur.empty()) args.push_back(cur);

  CLI::App app{"relief"};
  app.require_subcommand(1);
  std::vector<relief::cli::Action> actions(7);
  relief::cli::register_render(app, actions[0]);
  relief::cli::register_techniques(app, actions[1]);
  relief::cli::register_scenes(app, actions[2]);
  relief::cli::register_compare(app, actions[3]);
  relief::cli::register_info(app, actions[4]);
  relief::cli::register_bake(app, actions[5]);
  relief::cli::register_export(app, actions[6]);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::ParseError&) {
  }

  for (size_t i = 1; i < args.size(); ++i) {
    int w = 0, h = 0;
    const relief::Status s = relief::cli::parse_size(args[i], w, h);
    if (s.ok() && (w < 1 || h < 1 || static_cast<long long>(w) * h > relief::cli::kMaxTargetPixels))
      __builtin_trap();
    if (!s.ok()) one_line(s.message());
    const size_t eq = args[i].find('=');
    if (eq == std::string::npos || eq == 0) continue;
    const std::map<std::string, std::string> text{{args[i].substr(0, eq), args[i].substr(eq + 1)}};
    for (const relief::PluginDescriptor* p : relief::PluginRegistry::global().all()) {
      relief::Result<std::vector<float>> v = relief::resolve_params(*p, {}, text);
      if (!v.ok()) {
        one_line(v.status().message());
        continue;
      }
      for (int k = 0; k < p->num_params; ++k) {
        const relief::ParamSpec& spec = p->params[k];
        const float x = (*v)[k];
        if (!(x == x) ||
            (spec.type != relief::ParamType::kEnum && spec.type != relief::ParamType::kBool &&
             (x < spec.min_value || x > spec.max_value)))
          __builtin_trap();  // a value outside the schema got through
      }
    }
  }
  return 0;
}
