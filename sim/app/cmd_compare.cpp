// `fovsim compare REF TEST [--ppd P] [--json]`: PSNR, SSIM and the LDR-FLIP mean of an image
// pair; with --fvvdp, FovVideoVDP (Mantiuk et al. 2021) of an image pair or two PNG sequences.
// Parsing and printing only; the logic is sim/metrics/compare.cpp.
#include <cstdio>
#include <memory>
#include <tuple>

#include "sim/app/commands.h"
#include "sim/core/error.h"
#include "sim/experiment/config.h"
#include "sim/metrics/compare.h"
#include "sim/metrics/flip.h"

namespace fovsim::app {

namespace {
struct CompareArgs {
  std::string ref, test;
  double ppd = flip_default_ppd();
  bool json = false;
  bool fvvdp = false, foveated = false;
  std::string display, gaze;
  double fps = 0;
  int torch_threads = kFvvdpTorchThreads;
};
}  // namespace

void register_compare(CLI::App& app, Action& action) {
  auto a = std::make_shared<CompareArgs>();
  CLI::App* c =
      app.add_subcommand("compare", "PSNR, SSIM and LDR-FLIP mean of a reference and a test image");
  c->add_option("REF", a->ref,
                "Reference image (PNG, ...); with --fvvdp also a folder of PNG frames")
      ->required();
  c->add_option("TEST", a->test, "Test image (or folder), same size (and frame count)")->required();
  add_number(c, "--ppd", a->ppd,
             "Pixels per degree for FLIP (default: FLIP's 0.7 m from a 0.7 m, 3840 px display)",
             {flip_ppd_range(), "px/deg"})
      ->capture_default_str();
  c->add_flag("--json", a->json,
              "Print one JSON object with keys psnr, ssim, flip, ppd, width, height");
  c->add_flag("--fvvdp", a->fvvdp,
              "FovVideoVDP v1.2 (JOD, 10 = no visible difference) instead of PSNR/SSIM/FLIP");
  c->add_option("--display", a->display,
                "With --fvvdp: display name (models/displays/, e.g. standard_4k) or path");
  c->add_option("--gaze", a->gaze,
                "With --fvvdp: gaze X,Y in pixels from the top-left (implies --foveated)");
  add_number(c, "--fps", a->fps, "With --fvvdp: frame rate of PNG sequences",
             {fvvdp_fps_range(), "Hz"});
  add_number(
      c, "--torch-threads", a->torch_threads,
      "With --fvvdp: sum each band's pooling (spec section 10) in float32 as the reference's "
      "torch.norm does on a CPU with N intra-op threads (1: the reference on one thread)",
      {Range::closed(1, 1024), "threads", true, "sum in double"})
      ->capture_default_str();
  c->add_flag("--foveated", a->foveated,
              "With --fvvdp: foveated mode (gaze at the image centre unless --gaze)");
  c->callback([a, &action] {
    action = [a] {
      if (a->fvvdp) {
        FvvdpCompareOptions o;
        o.display = a->display;
        o.models_dir = default_models_dir();
        o.fps = a->fps;
        o.foveated = a->foveated;
        o.torch_threads = a->torch_threads;
        if (!a->gaze.empty()) {
          std::tie(o.gaze_x, o.gaze_y) = parse_gaze(a->gaze);
          o.has_gaze = true;
        }
        FvvdpComparison r = compare_fvvdp(a->ref, a->test, o);
        const std::string s =
            a->json ? fvvdp_comparison_json(r).dump() + "\n" : fvvdp_comparison_text(r);
        std::fputs(s.c_str(), stdout);
        return 0;
      }
      if (!a->display.empty() || !a->gaze.empty() || a->fps != 0 || a->foveated)
        throw Error("compare", "--display, --gaze, --fps and --foveated need --fvvdp");
      ImageComparison r = compare_files(a->ref, a->test, a->ppd);
      const std::string s = a->json ? comparison_json(r).dump() + "\n" : comparison_text(r);
      std::fputs(s.c_str(), stdout);
      return 0;
    };
  });
}

}  // namespace fovsim::app
