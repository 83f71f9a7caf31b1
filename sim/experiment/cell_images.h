// A cell's images of its saved frames (outputs.image_frames; results/README.md "Images"): which
// frames and formats, and the queue of one frame's images, written together at the end of the
// frame. Cell::queue_method_images (cell_images.cpp) queues a method's.
#pragma once
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/image.h"

namespace fovsim {

struct ImageOutputs {
  std::set<int> frames;
  bool png = true, exr = false, debug = false;
};

// The images of one frame, queued while the methods run and written together at the end of
// the frame (write_all), in parallel: PNG compression is ~20 ms per image at the quickstart's
// resolution and ran serially on the frame-loop thread (bench/README.md "Scaling"). Each job
// owns a copy of its image, since the cell's display buffer is reused by the next method.
// Which file each image goes to does not depend on the order the jobs run in.
struct ImageJobs {
  std::vector<std::pair<std::string, Image>> jobs;
  void add(std::string path, Image img) { jobs.emplace_back(std::move(path), std::move(img)); }
  void write_all();
};

// What a cell writes of its saved frames: the choice, this frame's queue and the memoised
// methods' files of this frame (path, stored bytes), written after the queue.
struct CellImages {
  ImageOutputs io;
  ImageJobs jobs;
  std::vector<std::pair<std::string, const std::string*>> memo_files;
};

// `stem`.png (display values) and, with outputs.exr, `stem`.exr (linear) in `dir`.
void write_images(const std::string& dir, const std::string& stem, const Image& display_img,
                  const Image* linear, const ImageOutputs& io, ImageJobs& q);

// |luma(a) - luma(b)| on the colour ramp, 0 .. 0.25 (outputs.error_images).
Image error_heatmap(const Image& a, const Image& b);

}  // namespace fovsim
