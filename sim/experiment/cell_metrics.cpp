#include <cstdint>

#include "sim/experiment/cell.h"
#include "sim/experiment/reference_side.h"
#include "sim/metrics/frame_metric.h"

namespace fovsim {

MetricValues Cell::measure(const FrameIn& in, MethodRun& m,
                           std::vector<std::pair<std::string, Image>>& heat) {
  const FrameData& fd = in.fd;
  const Image& out_display = in.ws.out_display;
  const MetricValues image_metrics =
      compute_metrics(metric.cfg, out_display, in.ref_display, fd.camera, fd.eccentricity,
                      &m.streams.temporal, &in.ws.scratch);
  MetricValues metrics = image_metrics;
  const RefSide& side = *m.side;  // the cell's metrics with this method's TAA (foveation loss)
  const std::vector<RefSide::Seq>& seq = side.seq;
  std::vector<double> seq_q(seq.size());
  std::vector<size_t> seq_heat(seq.size(), SIZE_MAX);  // index into `heat`
  for (size_t k = 0; k < seq.size(); ++k) {
    const MetricDecl& d = *seq[k].decl;
    if (m.streams.seq.size() <= k) m.streams.seq.push_back(d.sequence->make_test(*seq[k].ref));
    const bool h = in.want_images && *d.sequence->heatmap_suffix;
    Image img;
    const double q = m.streams.seq[k]->push(out_display, *seq[k].ref, h ? &img : nullptr);
    seq_q[k] = q;
    metrics.set(d.pooled_column, q);
    metrics.set(d.name, d.from_mean(q));
    if (h) {
      seq_heat[k] = heat.size();
      heat.emplace_back(m.stem + d.sequence->heatmap_suffix, std::move(img));
    }
  }
  if (metric.cfg.foveation_loss) {  // every metric against full at the same sampling rate
    if (side.fl_aliased()) {
      // The foveation-loss reference is the reference: the values above, but for
      // the metrics measured against the reference only (temporal_error; fl_mcfg has them off).
      for (auto& [k, v] : image_metrics.items())
        if (!is_reference_only_column(metric.cfg, k)) metrics.set(k + kFoveationLossSuffix, v);
    } else {
      // The same test image: the metrics may reuse their preparations of it from the call above.
      MetricValues fl =
          compute_metrics(side.fl_mcfg, out_display, *side.fl_ref, fd.camera, fd.eccentricity,
                          &m.streams.temporal_fl, &in.ws.fl_scratch, &in.ws.scratch);
      for (auto& [k, v] : fl.items()) metrics.set(k + kFoveationLossSuffix, v);
    }
    for (size_t k = 0; k < seq.size(); ++k) {
      const MetricDecl& d = *seq[k].decl;
      const bool h = in.want_images && *d.sequence->heatmap_suffix;
      Image img;
      double q = seq_q[k];
      if (side.fl_aliased()) {
        // The foveation-loss reference is the reference: the same test against the same
        // frames (no second test stream per method).
        if (h) img = heat[seq_heat[k]].second;
      } else {
        if (m.streams.seq_fl.size() <= k)
          m.streams.seq_fl.push_back(d.sequence->make_test(side.ref_fl(k)));
        // The same test frame as m.streams.seq[k]'s push above: its work on the frame is reused.
        q = m.streams.seq_fl[k]->push_same(out_display, side.ref_fl(k), h ? &img : nullptr,
                                           *m.streams.seq[k], *seq[k].ref);
      }
      metrics.set(d.pooled_column + kFoveationLossSuffix, q);
      metrics.set(d.name + kFoveationLossSuffix, d.from_mean(q));
      if (h)
        heat.emplace_back(m.stem + d.sequence->heatmap_suffix + kFoveationLossSuffix,
                          std::move(img));
    }
  }
  for (auto& f : m.fo.flags) flags_seen.insert(m.label + ":" + f);
  latency.note(metrics);
  return metrics;
}

}  // namespace fovsim
