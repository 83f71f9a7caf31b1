#include "sim/trace/trace_keys.h"

#include "sim/trace/synth.h"
#include "sim/trace/trace.h"
#include "sim/trace/tracking.h"

namespace fovsim {

const ParamTable<TraceBlock>& trace_block_table() {
  using B = TraceBlock;
  static const auto t =
      ParamTable<B>()
          .documented("comment", "any", "", "", "", "ignored")
          .text("on_invalid", "hold", on_invalid_choices(), &B::on_invalid)
          .doc("",
               "what the methods see on a frame whose sample is flagged invalid (blink, "
               "tracking loss): the last valid gaze; the view centre; the last valid gaze, "
               "rendered by `full` until tracking returns (charged as `full` by the cost "
               "model); the last valid gaze with the foveal region widened by the time since "
               "the last valid sample. Frames with valid samples are unchanged under every "
               "policy. frames.csv gets a `tracking` column (`valid`/`held`/`lost`) when this "
               "key is given or the frames contain invalid samples. A column map's "
               "`on_invalid` is the default of a trace imported with `map`. See "
               "docs/tracking.md")
          .number("widen_per_s", 10.0, Range::closed(0, 1000), &B::widen_per_s)
          .doc("",
               "with `on_invalid: widen`: eccentricities the methods see are divided by 1 + "
               "widen_per_s x (seconds since the last valid sample), so a foveal radius r "
               "grows to r (1 + widen_per_s dt): x2 after 100 ms. Given with another policy "
               "it is an error")
          .text("on_bad_sample", "fail", {"fail", "skip", "hold"}, &B::on_bad_sample)
          .doc("",
               "a malformed sample (or, with `map`, a valid gaze outside the FOV): an error at "
               "`file:line:column`, drop it, or hold the last good one")
          .number("quat_tolerance", 1e-3, Range::above(0, 0.5), &B::quat_tolerance)
          .doc("", "unit-norm tolerance of quaternions and gaze vectors")
          .number("start", 0.0, Range::at_least(0), &B::start)
          .doc("",
               "first frame, seconds after the first sample (frame times keep the trace's "
               "own time base)")
          .number("duration", 0.0, Range::at_least(0), &B::duration)
          .doc("", "length of the frame range in seconds; 0 = to the end")
          .text("on_short", "fail", {"fail", "truncate", "hold"}, &B::on_short)
          .doc("",
               "trace shorter than start + duration: error, use what there is, or repeat the "
               "last sample")
          .boolean("resample", true, &B::resample)
          .doc("", "resample to `rate_hz`")
          .number("rate_hz", 90, Range::above(0, 10000), &B::rate_hz)
          .default_from_member("display refresh")
          .doc("", "frame rate of the result")
          .integer("max_samples", int(kDefaultMaxTraceSamples), Range::closed(1, 2e9),
                   &B::max_samples)
          .doc("",
               "most samples held after resampling. Only the range used is resampled "
               "(`start` + `duration`, or what `frames.count` needs); a range over the limit "
               "is refused before it is allocated, naming this key. The same limit bounds a "
               "synthetic trace (duration x the higher of `rate_hz` and the eye model's "
               "internal rate, counted before generating) and the samples `on_short: "
               "\"hold\"` adds")
          .text("file", nullptr, {}, &B::file)
          .optional()
          .doc("",
               "canonical CSV (or a raw recording with `map`), relative to the folder of the "
               "config that wrote it unless absolute; exactly one of `file` / `synthetic`")
          .text("map", nullptr, {}, &B::map)
          .optional()
          .read_if([](const Params& p) { return p.has("file"); })
          .doc("",
               "column map (traces/README.md): import `file` on the fly. Valid gaze outside "
               "the FOV follows `on_bad_sample`; with `duration` > 0 only the rows up to "
               "`start + duration` + 2 frame periods are read, so a problem later in the "
               "file does not stop a short run")
          .documented("synthetic", "object", "", "", "",
                      "generate the trace instead (keys: `trace.synthetic` below)");
  return t;
}

const ParamTable<SynthBlock>& synth_block_table() {
  using B = SynthBlock;
  static const auto t =
      ParamTable<B>()
          .text("scenario", nullptr, synth_scenarios(), &B::scenario)
          .required()
          .doc("", "the scenario the eye model generates (traces/README.md)")
          .number("seed", 1, Range::closed(0, kMaxSynthSeed), &B::seed)
          .shown("1", "[0, 2^53], an integer")
          .doc("",
               "same seed, identical trace; distinct seeds, distinct traces (`trace synth "
               "--seed` has the same range; 2^64 is an error, not clamped)")
          .number("duration", 10, Range::above(0, 36000), &B::duration)
          .default_from_member("trace.start + (trace.duration or 10)")
          .doc("", "generated length in seconds")
          .documented("params", "object or string", "", "", "",
                      "eye-model overrides (any subset of `models/eyemodel/default.json`), "
                      "inline or a file relative to the config; unknown keys are errors naming "
                      "their path")
          .validate([](const B& b, Params& p) {
            check_integer(p.where("seed"), b.seed, Range::closed(0, kMaxSynthSeed));
          });
  return t;
}

}  // namespace fovsim
