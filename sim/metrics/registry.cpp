#include "sim/metrics/registry.h"

#include <cmath>

#include "sim/metrics/frame_metric.h"
#include "sim/metrics/fvvdp.h"

namespace fovsim {

namespace {

using Tol = MetricDecl::Tol;

MetricDecl frame_metric(std::string name, std::string unit, std::string label, Better better,
                        bool headline, Tol tol, int precision, std::string cite, std::string doc) {
  MetricDecl d;
  d.name = std::move(name);
  d.unit = std::move(unit);
  d.label = std::move(label);
  d.better = better;
  d.headline = headline;
  d.convergence_tol = tol;
  d.precision = precision;
  d.cite = std::move(cite);
  d.doc = std::move(doc);
  return d;
}

std::vector<MetricDecl> make_registry() {
  std::vector<MetricDecl> r;
  r.push_back(frame_metric("psnr", "dB", "PSNR [dB]", Better::higher, true, Tol::db, 3, "",
                           "10 log10(1 / MSE) over all pixels and channels"));
  r.push_back(frame_metric("fpsnr", "dB", "FPSNR [dB]", Better::higher, true, Tol::db, 3,
                           "Lee, Pattichis and Bovik 2002",
                           "foveated PSNR: squared error weighted by the eccentricity-dependent "
                           "cutoff frequency"));
  r.back().show_fl = true;
  r.push_back(frame_metric("ssim", "1", "SSIM [0-1]", Better::higher, true, Tol::none, 4,
                           "Wang et al. 2004", "structural similarity of Rec.709 luma"));
  r.push_back(frame_metric("flip", "1", "LDR-FLIP [0-1, lower is better]", Better::lower, true,
                           Tol::unit, 4, "Andersson et al. 2020", "mean LDR-FLIP error"));
  // FovVideoVDP: the perceptual, foveated, temporal quality axis (docs/metrics.md).
  {
    MetricDecl d = frame_metric(
        "fvvdp_jod", "JOD", "FovVideoVDP [JOD, 10 = no visible difference]", Better::higher, true,
        Tol::jod, 4, "Mantiuk et al. 2021 (FovVideoVDP v1.2)",
        "just-objectionable differences of the whole sequence, foveated around the true gaze");
    d.pooling = Pooling::sequence;
    d.pooled_column = "fvvdp_q";
    d.from_mean = &fvvdp_jod_from_q;
    d.sequence = &fvvdp_sequence_metric();
    d.show_fl = true;
    r.push_back(d);
  }
  r.push_back(frame_metric("rmse_fovea", "1", "RMSE in the fovea [0-1]", Better::lower, false,
                           Tol::none, 4, "", "RMSE over the pixels within metrics.fovea_deg"));
  r.back().paired = true;  // the latency what-if's metric (docs/latency.md)
  r.push_back(frame_metric("rmse_periphery", "1", "RMSE in the periphery [0-1]", Better::lower,
                           false, Tol::none, 4, "", "RMSE over the pixels beyond fovea_deg"));
  r.back().paired = true;
  {
    MetricDecl d =
        frame_metric("rmse_ecc_", "1", "RMSE in an eccentricity band [0-1]", Better::lower, false,
                     Tol::none, 4, "", "RMSE over the pixels of band [a, b) degrees");
    d.family = true;
    r.push_back(d);
  }
  {
    MetricDecl d = frame_metric("flip_ecc_", "1", "LDR-FLIP in an eccentricity band [0-1]",
                                Better::lower, false, Tol::none, 4, "Andersson et al. 2020",
                                "mean FLIP error over the pixels of band [a, b) degrees");
    d.family = true;
    r.push_back(d);
  }
  r.push_back(frame_metric("temporal_error", "1", "temporal error [luma RMS]", Better::lower, false,
                           Tol::none, 4, "",
                           "RMS frame-to-frame change of the error in the periphery"));
  return r;
}

const char* better_name(Better b) {
  return b == Better::higher ? "higher" : "lower";
}

const char* tol_name(Tol t) {
  switch (t) {
    case Tol::db:
      return "db";
    case Tol::unit:
      return "unit";
    case Tol::jod:
      return "jod";
    default:
      return "none";
  }
}

}  // namespace

// The per-frame metrics (frame_metric.h), one file each; their order is the order of their
// columns in frames.csv.
const FrameMetric& psnr_frame_metric();
const FrameMetric& ssim_frame_metric();
const FrameMetric& fpsnr_frame_metric();
const FrameMetric& region_rmse_frame_metric();
const FrameMetric& flip_frame_metric();
const FrameMetric& temporal_frame_metric();

const std::vector<FrameMetric>& frame_metrics() {
  static const std::vector<FrameMetric> m = {psnr_frame_metric(),  ssim_frame_metric(),
                                             fpsnr_frame_metric(), region_rmse_frame_metric(),
                                             flip_frame_metric(),  temporal_frame_metric()};
  return m;
}

const std::vector<MetricDecl>& metric_registry() {
  static const std::vector<MetricDecl> r = make_registry();
  return r;
}

namespace {
const MetricDecl* find_exact(const std::string& column) {
  for (auto& d : metric_registry()) {
    if (d.family ? column.size() > d.name.size() && column.compare(0, d.name.size(), d.name) == 0
                 : column == d.name)
      return &d;
    if (d.pooling == Pooling::sequence && column == d.pooled_column) return &d;
  }
  return nullptr;
}

bool ends_fl(const std::string& c) {
  const std::string suf = kFoveationLossSuffix;
  return c.size() > suf.size() && c.compare(c.size() - suf.size(), suf.size(), suf) == 0;
}
}  // namespace

const MetricDecl* find_metric(const std::string& column) {
  if (const MetricDecl* d = find_exact(column)) return d;
  if (ends_fl(column))
    return find_exact(column.substr(0, column.size() - std::string(kFoveationLossSuffix).size()));
  return nullptr;
}

bool is_foveation_loss_column(const std::string& column) {
  return ends_fl(column) && !find_exact(column) && find_metric(column);
}

std::vector<std::string> headline_metric_names(bool with_fl) {
  std::vector<std::string> out;
  for (auto& d : metric_registry())
    if (d.headline) out.push_back(d.name);
  if (with_fl)
    for (auto& d : metric_registry())
      if (d.headline && d.show_fl) out.push_back(d.name + kFoveationLossSuffix);
  return out;
}

std::vector<std::string> paired_metric_names() {
  std::vector<std::string> out = headline_metric_names(true);
  for (auto& d : metric_registry())
    if (d.paired && !d.headline) {
      out.push_back(d.name);
      out.push_back(d.name + kFoveationLossSuffix);
    }
  return out;
}

bool higher_is_better(const std::string& column) {
  const MetricDecl* d = find_metric(column);
  if (!d) return false;
  // The pooled column of a sequence metric runs the other way round when its map decreases
  // (FovVideoVDP's Q: larger Q, lower JOD).
  const std::string base =
      is_foveation_loss_column(column)
          ? column.substr(0, column.size() - std::string(kFoveationLossSuffix).size())
          : column;
  if (d->pooling == Pooling::sequence && base == d->pooled_column)
    return d->from_mean && d->from_mean(1.0) > d->from_mean(2.0) ? d->better == Better::lower
                                                                 : d->better == Better::higher;
  return d->better == Better::higher;
}

Json metric_registry_json() {
  Json a = Json::array();
  for (auto& d : metric_registry()) {
    Json j;
    j["name"] = d.name;
    j["family"] = d.family;
    j["unit"] = d.unit;
    j["label"] = d.label;
    j["better"] = better_name(d.better);
    j["pooling"] = d.pooling == Pooling::sequence ? "sequence" : "frame_mean";
    j["pooled_column"] = d.pooled_column;
    j["headline"] = d.headline;
    j["paired"] = d.paired;
    j["show_fl"] = d.show_fl;
    j["convergence_tol"] = tol_name(d.convergence_tol);
    j["precision"] = d.precision;
    j["cite"] = d.cite;
    j["doc"] = d.doc;
    a.push_back(j);
  }
  return a;
}

}  // namespace fovsim
