#include "sim/experiment/reference_side.h"

#include "sim/core/error.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/lighting.h"

namespace fovsim {

void RefSide::begin(const Shared& sh) {
  if (ready) return;
  ready = true;
  setup.display = &sh.display;
  setup.width = sh.sim_display.width;
  setup.height = sh.sim_display.height;
  setup.fps = video ? sh.display.refresh_hz : 0.0;
  setup.config = &mcfg;
  for (auto& d : metric_registry())
    if (d.sequence && d.sequence->enabled(mcfg)) {
      Seq q;
      q.decl = &d;
      q.ref = d.sequence->make_reference(setup);
      seq.push_back(std::move(q));
    }
}

void RefSide::frame(const Shared& sh, const Renderer& renderer, const FrameData& fd,
                    const Image& ref_display, int fi, bool record, PhaseTimes& ph,
                    CellWorkspaces& pool) {
  PhaseClock pc = PhaseClock::now();
  begin(sh);
  // The true gaze (also under the latency what-if), a screen point (pixel centres at i + 0.5).
  for (auto& q : seq) q.ref->push(ref_display, fd.gaze_px.x, fd.gaze_px.y);
  if (!seq.empty()) pc = ph.lap("metrics", pc);
  if (!mcfg.foveation_loss) return;
  if (!fl_full) {
    Json j = taa.keys();  // `full` with the method's TAA (its jitter is the method's own)
    j["method"] = "full";
    Params fp(j, file, "metrics.foveation_loss");
    (void)fp.string("method");
    fl_full = make_method("full", fp);
    fp.finish();
  }
  FrameContext fctx = fd.context(*sh.scene, renderer, sh.sim_display, false);
  fctx.render_scale = sh.scale;  // as the methods' (the TAA's clamp window is in display pixels)
  fl_fo.image_is_reference = false;
  fl_fo.counters.clear();
  fl_fo.debug.clear();
  fl_fo.flags.clear();
  render_with_lighting(*fl_full, fctx, fl_fo);
  const int is_ref = fl_fo.image_is_reference ? 1 : 0;
  FOVSIM_CHECK(aliased < 0 || aliased == is_ref,
               "metrics.foveation_loss: `full` changed between being the reference and not");
  aliased = is_ref;
  if (fl_aliased()) {
    fl_ref = &ref_display;  // the same pixels as tonemap(fd.reference): no copy
  } else {
    sh.tonemap.apply(fl_fo.image, fl_display);
    fl_ref = &fl_display;
  }
  pc = ph.lap("methods", pc);
  if (!fl_aliased())
    for (auto& q : seq) {
      if (!q.ref_fl) q.ref_fl = q.decl->sequence->make_reference(setup);
      q.ref_fl->push(*fl_ref, fd.gaze_px.x, fd.gaze_px.y);
    }
  // The reference's floor: `full` at the methods' sampling rate against the reference.
  if (record) {
    const CellWorkspaces::Lease ws = pool.take();  // its reference preparation is the cells'
    MetricValues fl = compute_metrics(fl_mcfg, *fl_ref, ref_display, fd.camera, fd.eccentricity,
                                      nullptr, &ws->scratch);
    for (auto& [k, v] : fl.items()) floor_vals[k][fi] = v;
  }
  for (auto& q : seq) {
    if (!q.floor) q.floor = q.decl->sequence->make_test(*q.ref);
    // The same frame as the foveation-loss reference stream's (or the reference's, aliased):
    // its work on the frame is reused (FovVideoVDP: no second temporal window).
    const double v =
        q.floor->push_frames_of(*fl_ref, *q.ref, nullptr, ref_fl(size_t(&q - seq.data())));
    if (record) floor_vals[q.decl->pooled_column][fi] = v;
  }
  ph.lap("metrics", pc);
}

void RefSide::reset() {
  for (auto& q : seq) {
    q.ref->reset();
    if (q.ref_fl) q.ref_fl->reset();
    if (q.floor) q.floor->reset();
  }
  if (fl_full) fl_full->restart();
}

}  // namespace fovsim
