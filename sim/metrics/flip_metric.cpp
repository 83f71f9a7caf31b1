// `flip` (frame_metric.h): the mean of the LDR-FLIP map (Andersson et al. 2020, flip.cpp) at
// flip_ppd(cam); with `regions` also flip_ecc_<a>_<b>, the mean FLIP error over
// a <= ecc < b (NaN for an empty region). Its map of a saved frame is `<label>_flip.png`
// (`flip_images`).
#include "sim/metrics/flip_metric.h"

#include <algorithm>
#include <limits>
#include <string>

#include "sim/core/error.h"

namespace fovsim {

namespace {

size_t flip_index() {
  static const size_t i = [] {
    const auto& ms = frame_metrics();
    for (size_t k = 0; k < ms.size(); ++k)
      if (std::string(ms[k].name) == "flip") return k;
    return ms.size();
  }();
  return i;
}

void compute(const FrameMetricArgs& a, MetricValues& out) {
  const MetricsConfig& cfg = a.cfg;
  const Image& test = a.test;
  FlipScratch& sc = *static_cast<FlipScratch*>(a.scratch);
  const FlipScratch* given = static_cast<const FlipScratch*>(a.same_test);
  const FlipPrepared* test_flip = given && given->test_valid ? &given->test : nullptr;
  const double ppd = flip_ppd(a.cam);
  if (sc.ref.ppd != ppd) flip_prepare(a.ref, ppd, sc.ref, &sc.workspace);
  const Image& map = sc.map;
  if (a.identical) {
    // Identical images: every FLIP term is a difference of equal values, so E = 0 exactly
    // (FLIP.md §10.1); skip the work (the `full` method of every run).
    sc.map.resize(test.width, test.height, 1, 0.f);
    out.set("flip", 0.0);
  } else if (test_flip) {
    FOVSIM_CHECK(test_flip->ppd == ppd, "compute_metrics: the given test FLIP preparation is at " +
                                            std::to_string(test_flip->ppd) + " ppd, not " +
                                            std::to_string(ppd));
    out.set("flip", flip(sc.ref, *test_flip, &sc.map));
  } else {
    flip_prepare(test, ppd, sc.test, &sc.workspace);
    sc.test_valid = true;
    out.set("flip", flip(sc.ref, sc.test, &sc.map));
  }
  const size_t nb = cfg.band_edges_deg.size() >= 2 ? cfg.band_edges_deg.size() - 1 : 0;
  if (cfg.on("regions") && nb > 0) {
    // Serial pass in pixel order (deterministic); the map is one float per pixel.
    std::vector<double> sum(nb, 0.0), n(nb, 0.0);
    const double* edges = cfg.band_edges_deg.data();
    for (size_t i = 0; i < map.pixels(); ++i) {
      const double e = a.ecc[i];
      if (e < edges[0] || !(e < edges[nb])) continue;
      const size_t k = size_t(std::upper_bound(edges, edges + nb + 1, e) - edges) - 1;
      sum[k] += map.data[i];
      n[k] += 1;
    }
    for (size_t k = 0; k < nb; ++k)
      out.set(flip_band_column(edges[k], edges[k + 1]),
              n[k] > 0 ? sum[k] / n[k] : std::numeric_limits<double>::quiet_NaN());
  }
}

}  // namespace

const FlipScratch* flip_scratch(const MetricsScratch& s) {
  const size_t i = flip_index();
  return i < s.per_metric.size() ? static_cast<const FlipScratch*>(s.per_metric[i].get()) : nullptr;
}

const FrameMetric& flip_frame_metric() {
  static const FrameMetric m = [] {
    FrameMetric d;
    d.name = "flip";
    d.toggle = {"flip", true, "Andersson et al. 2020",
                "write `flip`, with `regions` also `flip_ecc_*`"};
    d.columns = [](const MetricsConfig& cfg) {
      std::vector<std::string> c{"flip"};
      if (cfg.on("regions"))
        for (size_t k = 0; k + 1 < cfg.band_edges_deg.size(); ++k)
          c.push_back(flip_band_column(cfg.band_edges_deg[k], cfg.band_edges_deg[k + 1]));
      return c;
    };
    d.needs_camera = true;
    d.make_scratch = []() -> std::unique_ptr<FrameMetricScratch> {
      return std::make_unique<FlipScratch>();
    };
    d.prepares_reference = true;
    // Its preparations of both images (each five planes of doubles and more): six RGB images.
    d.scratch_bytes = [](double pixels) { return 6 * 12 * pixels; };
    d.compute = compute;
    d.image_suffix = "_flip";
    d.image_toggle = {
        "flip_images", true, "",
        "with `flip`: write `<label>_flip.png` (the FLIP error map) for image frames"};
    d.image = [](const FrameMetricScratch& s) {
      return flip_colormap(static_cast<const FlipScratch&>(s).map);
    };
    return d;
  }();
  return m;
}

}  // namespace fovsim
