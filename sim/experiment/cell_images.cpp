#include "sim/experiment/cell_images.h"

#include <tbb/parallel_for.h>

#include <cmath>

#include "sim/core/files.h"
#include "sim/experiment/cell.h"
#include "sim/metrics/frame_metric.h"

namespace fovsim {

void ImageJobs::write_all() {
  tbb::parallel_for(size_t(0), jobs.size(),
                    [&](size_t i) { write_image(jobs[i].first, jobs[i].second); });
  jobs.clear();
}

void write_images(const std::string& dir, const std::string& stem, const Image& display_img,
                  const Image* linear, const ImageOutputs& io, ImageJobs& q) {
  if (io.png) q.add(dir + "/" + safe_file_name(stem) + ".png", display_img);
  if (io.exr && linear) q.add(dir + "/" + safe_file_name(stem) + ".exr", *linear);
}

Image error_heatmap(const Image& a, const Image& b) {
  Image e(a.width, a.height, 1);
  for (size_t i = 0; i < a.pixels(); ++i) {
    const float* p = &a.data[3 * i];
    const float* q = &b.data[3 * i];
    e.data[i] = std::fabs(luma(p[0], p[1], p[2]) - luma(q[0], q[1], q[2]));
  }
  return heatmap(e, 0.f, 0.25f);  // |luma error| 0 .. 0.25 mapped to the colour ramp
}

void Cell::queue_method_images(const FrameIn& in, MethodRun& m, const Image& lin,
                               std::vector<std::pair<std::string, Image>>& heat) {
  write_images(in.img_dir, m.stem, in.ws.out_display, &lin, images.io, images.jobs);
  if (outputs.error_images)
    images.jobs.add(in.img_dir + "/" + safe_file_name(m.stem + "_error") + ".png",
                    error_heatmap(in.ws.out_display, in.ref_display));
  for (auto& [suffix, img] : frame_metric_images(metric.cfg, in.ws.scratch))  // e.g. FLIP's map
    images.jobs.add(in.img_dir + "/" + safe_file_name(m.stem + suffix) + ".png", std::move(img));
  for (auto& [name, img] : heat)
    images.jobs.add(in.img_dir + "/" + safe_file_name(name) + ".png", std::move(img));
  for (auto& [dname, dimg] : m.fo.debug)
    images.jobs.add(in.img_dir + "/" + safe_file_name(m.stem + "_" + dname) + ".png",
                    std::move(dimg));
}

}  // namespace fovsim
