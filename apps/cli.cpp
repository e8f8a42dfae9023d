#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "apps/version.h"
#include "rasterizer/output_file.h"

namespace relief::cli {

namespace {

// The longest message printed: "relief: " + this + "\n" stays under 300 characters.
constexpr size_t kMaxMessage = 288;

// `s` as one printable line: C0 control bytes, DEL and the C1 controls (U+0080..U+009F in UTF-8)
// as \xNN, everything else (UTF-8 text, backslashes, escapes made earlier) as it is; cut to
// kMaxMessage bytes with "..." (never inside an escape or a UTF-8 sequence).
std::string printable_line(const std::string& s) {
  static const char* hex = "0123456789abcdef";
  std::string out;
  auto esc = [&](unsigned char c) { return std::string{'\\', 'x', hex[c >> 4], hex[c & 15]}; };
  for (size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    std::string unit;
    if (c < 0x20 || c == 0x7f) {
      unit = esc(c);
      i += 1;
    } else if (c == 0xc2 && i + 1 < s.size() && static_cast<unsigned char>(s[i + 1]) >= 0x80 &&
               static_cast<unsigned char>(s[i + 1]) <= 0x9f) {
      unit = esc(c) + esc(static_cast<unsigned char>(s[i + 1]));
      i += 2;
    } else {
      size_t n = 1;  // a whole UTF-8 sequence stays together
      while (i + n < s.size() && n < 4 && (static_cast<unsigned char>(s[i + n]) & 0xc0) == 0x80 &&
             c >= 0xc0)
        ++n;
      unit = s.substr(i, n);
      i += n;
    }
    if (out.size() + unit.size() > kMaxMessage - 3) {
      out += "...";
      return out;
    }
    out += unit;
  }
  return out;
}

}  // namespace

int fail(const std::string& message, int exit_code) {
  const std::string line = "relief: " + printable_line(message) + "\n";
  std::fputs(line.c_str(), stderr);  // one write of the whole line
  std::fflush(stderr);
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
  // Outputs in flight are removed on SIGTERM / SIGINT (exit 143 / 130); SIGXFSZ is ignored so a
  // file-size limit is a write error, not a crash.
  install_output_signal_handlers();
  CLI::App app{"relief: per-fragment displacement (relief) mapping renderer"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Show help for every subcommand");
  app.set_version_flag(
      "--version", [] { return build_info_text(); },
      "Print the version, commit, build type, SIMD path and backends");
  std::vector<Action> actions(9);
  register_render(app, actions[0]);
  register_techniques(app, actions[1]);
  register_scenes(app, actions[2]);
  register_compare(app, actions[3]);
  register_info(app, actions[4]);
  register_bake(app, actions[5]);
  register_export(app, actions[6]);
  register_bench(app, actions[7]);
  register_version(app, actions[8]);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    std::fputs(e.what(), stdout);  // the text ends with a newline
    return 0;
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
