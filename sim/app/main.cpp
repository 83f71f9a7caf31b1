// fovsim CLI entry point: the only place that catches fovsim::Error, prints one line and exits.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "sim/app/commands.h"
#include "sim/core/error.h"
#include "sim/core/message_text.h"
#include "sim/core/params.h"
#include "sim/core/version.h"
#include "sim/core/watchdog.h"

namespace {

// A command line CLI11 rejected, as one line and its exit code: a mistyped command gets a
// suggestion, a group without its subcommand lists them, --help and --version exit 0.
int parse_error_exit(CLI::App& app, int argc, char** argv, const CLI::ParseError& e) {
  // A mistyped command ("fovsim rn", "fovsim trace valdate") gets a suggestion.
  CLI::App* cur = &app;
  for (int i = 1; i < argc; ++i) {
    if (argv[i][0] == '-') {  // a flag: a later word may still be an unknown command
      if (cur->get_require_subcommand_min() > 0) continue;
      break;
    }
    std::vector<std::string> names;
    CLI::App* next = nullptr;
    for (CLI::App* s : cur->get_subcommands({})) {
      names.push_back(s->get_name());
      if (s->get_name() == argv[i]) next = s;
    }
    if (next) {
      cur = next;
      continue;
    }
    std::string best = fovsim::closest_name(argv[i], names);
    if (!best.empty()) {
      std::fprintf(stderr, "fovsim: error: unknown command '%s' (did you mean `%s`?)\n", argv[i],
                   best.c_str());
      return 2;
    }
    if (!names.empty() && cur->get_subcommands({}).size() > 0 &&
        cur->get_require_subcommand_min() > 0) {
      std::string list;
      for (auto& n : names) list += (list.empty() ? "" : ", ") + n;
      const std::string word = fovsim::escape_control(argv[i], 40);
      std::fprintf(stderr, "fovsim: error: unknown command '%s' (commands: %s)\n", word.c_str(),
                   list.c_str());
      return 2;
    }
    break;
  }
  // A command group given without its subcommand ("fovsim trace"): name the group and list
  // its subcommands instead of CLI11's "A subcommand is required".
  if (cur->get_require_subcommand_min() > 0 && dynamic_cast<const CLI::RequiredError*>(&e)) {
    std::string list;
    for (CLI::App* s : cur->get_subcommands({})) list += (list.empty() ? "" : ", ") + s->get_name();
    const std::string name = cur == &app ? std::string("fovsim") : "fovsim " + cur->get_name();
    std::fprintf(stderr, "fovsim: error: %s needs a command (one of: %s; see --help)\n",
                 name.c_str(), list.c_str());
    return 2;
  }
  if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
  // Bad flags and values are one line like every other input error (the usage hint of
  // CLI11 would be a second line). An unknown subcommand is named as such.
  std::string msg = e.what();
  for (char& ch : msg)
    if (ch == '\n' || ch == '\r') ch = ' ';
  std::fprintf(stderr, "fovsim: error: %s (see --help)\n", fovsim::escape_control(msg).c_str());
  return 2;
}

// An output path given as "" is an error, not "the default folder" or the current one: true
// after printing it.
bool empty_output_path(CLI::App& app) {
  for (CLI::App* sub = &app; sub;) {
    for (const CLI::Option* o : sub->get_options()) {
      const std::string& n = o->get_name();
      const bool out = n == "--out" || n == "-o,--output" || n == "-o,--out" || n == "--output";
      if (!out || o->count() == 0) continue;
      for (const std::string& v : o->results())
        if (v.empty()) {
          std::fprintf(stderr,
                       "fovsim: error: %s: output path is empty (give a path, or omit the flag "
                       "for the default)\n",
                       o->get_name().c_str());
          return true;
        }
    }
    auto parsed = sub->get_subcommands();
    sub = parsed.empty() ? nullptr : parsed.front();
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fovsim " + fovsim::version_string() +
               " — trace-driven simulator and design-space explorer for foveated rendering.\n"
               "Replays head+gaze traces through CPU implementations of foveation methods and a\n"
               "cost-modelled GPU pipeline; reports per-frame costs, counters and image metrics."};
  app.set_version_flag("--version", fovsim::version_string() + " (" + fovsim::git_commit() + ")");
  app.require_subcommand(1);
  fovsim::app::Action action;
  // A hang reported by the library's watchdog ends the process with one line (exit 3: a bug,
  // not bad input). Files already written stay intact (they are written atomically).
  fovsim::Watchdog::set_handler([](const std::string& msg) {
    std::fprintf(stderr, "fovsim: error: %s\n", msg.c_str());
    std::fflush(stderr);
    std::_Exit(3);
  });
  fovsim::app::register_commands(app, action);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return parse_error_exit(app, argc, argv, e);
  }
  if (empty_output_path(app)) return 2;
  try {
    return action ? action() : 0;
  } catch (const fovsim::Error& e) {
    std::fprintf(stderr, "fovsim: error: %s\n", fovsim::escape_control(e.what(), 4000).c_str());
    return 2;
  } catch (const fovsim::InternalError& e) {  // FOVSIM_CHECK: a bug, not the input
    std::fprintf(stderr, "fovsim: internal error: %s (a bug in fovsim, not in the input)\n",
                 e.what());
    return 3;
  } catch (const std::bad_alloc&) {
    // The phases that hold large buffers name what they allocate and the key that sizes it
    // (with_memory_context, an Error above); this one is not attributed to any.
    std::fprintf(stderr,
                 "fovsim: error: out of memory (not attributed to a phase that names its key; "
                 "give the process more memory)\n");
    return 3;
  } catch (const nlohmann::json::exception& e) {  // JSON read without a check: a bug
    std::fprintf(stderr, "fovsim: internal error: unchecked JSON: %s (a bug in fovsim)\n",
                 fovsim::escape_control(fovsim::json_error_text(e), 200).c_str());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fovsim: internal error: %s\n", e.what());
    return 3;
  }
}
