// `fovsim compare` logic: load an image pair as the FLIP reference tool does, then PSNR, SSIM
// and the LDR-FLIP mean (docs/metrics.md, "fovsim compare").
#include "sim/metrics/compare.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <vector>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/params.h"
#include "sim/metrics/flip.h"
#include "sim/metrics/metrics.h"

namespace fovsim {

namespace {

// The header of an image file: its size, checked against max_image_pixels before anything is
// allocated (files.h). `in` is left open for the decoder.
struct ImageHeader {
  int width = 0, height = 0, channels = 0;
};

std::unique_ptr<OIIO::ImageInput> open_image(const std::string& path, ImageHeader& h) {
  if (!std::filesystem::exists(path)) throw Error(path, "no such file");
  check_input_file(path);  // a FIFO or /dev/zero is refused before the decoder blocks on it
  QuietStderr quiet;       // libpng's own error line: the thrown error says it once
  // Raw colour values: OpenImageIO premultiplies PNG colour by alpha unless asked not to; the
  // FLIP tool drops alpha without compositing.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) throw Error(path, "cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  h = {spec.width, spec.height, spec.nchannels};
  if (h.width <= 0 || h.height <= 0 || h.channels <= 0) throw Error(path, "empty image");
  const double max_px = max_image_pixels(), px = double(h.width) * double(h.height);
  if (px > max_px || h.channels > 16) {
    char b[200];
    std::snprintf(b, sizeof b, " (%.0f pixels), over the limit of %.0f pixels (%.0f Mpx", px,
                  max_px, max_px / 1048576.0);
    throw Error(path, "image header claims " + std::to_string(h.width) + "x" +
                          std::to_string(h.height) + "x" + std::to_string(h.channels) + b +
                          ": comparing a pair takes about " +
                          std::to_string(int(kCompareBytesPerPixel)) +
                          " bytes per pixel; set FOVSIM_MAX_IMAGE_MPIXELS to raise it)");
  }
  return in;
}

// `fvvdp`: FovVideoVDP's decoding (FovVideoVDP.md §1): 16-bit values v / 65535, grey kept as one
// channel; otherwise the FLIP tool's (above). Decoded straight into the output image (one
// file-sized buffer beside it, no float copy of the file).
Image read_display_encoded(const std::string& path, bool fvvdp) {
  ImageHeader hd;
  auto in = open_image(path, hd);
  QuietStderr quiet;
  const int W = hd.width, H = hd.height, C = hd.channels;
  const size_t n = size_t(W) * size_t(H) * size_t(C);
  const bool grey = fvvdp && C < 3;
  Image out(W, H, grey ? 1 : 3);
  // Pixel i of the file (C values at `p`) into the output: grey kept (FovVideoVDP) or copied
  // to RGB, alpha and extra channels dropped.
  auto put = [&](size_t i, auto&& value_of) {
    float* o = &out.data[i * size_t(out.channels)];
    const size_t b = i * size_t(C);
    if (grey) {
      o[0] = value_of(b);
      return;
    }
    for (int c = 0; c < 3; ++c) o[c] = value_of(b + size_t(C >= 3 ? c : 0));
  };
  const auto base = in->spec().format.basetype;
  if (base == OIIO::TypeDesc::UINT8 || base == OIIO::TypeDesc::UINT16) {
    // Integer files: exact bytes, then byte / 255 as the reference tool (stb_image) does.
    std::vector<uint16_t> raw(n);
    if (!in->read_image(0, 0, 0, C, OIIO::TypeDesc::UINT16, raw.data()))
      throw Error(path, "cannot decode image: " + in->geterror());
    const bool wide = base == OIIO::TypeDesc::UINT16;
    auto value = [&](size_t k) {
      // UINT8 read as UINT16 is v * 257; either way the high byte is the 8-bit value.
      if (fvvdp && wide) return float(raw[k]) / 65535.0f;
      const unsigned byte = wide ? unsigned(raw[k]) >> 8 : unsigned(raw[k]) / 257u;
      return float(byte) / 255.0f;
    };
    for (size_t i = 0; i < out.pixels(); ++i) put(i, value);
  } else {
    std::vector<float> v(n);
    if (!in->read_image(0, 0, 0, C, OIIO::TypeDesc::FLOAT, v.data()))
      throw Error(path, "cannot decode image: " + in->geterror());
    for (size_t i = 0; i < out.pixels(); ++i) put(i, [&](size_t k) { return v[k]; });
  }
  in->close();
  return out;
}

}  // namespace

// Out of memory while decoding names the image and the limit that sizes it.
Image read_ldr_rgb(const std::string& path) {
  return with_memory_context(path, "decoding the image", "lower FOVSIM_MAX_IMAGE_MPIXELS",
                             [&] { return read_display_encoded(path, false); });
}
Image read_fvvdp_image(const std::string& path) {
  return with_memory_context(path, "decoding the image", "lower FOVSIM_MAX_IMAGE_MPIXELS",
                             [&] { return read_display_encoded(path, true); });
}

ImageComparison compare_images(const Image& ref, const Image& test, double ppd,
                               const std::string& ref_name, const std::string& test_name) {
  if (ref.width != test.width || ref.height != test.height)
    throw Error("compare", "images differ in size: " + ref_name + " is " +
                               std::to_string(ref.width) + "x" + std::to_string(ref.height) + ", " +
                               test_name + " is " + std::to_string(test.width) + "x" +
                               std::to_string(test.height));
  check_flip_ppd(ppd, ref.width, ref.height, "--ppd");
  ImageComparison c;
  c.width = ref.width;
  c.height = ref.height;
  c.ppd = ppd;
  c.psnr = psnr(test, ref);
  c.ssim = (ref.width >= 11 && ref.height >= 11) ? ssim(test, ref) : std::nan("");
  c.flip = flip(ref, test, ppd);
  return c;
}

ImageComparison compare_files(const std::string& ref_path, const std::string& test_path,
                              double ppd) {
  // Both headers first: an oversized or mismatched TEST is refused before REF is decoded.
  ImageHeader hr, ht;
  open_image(ref_path, hr)->close();
  open_image(test_path, ht)->close();
  if (hr.width != ht.width || hr.height != ht.height)
    throw Error("compare", "images differ in size: " + ref_path + " is " +
                               std::to_string(hr.width) + "x" + std::to_string(hr.height) + ", " +
                               test_path + " is " + std::to_string(ht.width) + "x" +
                               std::to_string(ht.height));
  Image ref = read_ldr_rgb(ref_path), test = read_ldr_rgb(test_path);
  return compare_images(ref, test, ppd, ref_path, test_path);
}

Json comparison_json(const ImageComparison& c) {
  Json j;
  j["psnr"] = std::isinf(c.psnr) ? Json("inf") : Json(c.psnr);
  j["ssim"] = std::isnan(c.ssim) ? Json(nullptr) : Json(c.ssim);
  j["flip"] = c.flip;
  j["ppd"] = c.ppd;
  j["width"] = c.width;
  j["height"] = c.height;
  return j;
}

std::string comparison_text(const ImageComparison& c) {
  char buf[256];
  std::string psnr = std::isinf(c.psnr) ? "inf" : std::to_string(c.psnr);
  std::snprintf(buf, sizeof buf, "%.6f", c.psnr);
  if (!std::isinf(c.psnr)) psnr = buf;
  std::string ssim = "n/a (image smaller than 11x11)";
  if (!std::isnan(c.ssim)) {
    std::snprintf(buf, sizeof buf, "%.6f", c.ssim);
    ssim = buf;
  }
  std::snprintf(buf, sizeof buf, "%dx%d, ppd %.4f\n", c.width, c.height, c.ppd);
  std::string out = std::string("images  ") + buf;
  out += "psnr    " + psnr + " dB\n";
  out += "ssim    " + ssim + "\n";
  std::snprintf(buf, sizeof buf, "flip    %.6f\n", c.flip);
  out += buf;
  return out;
}

// ---------------------------------------------------------------------------------------------
// FovVideoVDP (Mantiuk et al. 2021).

std::vector<std::string> frame_files(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (path_kind(path) == PathKind::missing) throw Error(path, "no such file or folder");
  if (!fs::is_directory(path, ec)) return {path};
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(path, ec)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (e.is_regular_file() && ext == ".png") files.push_back(e.path().string());
  }
  if (files.empty()) throw Error(path, "folder has no PNG frames");
  std::sort(files.begin(), files.end());
  return files;
}

Range fvvdp_fps_range() {
  return Range::above(4, 1e4);
}

std::pair<double, double> parse_gaze(const std::string& s) {
  // "X,Y": each a number, then the one numeric check of every flag (params.h check_number:
  // NaN and infinities are refused there, as for --ppd and --fps).
  const size_t comma = s.find(',');
  double v[2] = {0, 0};
  bool ok = comma != std::string::npos;
  for (int i = 0; ok && i < 2; ++i) {
    const std::string part = i == 0 ? s.substr(0, comma) : s.substr(comma + 1);
    char* end = nullptr;
    v[i] = std::strtod(part.c_str(), &end);
    ok = !part.empty() && end == part.c_str() + part.size();
  }
  if (!ok)
    throw Error("--gaze", "expected X,Y in pixels from the top-left (e.g. 640,360), got '" +
                              escape_control(s, 60) + "'");
  for (int i = 0; i < 2; ++i) check_number(i == 0 ? "--gaze X" : "--gaze Y", v[i], Range::any());
  return {v[0], v[1]};
}

std::vector<std::string> display_names(const std::string& models_dir) {
  namespace fs = std::filesystem;
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(models_dir + "/displays", ec))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

FvvdpComparison compare_fvvdp(const std::string& ref_path, const std::string& test_path,
                              const FvvdpCompareOptions& opt) {
  FvvdpComparison c;
  const std::string& dn = opt.display;
  const bool is_path = dn.find('/') != std::string::npos || dn.find(".json") != std::string::npos;
  if (dn.empty() ||
      (!is_path && !std::filesystem::exists(opt.models_dir + "/displays/" + dn + ".json"))) {
    std::string list;
    for (const auto& n : display_names(opt.models_dir)) list += (list.empty() ? "" : ", ") + n;
    throw Error("--display", (dn.empty() ? std::string("FovVideoVDP needs a display")
                                         : "unknown display '" + dn + "'") +
                                 " (available: " + list + ")");
  }
  c.display = FvvdpDisplay::from_display(Display::load(dn, opt.models_dir));
  const std::vector<std::string> rf = frame_files(ref_path), tf = frame_files(test_path);
  if (rf.size() != tf.size())
    throw Error("compare", ref_path + " has " + std::to_string(rf.size()) + " frames, " +
                               test_path + " has " + std::to_string(tf.size()));
  const size_t N = rf.size();
  if (N >= 2 && opt.fps == 0)
    throw Error("--fps", "a sequence of " + std::to_string(N) +
                             " frames needs its frame rate: --fps F (Hz, > 4)");
  if (N >= 2) check_number("--fps", opt.fps, fvvdp_fps_range());
  if (N >= 2 && fvvdp_detail::filter_length(opt.fps) < 2) {
    char b[64];
    std::snprintf(b, sizeof b, "frame rate must be > 4 Hz, got %.6g", opt.fps);
    throw Error("--fps", b);
  }
  std::vector<Image> ref, test;
  for (size_t i = 0; i < N; ++i) {
    ref.push_back(read_fvvdp_image(rf[i]));
    test.push_back(read_fvvdp_image(tf[i]));
    const Image &r = ref.back(), &t = test.back(), &r0 = ref.front();
    for (const auto* im : {&r, &t}) {
      if (im->width != r0.width || im->height != r0.height) {
        const std::string& f = im == &r ? rf[i] : tf[i];
        throw Error(f, "frame is " + std::to_string(im->width) + "x" + std::to_string(im->height) +
                           ", " + rf[0] + " is " + std::to_string(r0.width) + "x" +
                           std::to_string(r0.height) + " (every frame must have the same size)");
      }
    }
    if (r.channels != t.channels) {
      // Mixed grey and RGB: use RGB for both (grey copied to three channels).
      for (Image* im : {&ref.back(), &test.back()})
        if (im->channels == 1) {
          Image rgb(im->width, im->height, 3);
          for (size_t k = 0; k < im->pixels(); ++k)
            for (int ch = 0; ch < 3; ++ch) rgb.data[3 * k + size_t(ch)] = im->data[k];
          *im = std::move(rgb);
        }
    }
  }
  c.width = ref[0].width;
  c.height = ref[0].height;
  if (c.width < 4 || c.height < 4)
    throw Error(rf[0], "image is " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                           ", FovVideoVDP needs at least 4x4 pixels");
  c.frames = int(N);
  c.fps = N >= 2 ? opt.fps : 0.0;
  c.foveated = opt.foveated || opt.has_gaze;
  c.gaze_x = opt.has_gaze ? opt.gaze_x : std::floor(c.width / 2);
  c.gaze_y = opt.has_gaze ? opt.gaze_y : std::floor(c.height / 2);
  c.torch_threads = opt.torch_threads;
  c.result =
      fvvdp(test, ref, c.display, c.fps, c.foveated, {{c.gaze_x, c.gaze_y}}, opt.torch_threads);
  return c;
}

Json fvvdp_comparison_json(const FvvdpComparison& c) {
  const FvvdpResult& r = c.result;
  Json j;
  j["fvvdp_jod"] = r.jod;
  j["q"] = r.mean_q;
  j["display"] = r.display_line;
  j["display_name"] = c.display.name;
  j["ppd"] = c.display.ppd;
  j["y_peak"] = c.display.y_peak;
  j["y_black"] = c.display.y_black;
  j["foveated"] = c.foveated;
  j["torch_threads"] = c.torch_threads;
  j["gaze"] = c.foveated ? Json::array({c.gaze_x, c.gaze_y}) : Json(nullptr);
  j["frames"] = c.frames;
  j["fps"] = c.frames >= 2 ? Json(c.fps) : Json(nullptr);
  j["mode"] = c.frames >= 2 ? "video" : "image";
  j["width"] = c.width;
  j["height"] = c.height;
  Json bands = Json::array();
  for (int b = 0; b < r.bands; ++b) {
    double q[2] = {0, 0};
    for (const auto& f : r.q)
      for (int ch = 0; ch < 2; ++ch) q[ch] += f[size_t(b)][size_t(ch)];
    bands.push_back({{"rho_cpd", r.band_freq[size_t(b)]},
                     {"q_sustained", q[0] / r.frames},
                     {"q_transient", r.channels == 2 ? Json(q[1] / r.frames) : Json(nullptr)}});
  }
  j["bands"] = bands;
  return j;
}

std::string fvvdp_comparison_text(const FvvdpComparison& c) {
  const FvvdpResult& r = c.result;
  std::ostringstream o;
  char buf[256];
  o << r.display_line << "\n";
  if (c.frames >= 2)
    std::snprintf(buf, sizeof buf, "input      %d frames of %dx%d at %g fps (video)\n", c.frames,
                  c.width, c.height, c.fps);
  else
    std::snprintf(buf, sizeof buf, "input      %dx%d (image)\n", c.width, c.height);
  o << buf;
  if (c.foveated) {
    std::snprintf(buf, sizeof buf, "gaze       %g,%g px\n", c.gaze_x, c.gaze_y);
    o << buf;
  }
  for (int b = 0; b < r.bands; ++b) {
    double q[2] = {0, 0};
    for (const auto& f : r.q)
      for (int ch = 0; ch < 2; ++ch) q[ch] += f[size_t(b)][size_t(ch)];
    if (r.channels == 2)
      std::snprintf(buf, sizeof buf, "band %-2d    %9.4f cpd  Q sustained %.6g  transient %.6g\n",
                    b, r.band_freq[size_t(b)], q[0] / r.frames, q[1] / r.frames);
    else
      std::snprintf(buf, sizeof buf, "band %-2d    %9.4f cpd  Q %.6g\n", b, r.band_freq[size_t(b)],
                    q[0] / r.frames);
    o << buf;
  }
  std::snprintf(buf, sizeof buf, "fvvdp_jod  %.6f\n", r.jod);
  o << buf;
  return o.str();
}

}  // namespace fovsim
