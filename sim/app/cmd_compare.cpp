// `fovsim compare REF TEST [--ppd P] [--json]`: PSNR, SSIM and the LDR-FLIP mean of an image
// pair. Parsing and printing only; the logic is sim/metrics/compare.cpp.
#include <cstdio>
#include <memory>

#include "sim/app/commands.h"
#include "sim/metrics/compare.h"
#include "sim/metrics/flip.h"

namespace fovsim::app {

namespace {
struct CompareArgs {
  std::string ref, test;
  double ppd = flip_default_ppd();
  bool json = false;
};
}  // namespace

void register_compare(CLI::App& app, Action& action) {
  auto a = std::make_shared<CompareArgs>();
  CLI::App* c =
      app.add_subcommand("compare", "PSNR, SSIM and LDR-FLIP mean of a reference and a test image");
  c->add_option("REF", a->ref, "Reference image (PNG, ...)")->required();
  c->add_option("TEST", a->test, "Test image, same size")->required();
  c->add_option("--ppd", a->ppd,
                "Pixels per degree for FLIP (default: FLIP's 0.7 m from a 0.7 m, 3840 px display)")
      ->capture_default_str();
  c->add_flag("--json", a->json,
              "Print one JSON object with keys psnr, ssim, flip, ppd, width, height");
  c->callback([a, &action] {
    action = [a] {
      ImageComparison r = compare_files(a->ref, a->test, a->ppd);
      const std::string s = a->json ? comparison_json(r).dump() + "\n" : comparison_text(r);
      std::fputs(s.c_str(), stdout);
      return 0;
    };
  });
}

}  // namespace fovsim::app
