// `fovsim trace import|validate|stats|synth|keys` (traces/README.md).
#include <cstdio>
#include <iostream>
#include <memory>

#include "sim/app/commands.h"
#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/experiment/config.h"
#include "sim/trace/importer.h"
#include "sim/trace/map_keys.h"
#include "sim/trace/map_search.h"
#include "sim/trace/stats.h"
#include "sim/trace/synth.h"
#include "sim/trace/trace.h"

namespace fovsim::app {

namespace {

struct TraceArgs {
  std::string in, map, out, display = kDefaultDisplay, models, on_bad = "fail";
  std::string scenario, params;
  bool guess = false;
  double seed = 1;
  double duration = 10, rate = 0;
  double max_gap = 1;
  double max_samples = kDefaultMaxTraceSamples;
};

Display load_display(const TraceArgs& a) {
  return Display::load(a.display, a.models.empty() ? default_models_dir() : a.models);
}

BadSamplePolicy policy(const std::string& s) {
  return s == "skip"   ? BadSamplePolicy::Skip
         : s == "hold" ? BadSamplePolicy::Hold
                       : BadSamplePolicy::Fail;
}

long outside_fov(const Trace& tr, const Display& d) {
  long n = 0;
  for (auto& s : tr.samples)
    if (s.valid && !gaze_inside_fov(d, s.gaze_dir)) ++n;
  return n;
}

void print_summary(const Trace& tr, const Display& d) {
  std::printf("%s", format_stats(trace_stats(tr)).c_str());
  long out = outside_fov(tr, d);
  std::printf("outside FOV        %ld valid samples outside the %s FOV (%.0fx%.0f deg)\n", out,
              d.name.c_str(), d.fov_h_deg, d.fov_v_deg);
  for (auto& w : tr.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
}

void add_display_opts(CLI::App* c, TraceArgs& a) {
  c->add_option("--display", a.display,
                "Display name or path (models/displays/NAME.json); bounds the gaze FOV")
      ->capture_default_str();
  c->add_option("--models", a.models,
                "Models directory (default: $FOVSIM_MODELS, ./models, or the source tree's)");
}

// `trace import`: a recording to the canonical CSV (or --guess a column map).
void register_trace_import(CLI::App* t, const std::shared_ptr<TraceArgs>& a, Action& action) {
  CLI::App* imp = t->add_subcommand(
      "import", "Convert a recording to the canonical CSV with a JSON column map");
  imp->add_option("IN", a->in, "Recording to import (CSV/TSV/...)")->required();
  imp->add_option("--map", a->map,
                  "Column map JSON (see traces/README.md, e.g. traces/maps/pico_neo3_pro.json)");
  imp->add_option("-o,--output", a->out, "Canonical CSV to write");
  imp->add_flag(
      "--guess", a->guess,
      "Print a column map chosen by importing a sample of IN under each plausible convention and "
      "scoring the result (choice, runner-up and margin on stderr)");
  imp->add_option("--on-bad", a->on_bad,
                  "Valid gaze outside the display FOV: fail (error at file:line:column), skip the "
                  "row, or hold the "
                  "last valid gaze")
      ->check(CLI::IsMember({"fail", "skip", "hold"}))
      ->capture_default_str();
  add_display_opts(imp, *a);
  imp->callback([a, imp, &action] {
    if (a->guess) {
      action = [a] {
        MapSearchResult r = search_map(a->in, load_display(*a));
        for (auto& l : r.report) std::fprintf(stderr, "%s\n", l.c_str());
        std::printf("%s\n", r.map.dump(2).c_str());
        return 0;
      };
      return;
    }
    if (a->map.empty()) throw CLI::RequiredError("--map (or --guess)");
    if (a->out.empty()) throw CLI::RequiredError("--output");
    action = [a, imp] {
      check_output_target(a->out);  // before any work: never replaces a FIFO, device or link
      Display d = load_display(*a);
      ImportReport rep;
      ImportOptions io;
      io.on_fov = policy(a->on_bad);
      io.on_fov_explicit = imp->count("--on-bad") > 0;  // else the map's "on_bad"
      Trace tr = import_trace_hinted(a->in, a->map, d, &rep, io);
      check_trace_as_written(tr, d, a->in, a->out);  // never a file trace validate refuses
      write_trace_csv(a->out, tr);
      std::printf("imported %s -> %s\n", a->in.c_str(), a->out.c_str());
      std::printf("rows               %ld read, %ld skipped, %ld flagged invalid\n", rep.data_rows,
                  rep.skipped_rows, rep.invalid_rows);
      if (rep.time_offset_s != 0) std::printf("time rebased by    %.6f s\n", rep.time_offset_s);
      print_summary(tr, d);
      return 0;
    };
  });
}

// `trace validate`: check a canonical trace CSV.
void register_trace_validate(CLI::App* t, const std::shared_ptr<TraceArgs>& a, Action& action) {
  CLI::App* val =
      t->add_subcommand("validate", "Check a canonical trace CSV (errors name file:line:column)");
  val->add_option("FILE", a->in, "Canonical trace CSV")->required();
  val->add_option("--on-bad", a->on_bad,
                  "Bad-sample policy: fail (first problem is an error), skip or hold")
      ->check(CLI::IsMember({"fail", "skip", "hold"}))
      ->capture_default_str();
  add_number(val, "--max-gap", a->max_gap, "Flag intervals between samples longer than this",
             {Range::above(0, 1e9), "s", false, "no check"})
      ->capture_default_str();
  add_display_opts(val, *a);
  val->callback([a, &action] {
    action = [a] {
      Display d = load_display(*a);
      TraceReadOptions o;
      o.on_bad = policy(a->on_bad);
      o.max_gap_s = a->max_gap > 0 ? a->max_gap : INFINITY;
      Trace tr = read_trace_csv(a->in, d, o);
      print_summary(tr, d);
      if (!tr.warnings.empty()) {
        std::printf("%s: usable, with %zu kind(s) of problems (see warnings)\n", a->in.c_str(),
                    tr.warnings.size());
        return 1;
      }
      std::printf("%s: valid\n", a->in.c_str());
      return 0;
    };
  });
}

// `trace stats`: summary of a canonical trace or a raw recording.
void register_trace_stats(CLI::App* t, const std::shared_ptr<TraceArgs>& a, Action& action) {
  CLI::App* st = t->add_subcommand(
      "stats", "Summary of a trace: duration, rate, gaps, invalid fraction, gaze statistics");
  st->add_option("FILE", a->in, "Canonical trace CSV (or a raw recording with --map)")->required();
  st->add_option("--map", a->map, "Column map: summarize a raw recording without writing it");
  st->add_option("--on-bad", a->on_bad, "Bad-sample policy for canonical files: fail, skip or hold")
      ->check(CLI::IsMember({"fail", "skip", "hold"}))
      ->capture_default_str();
  add_display_opts(st, *a);
  st->callback([a, &action] {
    action = [a] {
      Display d = load_display(*a);
      Trace tr;
      if (!a->map.empty()) {
        ImportOptions io;
        io.check_fov = false;  // counted in the summary instead
        tr = import_trace_hinted(a->in, a->map, d, nullptr, io);
      } else {
        TraceReadOptions o;
        o.on_bad = policy(a->on_bad);
        tr = read_trace_csv(a->in, d, o);
      }
      std::printf("trace              %s\n", a->in.c_str());
      print_summary(tr, d);
      return 0;
    };
  });
}

// `trace synth`: a synthetic trace from the eye-movement model.
void register_trace_synth(CLI::App* t, const std::shared_ptr<TraceArgs>& a, Action& action) {
  CLI::App* syn =
      t->add_subcommand("synth", "Generate a synthetic trace from the eye-movement model");
  std::string names;
  for (auto& s : synth_scenarios()) names += (names.empty() ? "" : ", ") + s;
  syn->add_option("--scenario", a->scenario, "Scenario: " + names)
      ->required()
      ->check(CLI::IsMember(synth_scenarios()));
  add_number(syn, "--seed", a->seed, "Random seed (same seed, same trace)",
             {Range::closed(0, kMaxSynthSeed), "seed", true})
      ->capture_default_str();
  add_number(syn, "--duration", a->duration, "Duration of the trace", {Range::above(0, 36000), "s"})
      ->capture_default_str();
  add_number(syn, "--rate", a->rate, "Output rate (default: the display's refresh rate)",
             {Range::above(0, 10000), "Hz"});
  add_number(syn, "--max-samples", a->max_samples,
             "Most samples generated (output or internal rate, whichever is higher)",
             {Range::closed(1, 2e9), "samples"})
      ->capture_default_str();
  syn->add_option("--params", a->params,
                  "Eye-model overrides JSON (any subset of models/eyemodel/default.json)");
  syn->add_option("-o,--output", a->out, "Canonical CSV to write")->required();
  add_display_opts(syn, *a);
  syn->callback([a, &action] {
    action = [a] {
      check_output_target(a->out);
      Display d = load_display(*a);
      EyeModel m;
      if (!a->params.empty()) m = load_eye_model(Json(a->params), "--params", "", "");
      SynthOptions o;
      o.scenario = a->scenario;
      o.seed = uint64_t(a->seed);
      o.duration_s = a->duration;
      o.rate_hz = a->rate > 0 ? a->rate : d.refresh_hz;
      const double n = synth_sample_count(m, o);
      if (!(n <= a->max_samples)) {
        char b[256];
        std::snprintf(b, sizeof b,
                      "%.6g s at %.6g Hz (internal rate %.6g Hz) is %.6g samples, over the limit "
                      "--max-samples %.6g (shorten it or raise --max-samples)",
                      o.duration_s, o.rate_hz, m.internal_rate_hz, n, a->max_samples);
        throw Error("--duration", b);
      }
      Trace tr = synthesize(m, o, d);
      write_trace_csv(a->out, tr);
      std::printf("wrote %s (%s)\n", a->out.c_str(), tr.source.c_str());
      print_summary(tr, d);
      return 0;
    };
  });
}

// `trace keys`: the column map's keys, as declared (sim/trace/map_keys.cpp).
void register_trace_keys(CLI::App* t, Action& action) {
  CLI::App* k = t->add_subcommand("keys", "List the keys of a column map (traces/README.md)");
  auto markdown = std::make_shared<bool>(false);
  k->add_flag("--markdown", *markdown, "As the Markdown table embedded in traces/README.md");
  k->callback([markdown, &action] {
    action = [markdown] {
      if (*markdown) {
        std::cout << map_keys_markdown();
        return 0;
      }
      for (const MapKey& m : map_keys())
        std::cout << m.path << (m.variant.empty() ? "" : " (" + m.variant + ")") << "\n";
      return 0;
    };
  });
}

}  // namespace

void register_trace(CLI::App& app, Action& action) {
  auto a = std::make_shared<TraceArgs>();
  CLI::App* t = app.add_subcommand(
      "trace", "Head+gaze traces: import recordings, validate, summarize, synthesize");
  t->require_subcommand(1);

  register_trace_import(t, a, action);
  register_trace_validate(t, a, action);
  register_trace_stats(t, a, action);
  register_trace_synth(t, a, action);
  register_trace_keys(t, action);
}

}  // namespace fovsim::app
