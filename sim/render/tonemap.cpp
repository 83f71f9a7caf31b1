// ToneMap::apply over an image (tonemap.h holds the curve).
#include "sim/render/tonemap.h"

#include <tbb/parallel_for.h>

namespace fovsim {

namespace {

template <ToneCurve C>
void encode_range(const float* in, float* out, size_t n, float ex) {
  for (size_t i = 0; i < n; ++i) out[i] = display_encode<C>(in[i] * ex);
}

}  // namespace

void ToneMap::apply(const Image& linear, Image& display) const {
  if (display.width != linear.width || display.height != linear.height ||
      display.channels != linear.channels)
    display.resize(linear.width, linear.height, linear.channels);
  const float ex = float(exposure);
  const Curve cv = curve;
  const float* in = linear.data.data();
  float* out = display.data.data();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, linear.data.size(), 1 << 14),
                    [&](const tbb::blocked_range<size_t>& r) {
                      const size_t b = r.begin(), n = r.end() - r.begin();
                      switch (cv) {
                        case Curve::Reinhard:
                          encode_range<ToneCurve::Reinhard>(in + b, out + b, n, ex);
                          break;
                        case Curve::Aces:
                          encode_range<ToneCurve::Aces>(in + b, out + b, n, ex);
                          break;
                        default:
                          encode_range<ToneCurve::Clamp>(in + b, out + b, n, ex);
                          break;
                      }
                    });
}

}  // namespace fovsim
